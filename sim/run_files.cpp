#include "sim/run_files.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>

namespace sim {
namespace {

void put(std::FILE* f, double v, const char* format) {
  if (!std::isnan(v)) std::fprintf(f, format, v);
}

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

File open_for_writing(const std::string& path) {
  File file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) throw std::runtime_error("cannot write " + path);
  return file;
}

}  // namespace

void write_trace_csv(const std::string& path, const std::vector<TraceSample>& trace) {
  const File file = open_for_writing(path);
  std::FILE* f = file.get();
  std::fputs("time_s,true_c,sensor_c,reported_c,target_c,heater_duty,fan_duty\n", f);
  for (const TraceSample& s : trace) {
    std::fprintf(f, "%.3f,%.3f,", s.t_s, s.true_c);
    put(f, s.sensor_c, "%.3f");
    std::fputc(',', f);
    put(f, s.reported_c, "%.2f");
    std::fprintf(f, ",%.2f,%.4f,%.4f\n", s.target_c, s.heater_duty, s.fan_duty);
  }
}

void write_transcript(const std::string& path, const std::vector<ReplyLine>& transcript) {
  const File file = open_for_writing(path);
  for (const ReplyLine& line : transcript)
    std::fprintf(file.get(), "%10.3f %s\n", line.t_s, line.text.c_str());
}

bool write_lines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream out(path);
  for (const std::string& line : lines) out << line << '\n';
  out.flush();
  return static_cast<bool>(out);
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // a file edited on Windows
    if (!line.empty()) lines.push_back(line);
  }
  if (lines.empty()) throw std::runtime_error(path + " holds no settings");
  return lines;
}

}  // namespace sim

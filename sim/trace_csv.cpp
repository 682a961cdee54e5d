#include "sim/trace_csv.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace sim {
namespace {

void put(std::FILE* f, double v, const char* format) {
  if (!std::isnan(v)) std::fprintf(f, format, v);
}

}  // namespace

void write_trace_csv(const std::string& path, const std::vector<TraceSample>& trace) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) throw std::runtime_error("cannot write " + path);
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

}  // namespace sim

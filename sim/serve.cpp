#include "sim/serve.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "sim/bound.h"
#include "sim/cli_args.h"
#include "sim/fault_injection.h"
#include "sim/gcode_format.h"
#include "sim/hotend_rig.h"
#include "sim/host_session.h"
#include "sim/pty_port.h"
#include "sim/report.h"
#include "sim/run_files.h"

namespace sim {
namespace {

constexpr double kBootTimeoutS = 5.0;
// Wall-clock time per simulation slice: output is written and the pty polled once per slice.
constexpr double kSliceWallS = 0.001;
constexpr double kMaxSliceS = 0.05;  // simulated: the host's latency stays below a USB frame's

// The command of a host line without its "N<n> " and "*<checksum>" ("N3 M104 S210*77" → "M104 S210");
// "" when the checksum is wrong (the firmware asks for a resend and ignores the line).
std::string command_of(std::string line) {
  const std::size_t star = line.find('*');
  if (star != std::string::npos) {
    int sum = 0;
    for (std::size_t i = 0; i < star; ++i) sum ^= static_cast<uint8_t>(line[i]);
    if (std::atoi(line.c_str() + star + 1) != sum) return std::string();
    line.erase(star);
  }
  line = trim(line);
  if (!line.empty() && (line[0] == 'N' || line[0] == 'n')) {
    const std::size_t space = line.find(' ');
    line = space == std::string::npos ? std::string() : trim(line.substr(space + 1));
  }
  return line;
}

// S of "M104 S210" (and M109, M303); nullopt for other commands.
std::optional<double> heating_s_word(const std::string& command, bool* is_set_point) {
  const std::string word = command.substr(0, command.find(' '));
  *is_set_point = word == "M104" || word == "M109";
  if (!*is_set_point && word != "M303") return std::nullopt;
  for (const std::string& w : split(command, ' '))
    if (w.size() > 1 && (w[0] == 'S' || w[0] == 's')) return std::atof(w.c_str() + 1);
  return std::nullopt;
}

// The firmware's transmission errors (the host resends) are not faults.
bool is_fault_error(const std::string& line) {
  if (line.rfind("Error:", 0) != 0) return false;
  for (const char* transmission : {"line number", "Line Number", "checksum", "format error"})
    if (line.find(transmission) != std::string::npos) return false;
  return true;
}

class Server {
 public:
  Server(const ServeConfig& config, std::ostream& out);
  ServeResult run(const volatile std::sig_atomic_t& stop);

 private:
  int next_line_byte();
  void on_host_line(const std::string& line);
  void on_step(double now_s);
  void on_board_line(const ReplyLine& line);
  void finish(double wall_s);

  ServeConfig config_;
  PtyPort port_;
  HotendRig rig_;
  HostSession listener_;  // only listens: collects the board's lines and T: reports
  ServeResult result_;
  std::string to_host_;      // the board's bytes of the current slice
  std::string host_line_;    // the host's current line, as delivered to the UART
  std::string injected_;     // a fault's G-code, sent between two host lines
  std::optional<double> heating_start_s_;
  std::optional<double> first_fault_s_;
  std::vector<bool> fault_done_;
  std::optional<double> fault_error_s_;  // first Error: line of a fault, since power-on
};

Server::Server(const ServeConfig& config, std::ostream& out)
    : config_(config),
      port_(config.link_path),
      rig_(config.board, config.plant, config.elf_path, config.noise_lsb, config.seed),
      listener_(rig_.board()),
      fault_done_(config.faults.size(), false) {
  result_.device = port_.device();
  AvrBoard& board = rig_.board();
  board.on_uart_byte([this](uint8_t byte) { to_host_.push_back(static_cast<char>(byte)); });
  board.feed_uart_line([this] { return next_line_byte(); });
  listener_.on_line([this](const ReplyLine& line) { on_board_line(line); });
  rig_.on_step([this](double now_s, double) { on_step(now_s); });

  out << "hotend-sim serve: " << config.board.name << " (" << config.board.mcu << ") running " << config.elf_path
      << "\n  on the simulated hotend " << config.plant.name << ", " << format_decimal(config.speed)
      << "× real time\nserial port  " << port_.device() << "\n";
  if (!port_.link().empty()) out << "link         " << port_.link() << " -> " << port_.device() << "\n";
  const std::string& dev = port_.link().empty() ? port_.device() : port_.link();
  out << "connect at 115200 baud:\n"
      << "  pronsole     pronsole, then: connect " << dev << " 115200\n"
      << "  Pronterface  port " << dev << ", 115200, Connect\n"
      << "  OctoPrint    Settings > Serial Connection: add " << dev
      << " to the additional serial ports, 115200\n"
      << "Ctrl-C (SIGINT) or SIGTERM ends the session and prints its report.\n";
  out.flush();
}

// The host→board wire asks for its next byte: a fault's G-code between two host lines, else
// one byte from the pty (the rest waits in the kernel's buffer).
int Server::next_line_byte() {
  if (!injected_.empty() && host_line_.empty()) {
    const int byte = static_cast<uint8_t>(injected_.front());
    injected_.erase(0, 1);
    return byte;
  }
  const int byte = port_.read_byte();
  if (byte < 0) return byte;
  if (byte == '\n' || byte == '\r') {
    if (!host_line_.empty()) on_host_line(host_line_);
    host_line_.clear();
  } else {
    host_line_.push_back(static_cast<char>(byte));
  }
  return byte;
}

void Server::on_host_line(const std::string& line) {
  ++result_.host_lines;
  bool is_set_point = false;
  const std::optional<double> s = heating_s_word(command_of(line), &is_set_point);
  if (!s) return;
  const double now = rig_.board().time_s();
  if (*s > 0.0 && !heating_start_s_) heating_start_s_ = now;
  const double current = result_.set_points.empty() ? 0.0 : result_.set_points.back().target_c;
  if (is_set_point && *s != current) {
    result_.set_points.push_back(SetPoint{now, *s});
    rig_.set_target(*s);
  }
}

void Server::on_step(double now_s) {
  if (!heating_start_s_) return;
  for (std::size_t i = 0; i < config_.faults.size(); ++i) {
    if (fault_done_[i] || now_s < *heating_start_s_ + config_.faults[i].second) continue;
    fault_done_[i] = true;
    result_.faults_injected.emplace_back(config_.faults[i].first, now_s);
    if (!first_fault_s_) first_fault_s_ = now_s;
    inject_fault(config_.faults[i].first, rig_, [this](const std::string& line) { injected_ += line + "\n"; });
  }
}

void Server::on_board_line(const ReplyLine& line) {
  RunResult& r = result_.run;
  if (line.text == "start") r.booted = true;
  if (line.text.rfind("Error:", 0) == 0) r.error_lines.push_back(line.text);
  if (is_fault_error(line.text) && !fault_error_s_) fault_error_s_ = line.t_s;
  if (auto report = parse_temp_report(line.text)) {
    rig_.set_reported(report->temp_c);
    // The board's own target corrects the host-line parse (a line it refused, M112, a tune's end).
    const double current = result_.set_points.empty() ? 0.0 : result_.set_points.back().target_c;
    if (line.text.find('/') != std::string::npos && report->target_c != current) {
      result_.set_points.push_back(SetPoint{line.t_s, report->target_c});
      rig_.set_target(report->target_c);
    }
    if (first_fault_s_ || fault_error_s_) return;  // the metrics stop at a fault
    ++r.report_count;
    if (report->power < 0 || report->power > 255) ++r.report_power_bad;
    r.report_error_max_c = std::max(r.report_error_max_c, rig_.report_error_c(*report));
  }
}

ServeResult Server::run(const volatile std::sig_atomic_t& stop) {
  AvrBoard& board = rig_.board();
  const double slice_s = std::min(kMaxSliceS, config_.speed * kSliceWallS);
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_s = [&wall_start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  RunResult& r = result_.run;
  while (!stop) {
    port_.refresh();
    r.cpu = board.run_until(board.cycles_from_s(board.time_s() + slice_s));
    port_.write(to_host_);
    to_host_.clear();
    if (r.cpu != CpuState::kRunning) {
      r.problems.push_back(r.cpu == CpuState::kCrashed ? "the CPU crashed" : "the CPU stopped");
      break;
    }
    if (!r.booted && board.time_s() > kBootTimeoutS) {
      r.problems.push_back("no `start` line within 5 s of power-on");
      break;
    }
    const double ahead_s = board.time_s() / config_.speed - wall_s();
    if (ahead_s > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead_s));
  }
  finish(wall_s());
  return std::move(result_);
}

void Server::finish(double wall_s) {
  RunResult& r = result_.run;
  AvrBoard& board = rig_.board();
  r.wall_s = wall_s;
  record_board_figures(board, r);
  r.transcript = listener_.transcript();
  r.trace = rig_.trace();
  r.config.board = config_.board;
  r.config.plant = config_.plant;
  r.config.elf_path = config_.elf_path;
  r.config.noise_lsb = config_.noise_lsb;
  r.config.seed = config_.seed;
  r.config.csv_path = config_.csv_path;
  result_.bytes_from_host = port_.bytes_from_host();
  result_.bytes_to_host = port_.bytes_to_host();
  result_.bytes_lost_to_host = port_.bytes_lost();
  result_.uart_overruns = board.uart_overruns();
  if (!config_.csv_path.empty()) write_trace_csv(config_.csv_path, r.trace);

  // Control quality of the last nonzero set-point, until it changed or a fault stopped it.
  const auto& sp = result_.set_points;
  auto last = std::find_if(sp.rbegin(), sp.rend(), [](const SetPoint& p) { return p.target_c > 0.0; });
  if (last == sp.rend()) return;
  double end_s = r.end_s;
  if (last != sp.rbegin()) end_s = std::prev(last)->t_s;
  for (std::optional<double> stop_s : {first_fault_s_, fault_error_s_})
    if (stop_s && *stop_s > last->t_s) end_s = std::min(end_s, *stop_s);
  std::vector<TraceSample> segment;
  for (const TraceSample& s : r.trace)
    if (s.t_s <= end_s) segment.push_back(s);
  r.heating_start_s = last->t_s;
  r.config.target_c = last->target_c;
  r.config.seconds = end_s - last->t_s;
  r.metrics = compute_metrics(segment, last->t_s, last->target_c);
  r.bound = physical_bound(config_.plant, last->target_c);
}

}  // namespace

ServeResult serve(const ServeConfig& config, std::ostream& out, const volatile std::sig_atomic_t& stop) {
  return Server(config, out).run(stop);
}

void print_serve_report(std::ostream& out, const ServeResult& s) {
  out << "session            " << s.device << ": " << s.host_lines << " host lines, " << s.bytes_from_host
      << " B in, " << s.bytes_to_host << " B out (" << s.bytes_lost_to_host << " B lost: no host or its buffer full), "
      << s.uart_overruns << " UART overruns\n"
      << "set-points         ";
  if (s.set_points.empty()) out << "none";
  for (const SetPoint& p : s.set_points)
    out << format_fixed(p.target_c, 0) << " °C at " << format_fixed(p.t_s, 1) << " s  ";
  out << "\n";
  for (const auto& f : s.faults_injected)
    out << "fault injected     " << fault_name(f.first) << " at " << format_fixed(f.second, 1)
        << " s after power-on\n";
  if (!s.run.heating_start_s) out << "(no nonzero set-point: no control-quality figures)\n";
  print_report(out, s.run);
}

}  // namespace sim

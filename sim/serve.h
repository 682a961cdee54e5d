// `hotend-sim serve`: the simulated printer (sim/hotend_rig.h) behind a pseudo-terminal, for real
// host programs (pronsole, Pronterface, OctoPrint) — a virtual printer. Simulated time is paced
// against the wall clock (`speed` × real time); host→board bytes travel at the line rate the
// firmware programmed, board→host bytes are written as the UART sends them.
#pragma once

#include <csignal>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "sim/board_spec.h"
#include "sim/fault_outcome.h"
#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

struct ServeConfig {
  BoardSpec board;
  PlantSpec plant;
  std::string elf_path;
  std::string link_path;  // symlink to the pty ("" = none)
  double speed = 1.0;     // simulated seconds per wall-clock second
  // (kind, seconds after the heating start: the host's first M104/M109/M303 with S > 0)
  std::vector<std::pair<FaultKind, double>> faults;
  std::string csv_path;
  double noise_lsb = 0.5;
  uint64_t seed = 1;
};

// A change of the host's set-point (M104/M109 S…), simulated seconds since power-on.
struct SetPoint {
  double t_s;
  double target_c;
};

struct ServeResult {
  // The usual run record: `heating_start_s`, `config.target_c` and the metrics describe the last
  // nonzero set-point, from when the host set it until the next change, a fault's Error: line,
  // or the end.
  RunResult run;
  std::string device;
  uint64_t host_lines = 0;  // lines the host sent
  uint64_t bytes_from_host = 0, bytes_to_host = 0, bytes_lost_to_host = 0;
  uint64_t uart_overruns = 0;
  std::vector<SetPoint> set_points;
  std::vector<std::pair<FaultKind, double>> faults_injected;  // (kind, since power-on)
};

// Opens the pty, prints where and how to connect to `out`, and runs until `stop` is set
// (SIGINT/SIGTERM) or the CPU stops. Throws std::runtime_error if it cannot start.
ServeResult serve(const ServeConfig& config, std::ostream& out, const volatile std::sig_atomic_t& stop);

void print_serve_report(std::ostream& out, const ServeResult& result);

}  // namespace sim

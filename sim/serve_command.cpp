#include "sim/serve_command.h"

#include <csignal>
#include <iostream>
#include <stdexcept>

#include "sim/cli_args.h"
#include "sim/run_setup.h"
#include "sim/serve.h"

namespace sim {
namespace {

volatile std::sig_atomic_t g_stop = 0;

void request_stop(int) { g_stop = 1; }

}  // namespace

int serve_command(const std::vector<std::string>& args) {
  const Options o = parse_options(args, {});
  reject_unknown(o, {"board", "plant", "link", "speed", "fault", "csv", "elf", "noise-lsb", "seed"});
  ServeConfig c;
  c.board = board_named(o.get("board", "ramps14"));
  c.plant = plant_named(o.get("plant", "hotend40w"));
  c.elf_path = o.has("elf") ? o.get("elf") : default_elf_path(HOTEND_SIM_FIRMWARE_DIR, c.board);
  c.link_path = o.get("link");
  c.speed = parse_number(o.get("speed", "1"), "--speed");
  if (!(c.speed > 0.0)) throw std::invalid_argument("--speed must be above 0");
  c.csv_path = o.get("csv");
  c.noise_lsb = parse_number(o.get("noise-lsb", "0.5"), "--noise-lsb");
  c.seed = static_cast<uint64_t>(parse_number(o.get("seed", "1"), "--seed"));
  for (const std::string& text : o.all("fault")) {  // the same kinds and syntax as `run --fault`
    RunConfig parsed;
    parse_fault(text, parsed);
    if (parsed.fault_in_tune)
      throw std::invalid_argument("--fault " + text + ": serve counts from the host's first heating command (KIND@T)");
    c.faults.emplace_back(parsed.fault, parsed.fault_at_s);
  }

  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  const ServeResult result = serve(c, std::cout, g_stop);
  std::cout << "\n";
  print_serve_report(std::cout, result);
  return 0;
}

}  // namespace sim

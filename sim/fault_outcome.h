// What a fault run must show (issue 2: thermistor open/short → heater off within 1 s and the
// error printed; a hang → watchdog reset, `start` again, heater off), judged from what the
// harness recorded. Times are relative to the fault.
#pragma once

#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "sim/host_session.h"

namespace sim {

// kM108 / kM112: the host stops the heating (break-and-continue, emergency stop) at that time.
// kM112Wait .. kOverrunNumbered: serial-layer scenarios (sim/serial_scenario.h). The hardware
// faults the protection (issue 8) must catch, applied by the simulator from the fault on:
// kDetached (the thermistor leaves the block and cools towards ambient in air, the block keeps
// being heated), kHeaterDead (power 0), kStuckOn (100 % whatever the pin says), kQuarterPower
// (×0.25: a 24 V cartridge on 12 V), kFanStuck (fan 100 % whatever the pin says).
enum class FaultKind { kNone, kOpen, kShort, kHang, kM108, kM112, kM112Wait, kM112Burst, kOverrun, kOverrunNumbered,
                       kDetached, kHeaterDead, kStuckOn, kQuarterPower, kFanStuck };

// What the fault is, in words, for reports ("thermistor open").
const char* fault_name(FaultKind kind);

// A fault the firmware can only see through its model or watch (not a reading out of range).
constexpr bool is_plant_fault(FaultKind kind) {
  return kind == FaultKind::kDetached || kind == FaultKind::kHeaterDead || kind == FaultKind::kStuckOn ||
         kind == FaultKind::kQuarterPower || kind == FaultKind::kFanStuck;
}

struct FaultOutcome {
  std::optional<double> heater_last_on_s;  // last moment the heater pin was on (nullopt: on at the end)
  bool heater_on_at_end = false;
  std::string expected_error;          // "MINTEMP"/"MAXTEMP", "" for a hang
  std::optional<double> error_line_s;  // when the expected Error: line came
  std::optional<double> reset_s;       // first CPU reset after the fault
  bool restarted = false;              // `start` printed after that reset
  bool heater_on_after_reset = false;
  std::vector<std::string> serial_problems;  // overrun scenarios: check_overrun_replies()
  // Plant faults: the first Error: line of any kind after the fault, and what the hotend did.
  std::optional<double> first_error_s;
  std::string first_error;
  double block_peak_c = 0.0;       // highest block temperature from the fault to the end
  double sensor_min_before_error_c = 0.0;  // lowest true (sensor-node) temperature until the Error (or the end)
};

// Raw observations of one fault run (absolute simulated times, seconds since power-on).
struct FaultRecord {
  FaultKind kind = FaultKind::kNone;
  double fault_s = 0.0;
  bool heater_on_at_end = false;
  double heater_last_change_s = 0.0;  // the pin meter's last edge
  std::optional<double> reset_s;      // first reset after the fault
  bool heater_turned_on_after_reset = false;
  double block_peak_c = 0.0;
  std::vector<std::pair<double, double>> true_c;  // (t, true sensor-node °C) from the fault on, per trace sample
};

FaultOutcome evaluate_fault(const FaultRecord& record, const std::vector<ReplyLine>& lines);

}  // namespace sim

#include "sim/fault_outcome.h"

#include <algorithm>

namespace sim {
namespace {

const char* expected_error(FaultKind kind) {
  switch (kind) {
    case FaultKind::kOpen:
      return "MINTEMP";  // an open thermistor reads as very cold
    case FaultKind::kShort:
      return "MAXTEMP";  // a shorted one as very hot
    case FaultKind::kM112:
    case FaultKind::kM112Wait:
    case FaultKind::kM112Burst:
      return "Emergency stop";
    case FaultKind::kOverrun:
    case FaultKind::kOverrunNumbered:
      return "serial input lost";
    // Marlin's two wordings ("Heating failed, system stopped!", "Thermal Runaway, system
    // stopped!") share this; MAXTEMP does not count: the model check should come first.
    case FaultKind::kDetached:
    case FaultKind::kHeaterDead:
    case FaultKind::kStuckOn:
    case FaultKind::kQuarterPower:
      return "system stopped!";
    default:
      return "";
  }
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

FaultOutcome evaluate_fault(const FaultRecord& r, const std::vector<ReplyLine>& lines) {
  FaultOutcome f;
  f.heater_on_at_end = r.heater_on_at_end;
  // Off at the end: its last edge was the moment it went off.
  if (!r.heater_on_at_end) f.heater_last_on_s = std::max(0.0, r.heater_last_change_s - r.fault_s);
  f.expected_error = expected_error(r.kind);
  if (r.reset_s) {
    f.reset_s = *r.reset_s - r.fault_s;
    f.heater_on_after_reset = r.heater_on_at_end || r.heater_turned_on_after_reset;
  }
  for (const ReplyLine& line : lines) {
    if (!f.error_line_s && !f.expected_error.empty() && line.t_s >= r.fault_s &&
        starts_with(line.text, "Error:") && line.text.find(f.expected_error) != std::string::npos)
      f.error_line_s = line.t_s - r.fault_s;
    if (r.reset_s && line.t_s >= *r.reset_s && line.text == "start") f.restarted = true;
    if (!f.first_error_s && line.t_s >= r.fault_s && starts_with(line.text, "Error:")) {
      f.first_error_s = line.t_s - r.fault_s;
      f.first_error = line.text;
    }
  }
  f.block_peak_c = r.block_peak_c;
  f.sensor_min_before_error_c = r.true_c.empty() ? 0.0 : r.true_c.front().second;
  for (const auto& [t, c] : r.true_c)
    if (!f.error_line_s || t <= r.fault_s + *f.error_line_s) f.sensor_min_before_error_c = std::min(f.sensor_min_before_error_c, c);
  return f;
}

const char* fault_name(FaultKind kind) {
  switch (kind) {
    case FaultKind::kOpen:
      return "thermistor open";
    case FaultKind::kShort:
      return "thermistor shorted";
    case FaultKind::kHang:
      return "firmware hang (D0)";
    case FaultKind::kM108:
      return "host sends M108";
    case FaultKind::kM112:
      return "host sends M112";
    case FaultKind::kM112Wait:
      return "M112 behind a waiting M109 and a held line";
    case FaultKind::kM112Burst:
      return "M112 after a burst that fills the RX ring";
    case FaultKind::kOverrun:
      return "RX overrun, unnumbered lines";
    case FaultKind::kOverrunNumbered:
      return "RX overrun, numbered lines";
    case FaultKind::kDetached:
      return "thermistor detached";
    case FaultKind::kHeaterDead:
      return "heater dead";
    case FaultKind::kStuckOn:
      return "heater stuck on";
    case FaultKind::kQuarterPower:
      return "heater at a quarter power";
    case FaultKind::kFanStuck:
      return "part fan stuck at 100 %";
    case FaultKind::kNone:
      break;
  }
  return "none";
}

}  // namespace sim

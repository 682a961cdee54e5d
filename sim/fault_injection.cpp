#include "sim/fault_injection.h"

namespace sim {

void inject_fault(FaultKind kind, ThermistorAdc& sensor, const std::function<void(const std::string&)>& send_line) {
  if (kind == FaultKind::kOpen) sensor.set_fault(SensorFault::kOpen);
  if (kind == FaultKind::kShort) sensor.set_fault(SensorFault::kShorted);
  if (kind == FaultKind::kHang) send_line("D0");
  if (kind == FaultKind::kM108) send_line("M108");
  if (kind == FaultKind::kM112) send_line("M112");
}

}  // namespace sim

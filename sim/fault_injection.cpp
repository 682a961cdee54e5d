#include "sim/fault_injection.h"

namespace sim {

void inject_fault(FaultKind kind, HotendRig& rig, const std::function<void(const std::string&)>& send_line) {
  rig.mark_fault(kind);  // plant faults act from here; the block peak is watched from here
  if (kind == FaultKind::kOpen) rig.sensor().set_fault(SensorFault::kOpen);
  if (kind == FaultKind::kShort) rig.sensor().set_fault(SensorFault::kShorted);
  if (kind == FaultKind::kHang) send_line("D0");
  if (kind == FaultKind::kM108) send_line("M108");
  if (kind == FaultKind::kM112) send_line("M112");
}

}  // namespace sim

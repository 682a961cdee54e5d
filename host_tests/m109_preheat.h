// `M109 S<to_c>` before an M303, on a host plant: heated from cold by the firmware's default PID
// (M301 P34 I1 D100, 128 ms) until the reading is within 1 °C of to_c (M109's window), so that the
// tune starts with the heat still in flight behind the plant's lags.
#pragma once

#include <cmath>
#include <stdint.h>

#include "control/pid.h"
#include "design/plant_sim.h"

namespace host_rig {

inline void heat_as_m109(design::PlantSim& sim, double to_c) {
  control::Pid pid;
  pid.configure(control::PidGains{34L << 16, 1L << 16, 100L << 16}, 128);
  const int32_t to_q8 = static_cast<int32_t>(std::lround(to_c * 256));
  for (int i = 0; i < 40000; ++i) {  // ≤ 85 min
    const int32_t y = static_cast<int32_t>(std::lround(sim.measured_c() * 256));
    if (y >= to_q8 - 256) break;
    sim.run(pid.step(to_q8, y) / 65535.0, 0.128);
  }
}

}  // namespace host_rig

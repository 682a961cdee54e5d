// How a host plant gets to an M303's hot start: right after `M109`, or held there a long while.
#pragma once

#include <cmath>
#include <stdint.h>

#include "control/pid.h"
#include "design/lti_model.h"
#include "design/plant_sim.h"

namespace host_rig {

// `M109 S<to_c>` before an M303: heated from cold by the firmware's default PID (M301 P34 I1 D100,
// 128 ms) until the reading is within 1 °C of to_c (M109's window), so that the tune starts with
// the heat still in flight behind the plant's lags.
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

// Held at start_c a long while (40,000 periods of 128 ms, as a printer idling there) by the duty
// that keeps the plant there; returns that duty.
inline double hold_at(design::PlantSim& sim, const design::LtiModel& m, double start_c) {
  const double duty = (start_c - m.ambient_c) / design::dc_gain(m);
  for (int i = 0; i < 40000; ++i) sim.run(duty, 0.128);
  return duty;
}

// The static gain such a hold gives the tune, as the firmware's SteadyHold measures it (reading
// − 25 °C over duty; the rig holds it exactly), °C × 256 per unit duty.
inline int32_t held_gain_q8(double start_c, double duty) {
  return static_cast<int32_t>(std::lround((start_c - 25.0) / duty * 256));
}

}  // namespace host_rig

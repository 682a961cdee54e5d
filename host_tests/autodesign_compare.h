// What the on-board state-feedback design tests (test_state_feedback_autodesign.cpp, one state;
// test_state_feedback_two_lags.cpp, two lags) compare with the host's double design: the
// constants field by field, and the closed loop both sets give on the same plant.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "control/state_feedback.h"
#include "control/state_feedback_constants.h"
#include "design/plant_sim.h"

namespace autodesign_compare {

// One constant of the board's set (b) and the host's (h): mantissas and shifts.
struct Field {
  std::string name;
  int16_t mb, mh;
  uint8_t sb, sh;
};

// Every constant the law of b.n states and b.delay predictor taps uses.
inline std::vector<Field> fields(const control::StateFeedbackConstants& b, const control::StateFeedbackConstants& h) {
  std::vector<Field> f;
  for (int i = 0; i < b.n; ++i) {
    const std::string n = "[" + std::to_string(i) + "]";
    f.push_back({"phi_diag" + n, b.phi_diag[i], h.phi_diag[i], b.phi_shift[i], h.phi_shift[i]});
    if (b.n > 1) f.push_back({"phi_off" + n, b.phi_off[i], h.phi_off[i], b.phi_shift[i], h.phi_shift[i]});
    f.push_back({"gamma_a" + n, b.gamma_a[i], h.gamma_a[i], b.phi_shift[i], h.phi_shift[i]});
    f.push_back({"gamma_b" + n, b.gamma_b[i], h.gamma_b[i], b.phi_shift[i], h.phi_shift[i]});
    f.push_back({"fb_gain" + n, b.fb_gain[i], h.fb_gain[i], b.ctrl_shift, h.ctrl_shift});
    f.push_back({"ss_share" + n, b.ss_share[i], h.ss_share[i], b.ss_share_shift, h.ss_share_shift});
  }
  for (int i = 0; i <= b.n; ++i)  // the states and the disturbance
    f.push_back({"obs_gain[" + std::to_string(i) + "]", b.obs_gain[i], h.obs_gain[i], b.obs_shift[i], h.obs_shift[i]});
  f.push_back({"ff_gain", b.ff_gain, h.ff_gain, b.ctrl_shift, h.ctrl_shift});
  f.push_back({"bias_gain", b.bias_gain, h.bias_gain, b.ctrl_shift, h.ctrl_shift});
  f.push_back({"fan_gain", b.fan_gain, h.fan_gain, b.fan_shift, h.fan_shift});
  f.push_back({"inv_gain", b.inv_gain, h.inv_gain, b.inv_gain_shift, h.inv_gain_shift});
  for (int j = 0; j < b.delay; ++j)
    f.push_back({"fir[" + std::to_string(j) + "]", b.fir[j], h.fir[j], b.fir_shift, h.fir_shift});
  return f;
}

inline double value(int16_t m, uint8_t s) { return std::ldexp(static_cast<double>(m), -s); }

// Heat-up 25 → 210 °C, then the part fan to 100 % at fan_at_s: the true temperature every 128 ms.
// Sensor noise σ 0.05 °C, the same sequence for both constant sets (same seed, same calls).
inline std::vector<double> closed_loop(const design::LtiModel& plant, const control::StateFeedbackConstants& k,
                                       double fan_at_s, double end_s) {
  control::StateFeedback sf;
  EXPECT_TRUE(sf.configure(k));
  design::PlantSim sim(plant);
  sim.set_noise(0.05);
  std::vector<double> trace;
  for (double t = 0; t < end_s; t += 0.128) {
    const bool fan = t >= fan_at_s;
    sim.set_fan(fan ? 1.0 : 0.0);
    const control::StepInput in{210 * 256, static_cast<int32_t>(std::lround(sim.measured_c() * 256)),
                                static_cast<uint8_t>(fan ? 255 : 0)};
    sim.run(sf.step(in) / 65535.0, 0.128);
    trace.push_back(sim.true_c());
  }
  return trace;
}

}  // namespace autodesign_compare

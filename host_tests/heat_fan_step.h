// The HIL scenario the host rigs share (sim/CMakeLists.txt's HIL3 and HIL7, without simavr's ADC):
// a configured ControllerBank heats a double-precision plant (design/plant_sim.h) from ambient to
// the target, holds it, and meets a part-fan step 0 → 100 %; the firmware's ThermalWatch watches.
// Figures from the plant's true temperature, as sim/metrics.h defines them.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "design/lti_model.h"
#include "design/plant_sim.h"
#include "firmware/controller_bank.h"
#include "firmware/thermal_watch.h"

namespace heat_fan_step {

constexpr double kPeriodS = firmware::kControlPeriodMs / 1000.0;

struct Result {
  double overshoot_c = 0;                      // before the fan step
  double settling_s = 0;                       // the end of the last period outside ±1 °C before it
  double steady_mean_c = 0, steady_pp_c = 0;   // error over the quarter before the fan step
  double dip_c = 0;                            // largest |error| after it
  double recovery_s = -1;                      // back inside ±1 °C for good after it; −1: not at the end
  double end_error_c = 0;
  firmware::Fault fault = firmware::Fault::kNone;  // the first the watch latched
  double fault_s = -1;
};

// trace (optional): per period the true error (°C) and the duty (0..1), interleaved.
inline Result run(firmware::ControllerBank& bank, const design::LtiModel& model, double target_c, double fan_at_s,
                  double run_s, double noise_c, std::vector<double>* trace = nullptr) {
  Result f;
  firmware::ThermalWatch watch;
  design::PlantSim sim(model);
  sim.set_noise(noise_c);
  const int32_t target_q8 = static_cast<int32_t>(std::lround(target_c * 256));
  const int periods = static_cast<int>(run_s / kPeriodS);
  const int fan_k = static_cast<int>(fan_at_s / kPeriodS);
  const int steady_from = fan_k * 3 / 4;
  double lo = 1e9, hi = -1e9, sum = 0;
  int n = 0;
  uint8_t fan = 0;
  bank.prepare_feedforward(target_q8);
  for (int k = 0; k < periods; ++k) {
    if (k == fan_k) {
      fan = 255;
      sim.set_fan(1.0);  // the bank follows the fan from the step's input
    }
    const int32_t measured_q8 = static_cast<int32_t>(std::lround(sim.measured_c() * 256));
    const uint16_t duty_q16 = bank.step(control::StepInput{target_q8, measured_q8, fan});
    const firmware::Fault fault = watch.update(target_q8, measured_q8, duty_q16);
    if (fault != firmware::Fault::kNone && f.fault == firmware::Fault::kNone) {
      f.fault = fault;
      f.fault_s = k * kPeriodS;
    }
    sim.run(duty_q16 / 65535.0, kPeriodS);
    const double e = sim.true_c() - target_c;
    if (trace) {
      trace->push_back(e);
      trace->push_back(duty_q16 / 65535.0);
    }
    if (k < fan_k) {
      f.overshoot_c = std::max(f.overshoot_c, e);
      if (std::fabs(e) > 1.0) f.settling_s = (k + 1) * kPeriodS;
      if (k >= steady_from) {
        lo = std::min(lo, e);
        hi = std::max(hi, e);
        sum += e;
        ++n;
      }
    } else {
      f.dip_c = std::max(f.dip_c, std::fabs(e));
      if (std::fabs(e) > 1.0) f.recovery_s = (k + 1 - fan_k) * kPeriodS;
    }
  }
  f.end_error_c = sim.true_c() - target_c;
  if (f.recovery_s < 0) f.recovery_s = 0;
  if (std::fabs(f.end_error_c) > 1.0) f.recovery_s = -1;  // never back
  f.steady_pp_c = hi - lo;
  f.steady_mean_c = n ? sum / n : 0;
  return f;
}

}  // namespace heat_fan_step

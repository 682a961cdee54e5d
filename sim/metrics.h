// Closed-loop quality figures computed from the plant's TRUE temperature (not from what the
// firmware reports), averaged over each trace sample — one heater PWM period — so they measure
// the control loop, not the PWM ripple (reported separately). All times are relative to the
// heating start t0 (the firmware's `ok` to M104), all temperatures in °C.
//
// Definitions (band = ±1 °C around the target):
// - time to reach: first sample inside the band;
// - overshoot: max(T − target, 0) before the disturbance (or run end);
// - settling: time of the last sample outside the band, if the run ends inside it;
// - steady state: the last 25 % of the pre-disturbance part of the run — mean error (T − target)
//   and peak-to-peak of T, and the largest PWM ripple (max − min within one sample);
// - IAE: ∫|T − target| dt over the pre-disturbance part;
// - disturbance (e.g. a part-fan step at t_d): max |T − target| after t_d and the recovery time
//   from t_d to the last sample outside the band.
#pragma once

#include <optional>
#include <vector>

namespace sim {

struct TraceSample {
  double t_s = 0.0;            // simulated time since power-on
  double true_c = 0.0;         // plant output (sensor node), mean over the sample period
  double true_ripple_c = 0.0;  // its max − min within the period (the heater PWM's ripple)
  double sensor_c = 0.0;       // temperature equivalent of the mean injected ADC code over the period
  double reported_c = 0.0;     // last T: value the firmware printed (NaN before the first)
  double target_c = 0.0;       // last M104 target sent
  double heater_duty = 0.0;    // mean over the period, from the pin
  double fan_duty = 0.0;       // mean over the period, from the pin
};

struct DisturbanceMetrics {
  double at_s = 0.0;
  double max_deviation_c = 0.0;
  std::optional<double> recovery_s;
};

struct Metrics {
  std::optional<double> time_to_reach_s;
  double overshoot_c = 0.0;
  std::optional<double> settling_s;
  double steady_from_s = 0.0;  // the steady-state window, relative to t0
  double steady_to_s = 0.0;
  double steady_mean_error_c = 0.0;
  double steady_peak_to_peak_c = 0.0;
  double steady_ripple_c = 0.0;
  double iae_c_s = 0.0;
  std::optional<DisturbanceMetrics> disturbance;
};

constexpr double kBandC = 1.0;
constexpr double kSteadyFraction = 0.25;

// `disturbance_at_s`, relative to t0, splits the run in two when given.
Metrics compute_metrics(const std::vector<TraceSample>& trace, double t0_s, double target_c,
                        std::optional<double> disturbance_at_s = std::nullopt);

}  // namespace sim

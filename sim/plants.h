// The plant bank: hotend thermal models from the seed papers plus one physical model, all in
// continuous time (seconds), output = temperature rise above ambient (K), inputs = heater duty
// 0–1 and part-fan duty 0–1 (extra heat loss, design/lti_model.h). Plant steps one instance
// exactly (zero-order hold on the measured duty, dead time as a delay line).
//
// The dead time sits at the output (transport from the heated block to the thermistor): for the
// heater this is the same as an input delay, and it makes the fan's extra loss reach the sensor
// through the same delay as the heater's power — a fan step is then an input-equivalent
// disturbance that feedforward can cancel, not one that outruns every controller.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "design/expm.h"
#include "design/lti_model.h"

namespace sim {

struct PlantSpec {
  std::string name;
  std::string description;
  // The plant's dynamics and fan path (design/lti_model.h, the same model type the design tool
  // and the host tests use). Its dead time is simulated at the output (see Plant).
  design::LtiModel model;
  double ambient_c = 25.0;
  // What the HIL tests and the benchmark run on this plant by default: the seed000 models are
  // nearly integrating (slow poles of 10–20 min), so they get the seed's own 150 °C set point
  // and an hour: with PI gains their integral settles over ~40 min.
  double default_target_c = 210.0;
  double default_seconds = 600.0;
};

// All plants, in the order the benchmark prints them.
const std::vector<PlantSpec>& plant_bank();
const PlantSpec* find_plant(const std::string& name);

struct PlantInput {
  double heater_duty = 0.0;  // 0..1, average over the step
  double fan_duty = 0.0;     // 0..1, average over the step
};

class Plant {
 public:
  Plant(const PlantSpec& spec, double dt_s);

  // Advances the model by dt with the given average inputs.
  void step(const PlantInput& in);
  // The "true" temperature: the sensor node / model output, °C.
  double temperature_c() const { return spec_.ambient_c + rise_k_; }
  // The heater block's temperature: the block node of a physical (two-node) model, otherwise
  // the model's output before the transport delay to the sensor. What a fault heats (a detached
  // thermistor no longer sees it), °C.
  double block_temperature_c() const;
  double time_s() const { return double(steps_) * dt_s_; }
  double dt_s() const { return dt_s_; }
  const PlantSpec& spec() const { return spec_; }

 private:
  const design::ExpIntegral& zoh_for_fan_level(int level);

  static constexpr int kFanLevels = 256;      // airflow quantised to 1/256 for the cache
  static constexpr double kFanSpinUpS = 0.5;  // airflow lag behind the modulated fan pin

  PlantSpec spec_;
  double dt_s_;
  std::vector<double> x_, x_next_;  // state, and scratch for the update (no allocation per step)
  std::vector<double> delay_line_;  // C·x per step over the dead time, oldest at delay_index_
  std::size_t delay_index_ = 0;
  double rise_k_ = 0.0;       // the delayed output
  double undelayed_rise_k_ = 0.0;
  double airflow_step_gain_;  // first-order lag of the airflow per step
  double airflow_ = 0.0;      // filtered fan duty 0..1
  std::vector<std::unique_ptr<design::ExpIntegral>> zoh_by_fan_level_;
  long long steps_ = 0;
};

// Output rise (K) after each of `steps` steps of dt at 100 % heater, fan off, from ambient:
// the unit step response the physical bound and the FOPDT approximation are computed from.
std::vector<double> full_power_step_response_k(const PlantSpec& spec, double dt_s, std::size_t steps);

}  // namespace sim

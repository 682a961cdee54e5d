// The gains a run uses when none are given: the plant's first-order-plus-dead-time
// approximation (fitted to its simulated full-power step response, as an autotune would see
// it) through a model-based PID rule.
#pragma once

#include <string>

#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

struct FopdtApproximation {
  double gain_k = 0.0;  // K per unit duty
  double lag_s = 0.0;   // T
  double delay_s = 0.0; // τ
};

struct GainChoice {
  MarlinGains gains;
  FopdtApproximation model;
  std::string description;  // rule and model, for reports
};

FopdtApproximation fopdt_approximation(const PlantSpec& plant);
GainChoice default_gains(const PlantSpec& plant);

}  // namespace sim

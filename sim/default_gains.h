// The gains a run uses when none are given: the plant's first-order-plus-dead-time
// approximation (the two-point fit of its simulated full-power step response, as an autotune
// would see it) through a model-based PID rule from control/tuning.h.
#pragma once

#include <string>

#include "control/tuning.h"
#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

struct GainChoice {
  MarlinGains gains;
  tuning::Fopdt model;
  std::string description;  // rule and model, for reports
};

tuning::Fopdt fopdt_approximation(const PlantSpec& plant);
GainChoice default_gains(const PlantSpec& plant);

}  // namespace sim

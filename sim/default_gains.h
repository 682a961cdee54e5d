// PID gains from the plant model for runs that are not given --gains: the plant's
// first-order-plus-dead-time approximation (the two-point fit of its simulated full-power step
// response, as an autotune would see it) through a rule from design/tuning.h.
#pragma once

#include <string>
#include <vector>

#include "design/tuning.h"
#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

struct GainChoice {
  MarlinGains gains;
  tuning::Fopdt model;
  std::string description;  // rule and model, for reports
};

// Rule names: "simc" (the default: SIMC PI, τc = 2τ), "simc-tight" (τc = τ), "amigo",
// "cohen-coon", "zn-step" — all on the FOPDT fit — and "zn-relay": Marlin's M303 autotune, a
// relay experiment at the target and the classic Ziegler–Nichols ultimate-cycle rule.
const std::vector<std::string>& gain_rule_names();
constexpr const char* kDefaultGainRule = "simc";

tuning::Fopdt fopdt_approximation(const PlantSpec& plant);
// Throws std::invalid_argument for an unknown rule. `target_c` matters only to zn-relay.
GainChoice gains_by_rule(const PlantSpec& plant, const std::string& rule, double target_c);

}  // namespace sim

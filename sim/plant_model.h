// What the model-based controllers are told about each plant of the bank, computed from the
// plant's own model the way a user would obtain it: the M307 FOPDT model of the feedforward and
// the state-feedback constants (M311) from control/'s design code. The harness sends these as
// G-code, so the firmware runs exactly what a host could upload.
#pragma once

#include <string>
#include <vector>

#include "design/lti_model.h"
#include "control/state_feedback_constants.h"
#include "sim/plants.h"

namespace sim {

// M307 A C D F (docs/controllers.md): FOPDT rise at 100 % duty (°C), time constant (s), dead
// time (s), extra loss with the part fan at 100 % (% of the no-fan loss).
struct HotendModelSetting {
  double rise_k = 0.0;
  double time_constant_s = 0.0;
  double dead_time_s = 0.0;
  double fan_loss_pct = 0.0;
  std::string source;  // "exact FOPDT" or the two-point fit it came from
};

// Exact when the plant is a FOPDT; otherwise the two-point fit of its full-power step response
// (the fit the default PID gains use). The fan loss is exact for every plant:
// F = (K_fan-off / K_fan-full − 1) · 100.
HotendModelSetting hotend_model_for(const PlantSpec& plant);
std::string m307_command(const HotendModelSetting& model);

// The model the design tool is given for the plant: the bank's own design::LtiModel (matrices,
// dead time, fan path) with the plant's ambient.
design::LtiModel design_model_for(const PlantSpec& plant);

struct StateFeedbackSetting {
  control::StateFeedbackConstants constants;
  std::string description;  // law period, dead-time periods, closed-loop time constant
};
// design::design_state_feedback() with its default pole rule (docs/state_feedback.md) and
// quantize(); throws std::runtime_error if the design or the quantisation fails.
StateFeedbackSetting state_feedback_for(const PlantSpec& plant);

// The canonical M311 upload (control/state_feedback_gcode.h): 13 field lines and `M311 W1`.
std::vector<std::string> m311_commands(const control::StateFeedbackConstants& constants);

}  // namespace sim

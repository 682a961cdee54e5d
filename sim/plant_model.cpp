#include "sim/plant_model.h"

#include <cstdio>
#include <stdexcept>

#include "design/state_feedback_design.h"
#include "control/state_feedback_gcode.h"
#include "design/state_feedback_quantize.h"
#include "sim/default_gains.h"
#include "sim/gcode_format.h"

namespace sim {
namespace {

// A one-state model whose output is its state: K·e^(−τs)/(T·s + 1) exactly.
bool is_fopdt(const design::LtiModel& m) { return m.n == 1 && m.c(0, 0) == 1.0 && m.a(0, 0) < 0.0; }

double fan_loss_fraction(const design::LtiModel& m) {
  return design::dc_gain(m, 0.0) / design::dc_gain(m, 1.0) - 1.0;
}

}  // namespace

HotendModelSetting hotend_model_for(const PlantSpec& plant) {
  const design::LtiModel& m = plant.model;
  HotendModelSetting s;
  s.fan_loss_pct = 100.0 * fan_loss_fraction(m);
  if (is_fopdt(m)) {
    s.rise_k = design::dc_gain(m);
    s.time_constant_s = -1.0 / m.a(0, 0);
    s.dead_time_s = m.delay_s;
    s.source = "exact FOPDT";
    return s;
  }
  const tuning::Fopdt fit = fopdt_approximation(plant);
  s.rise_k = fit.k_c_per_duty;
  s.time_constant_s = fit.t_s;
  s.dead_time_s = fit.tau_s;
  s.source = "two-point FOPDT fit of the full-power step";
  return s;
}

std::string m307_command(const HotendModelSetting& model) {
  // Three places: the firmware keeps the model in Q8 (1/256).
  return "M307 A" + format_decimal(model.rise_k, 3) + " C" + format_decimal(model.time_constant_s, 3) +
         " D" + format_decimal(model.dead_time_s, 3) + " F" + format_decimal(model.fan_loss_pct, 3);
}

design::LtiModel design_model_for(const PlantSpec& plant) {
  if (plant.model.n > design::kMaxModelStates) throw std::runtime_error(plant.name + ": too many states to design for");
  // The bank's models are the design tool's type: only the ambient is the plant's own. The bank
  // simulates the dead time at the output, the design puts it at the input: the same transfer
  // function, and the fan's loss passes it either way (sim/plants.h).
  design::LtiModel d = plant.model;
  d.ambient_c = plant.ambient_c;
  return d;
}

StateFeedbackSetting state_feedback_for(const PlantSpec& plant) {
  const design::LtiModel model = design_model_for(plant);
  const design::Design d = design::design_state_feedback(model);
  if (d.error) throw std::runtime_error(plant.name + ": state-feedback design failed: " + d.error);
  StateFeedbackSetting s;
  if (const char* err = design::quantize(d, model.fan_loss_per_k, &s.constants))
    throw std::runtime_error(plant.name + ": state-feedback constants: " + err);
  char text[160];
  std::snprintf(text, sizeof text, "law every %d × 128 ms, dead time %d periods, closed-loop T %.1f s",
                d.decimation, d.zoh.delay, d.t_cl_s);
  s.description = text;
  return s;
}

std::vector<std::string> m311_commands(const control::StateFeedbackConstants& constants) {
  std::vector<std::string> lines;
  control::write_state_feedback_mcode(constants, [&lines](const char* line) { lines.emplace_back(line); });
  return lines;
}

}  // namespace sim

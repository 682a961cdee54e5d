#include "sim/controller_setup.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "sim/default_gains.h"
#include "sim/gcode_format.h"
#include "sim/plant_model.h"

namespace sim {
namespace {

constexpr double kMarlinFullScale = 255.0;

// M310 S values (docs/controllers.md).
constexpr int kPid = 0, kStateFeedback = 1, kFuzzyPid = 2, kMarlinPid = 3;

// Seed 002's fuzzy supervisor as published: quantisation 0.4 /°C (e) and 0.6 s/°C (ec), around
// the M301 gains with the firmware's default spread (docs/controllers.md, M312).
const char* const kFuzzyConfig = "M312 S50 E0.4 C0.6";

std::string select(int controller, bool feedforward) {
  return "M310 S" + std::to_string(controller) + " F" + (feedforward ? "1" : "0");
}

ControllerSetup pid_family(const std::string& name, const PlantSpec& plant, double target_c, const char* rule,
                           int controller, bool feedforward) {
  ControllerSetup s;
  s.name = name;
  const GainChoice g = gains_by_rule(plant, rule, target_c);
  s.gains = g.gains;
  s.gains_source = g.description;
  // The model goes with every controller that uses it (the tune sets it for all: M303 U1): the
  // feedforward of F1, the part-fan term and fuzzy-PID's model heat-up of F0 (docs/controllers.md).
  // The Marlin baseline ignores it.
  if (controller != kMarlinPid) s.gcode.push_back(m307_command(hotend_model_for(plant)));
  if (controller == kFuzzyPid) s.gcode.push_back(kFuzzyConfig);
  s.gcode.push_back(select(controller, feedforward));
  return s;
}

}  // namespace

const std::vector<std::string>& controller_names() {
  static const std::vector<std::string> names{"pid",     "pid+ff",    "fuzzy", "fuzzy+ff",
                                              "statefb", "marlin-zn", "paper"};
  return names;
}

std::optional<PublishedGains> published_gains(const PlantSpec& plant) {
  // Seed 003 (Cojuhari et al.): PID by the analytical maximum-stability-degree rule on model
  // (15), k = 2.847 — the paper's best on the real printer (1 % overshoot, 90 s settling at
  // ±5 %). Its printer ran RAMPS 1.4 firmware with a Marlin-style autotune, so the gains run
  // on the Marlin structure.
  if (plant.name == "seed003")
    return PublishedGains{"seed 003, analytical max. stability degree on model (15)", 14.23, 0.671, 81.58, 2.847,
                          kMarlinPid, ""};
  // Seed 004 (Gan Xinji et al.): Simulink PID Kp 4, KI 0.26, KD −19.6 on K = 0.233. A negative
  // Kd cannot be sent (M301 refuses it, and it would be anti-damping): D = 0.
  if (plant.name == "seed004")
    return PublishedGains{"seed 004, Kp 4, KI 0.26, KD -19.6 (sic)", 4.0, 0.26, 0.0, 0.233, kPid,
                          "published KD -19.6 sent as 0"};
  return std::nullopt;
}

MarlinGains marlin_gains_from_paper(const PublishedGains& p, double rise_k) {
  const double scale = p.plant_gain * kMarlinFullScale / rise_k;
  return MarlinGains{p.kp * scale, p.ki * scale, p.kd * scale};
}

bool controller_applies(const std::string& name, const PlantSpec& plant) {
  if (name == "paper") return published_gains(plant).has_value();
  return std::find(controller_names().begin(), controller_names().end(), name) != controller_names().end();
}

ControllerSetup controller_setup(const std::string& name, const PlantSpec& plant, double target_c) {
  if (!controller_applies(name, plant))
    throw std::invalid_argument("controller \"" + name + "\" does not apply to " + plant.name +
                                " (controllers: pid, pid+ff, fuzzy, fuzzy+ff, statefb, marlin-zn, paper)");
  if (name == "pid") return pid_family(name, plant, target_c, kDefaultGainRule, kPid, false);
  if (name == "pid+ff") return pid_family(name, plant, target_c, kFeedforwardGainRule, kPid, true);
  if (name == "fuzzy") return pid_family(name, plant, target_c, kDefaultGainRule, kFuzzyPid, false);
  if (name == "fuzzy+ff") return pid_family(name, plant, target_c, kFeedforwardGainRule, kFuzzyPid, true);
  if (name == "marlin-zn") return pid_family(name, plant, target_c, "zn-relay", kMarlinPid, false);
  ControllerSetup s;
  s.name = name;
  if (name == "statefb") {
    const StateFeedbackSetting sf = state_feedback_for(plant);
    s.gains_source = "state feedback: " + sf.description;
    s.gcode = m311_commands(sf.constants);
    s.gcode.push_back("M310 S1");
    return s;
  }
  // paper
  const PublishedGains p = *published_gains(plant);
  s.gains = marlin_gains_from_paper(p, design::dc_gain(plant.model));
  s.gains_source = p.source + ", loop gain matched (K " + format_decimal(p.plant_gain, 3) + " -> " +
                   format_decimal(design::dc_gain(plant.model), 1) + " °C per 100 %)" +
                   (p.note.empty() ? "" : "; " + p.note);
  s.gcode.push_back(select(p.controller, false));
  return s;
}

}  // namespace sim

// The controllers the benchmark and the HIL tests compare, each as the G-code a host would send
// to set it up on a given plant (M301 gains, M307 model, M311 state-feedback constants, M312
// fuzzy configuration, M310 choice; docs/controllers.md), computed from the plant's model:
//   pid        S0 F0   PID, gains by the default rule (SIMC PI, τc = 2τ, on the FOPDT fit), the
//                      M307 model (for the part-fan term)
//   pid+ff     S0 F1   PID + model feedforward (M307), gains by kFeedforwardGainRule
//   fuzzy      S2 F0   fuzzy-PID around the pid gains (seed 002's quantisation factors), the M307
//                      model (its heat-up and the part-fan term)
//   fuzzy+ff   S2 F1   fuzzy-PID around the pid+ff gains, with the feedforward
//   statefb    S1      state feedback + feedforward, constants designed from the plant's model
//   marlin-zn  S3 F0   baseline: Marlin's PID structure, classic Ziegler–Nichols relay gains
//   paper      S3/S0   baseline: the seed's own published gains (seed003, seed004 only)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/plants.h"
#include "sim/sim_run.h"

namespace sim {

struct ControllerSetup {
  std::string name;
  std::optional<MarlinGains> gains;  // sent as M301 first (nullopt: the controller uses none)
  std::string gains_source;
  std::vector<std::string> gcode;  // untimed set-up commands, in order, after M301
};

// Every controller, in the benchmark's order.
const std::vector<std::string>& controller_names();
// False where a controller has nothing to run (paper: only the seeds that published gains).
bool controller_applies(const std::string& name, const PlantSpec& plant);
// Throws std::invalid_argument for an unknown name or one that does not apply to the plant,
// std::runtime_error if the state-feedback design fails.
ControllerSetup controller_setup(const std::string& name, const PlantSpec& plant, double target_c);

// The PID rule of pid+ff and fuzzy+ff (a name gains_by_rule() knows); see controller_setup.cpp.
constexpr const char* kFeedforwardGainRule = "simc-tight";

// A seed's published PID gains and the plant gain they were designed for.
struct PublishedGains {
  std::string source;              // which paper, which table or equation
  double kp, ki, kd;               // as published (the paper's input units per °C; s)
  double plant_gain;               // the paper's K: °C per unit of its controller output
  int controller;                  // M310 S: the structure the paper's gains ran on
  std::string note;                // what had to change (e.g. a negative Kd)
};
std::optional<PublishedGains> published_gains(const PlantSpec& plant);
// Same loop gain C(s)·G(s) on our plant (rise_k °C at 100 % duty) as in the paper (plant gain
// k): Kp/255 · rise_k = kp · k, and likewise for Ki and Kd (their time units are seconds in
// both). Marlin units: output 0–255.
MarlinGains marlin_gains_from_paper(const PublishedGains& paper, double rise_k);

}  // namespace sim

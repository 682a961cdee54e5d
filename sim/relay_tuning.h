// The relay experiment behind Marlin's M303 autotune and the classic Ziegler–Nichols
// ultimate-cycle rule (issue 3's baseline), run on the plant model in double: an ideal relay
// around the target's steady-state duty makes the loop oscillate at its ultimate period Pu, and
// the describing function gives the ultimate gain Ku = 4·d/(π·a) (Åström & Hägglund 1984).
// Like Marlin's M303 each phase lasts at least 5 s; unlike it the bias is the exact balancing
// duty (M303 converges to it) and the output is the true temperature (no sensor noise).
#pragma once

#include "sim/plants.h"

namespace sim {

struct RelayResult {
  bool oscillated = false;
  double ultimate_gain_duty_per_k = 0.0;  // Ku: duty fraction per K
  double ultimate_period_s = 0.0;         // Pu
  double amplitude_k = 0.0;               // a: half the output's peak-to-peak
  double relay_amplitude_duty = 0.0;      // d
};

// The relay decides once per `decision_period_s` (the firmware's control period, as M303 runs on
// it; the sampling delay it adds sets Pu on lag-only plants such as hotend40w).
RelayResult relay_experiment(const PlantSpec& plant, double target_c, double decision_period_s);

}  // namespace sim

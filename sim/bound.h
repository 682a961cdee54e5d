// The physical bound: the shortest settling time into ±band any controller could reach on a
// plant with heater power ≤ 100 %, starting from ambient — full power, then exactly the
// steady-state duty, with the switch instant chosen optimally. Computed in double on the model.
#pragma once

#include "sim/plants.h"

namespace sim {

struct PhysicalBound {
  bool reachable = false;    // false if even 100 % cannot hold the target
  double settling_s = 0.0;   // from heater on to the last moment outside ±band
  double switch_s = 0.0;     // when the optimal input drops from 100 % to steady_duty
  double steady_duty = 0.0;  // 0..1
};

PhysicalBound physical_bound(const PlantSpec& plant, double target_c, double band_c = 1.0);

}  // namespace sim

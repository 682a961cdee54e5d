// One closed-loop runner for the host controller tests: a plant stepped once per control period
// under a controller, the trajectory recorded. Shared by the PID and fuzzy-PID suites.
#pragma once

#include <algorithm>
#include <vector>

#include "host_tests/hotend40w_model.h"

namespace test_plant {

struct Trajectory {
  std::vector<double> temp_c;  // sensor temperature after each period
  std::vector<double> duty;    // duty applied during each period (0..1)
  double max_c = -1e9;
};

// `controller(measured_c)` returns the duty 0..1 for the next period; `before_period(k, plant)`
// may disturb the plant (e.g. switch the part fan) before period k.
template <class Plant, class Controller, class BeforePeriod>
Trajectory run_closed_loop(Plant plant, Controller controller, double seconds, BeforePeriod before_period) {
  Trajectory t;
  for (int k = 0; k < int(seconds / kPeriodS); ++k) {
    before_period(k, plant);
    const double duty = controller(plant.sensor_c());
    plant.advance(duty, kPeriodS);
    t.temp_c.push_back(plant.sensor_c());
    t.duty.push_back(duty);
    t.max_c = std::max(t.max_c, plant.sensor_c());
  }
  return t;
}

template <class Plant, class Controller>
Trajectory run_closed_loop(Plant plant, Controller controller, double seconds) {
  return run_closed_loop(plant, controller, seconds, [](int, Plant&) {});
}

}  // namespace test_plant

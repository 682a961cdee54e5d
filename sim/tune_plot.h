// The picture of an --autotune run (issue 7): the hotend's true temperature and heater duty from
// the firmware's M303 on, with the response of the model the tune identified (M307 A C D F,
// simulated from the same heater and fan duty) laid over it — how well the board's model
// describes the hotend, through the tune and the tuned heat-up that follows.
#pragma once

#include <vector>

#include "sim/sim_run.h"
#include "sim/svg_plot.h"

namespace sim {

// Empty when the run has no finished tune.
std::vector<PlotSeries> tune_plot_series(const RunResult& result);

}  // namespace sim

// `hotend-sim plot`: temperature and heater duty against time for several runs (their --csv
// files) in one SVG, e.g. every controller on one plant for the README (issue 3).
#pragma once

#include <string>
#include <vector>

namespace sim {

struct PlotSeries {
  std::string label;
  std::vector<double> time_s, true_c, target_c, heater_duty;
};

// Reads the columns it needs from a trace CSV written by --csv (throws std::runtime_error).
PlotSeries read_trace_csv(const std::string& path, const std::string& label);
// Three panels sharing the time axis: true temperature (target dashed), the same zoomed to the
// target ± 5 °C, heater duty in %.
void write_svg_plot(const std::string& path, const std::string& title, const std::vector<PlotSeries>& series);

}  // namespace sim

#include "sim/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sim {
namespace {

constexpr double kWidth = 900, kPanelHeight = 260, kLeft = 60, kRight = 20, kTop = 40, kGap = 50;
// Per polyline: buckets are averaged down to between this and twice this many points (about a
// point per pixel of the 820-pixel plot area; keeps a 7-run plot below 200 KB for the repository).
constexpr std::size_t kMaxPoints = 600;
const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};
constexpr double kZoomC = 5.0;  // the middle panel: target ± this

struct Axis {
  double lo, hi;
  double step;  // tick spacing
};

// Round tick spacing (1, 2 or 5 × 10^n) for about six ticks, limits snapped to it.
Axis nice_axis(double lo, double hi) {
  if (!(hi > lo)) hi = lo + 1.0;
  const double raw = (hi - lo) / 6.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
  return Axis{std::floor(lo / step) * step, std::ceil(hi / step) * step, step};
}

// Pixel coordinates: a tenth of a pixel is finer than any display.
std::string fmt_px(double v) {
  char text[24];
  std::snprintf(text, sizeof text, "%.1f", v);
  return text;
}

std::string fmt(double v) {
  std::ostringstream s;
  s << std::round(v * 100.0) / 100.0;
  return s.str();
}

// Bucket means so a long run stays a light polyline and the PWM's ripple averages out.
std::string polyline(const std::vector<double>& t, const std::vector<double>& y, const Axis& tx,
                     const Axis& ay, double top, const char* colour, const char* extra = "") {
  std::ostringstream out;
  out << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.2\" " << extra << " points=\"";
  const std::size_t per = std::max<std::size_t>(1, t.size() / kMaxPoints);
  for (std::size_t i = 0; i + per <= t.size(); i += per) {
    double st = 0, sy = 0;
    for (std::size_t k = i; k < i + per; ++k) st += t[k], sy += y[k];
    const double x = kLeft + (st / per - tx.lo) / (tx.hi - tx.lo) * (kWidth - kLeft - kRight);
    // Clamped to the panel: the zoomed panel shows far-off values on its edge.
    const double v = std::clamp(sy / per, ay.lo, ay.hi);
    const double yy = top + kPanelHeight - (v - ay.lo) / (ay.hi - ay.lo) * kPanelHeight;
    out << fmt_px(x) << "," << fmt_px(yy) << " ";
  }
  out << "\"/>\n";
  return out.str();
}

std::string panel_frame(const Axis& tx, const Axis& ay, double top, const std::string& label) {
  std::ostringstream out;
  const double w = kWidth - kLeft - kRight;
  out << "<rect x=\"" << kLeft << "\" y=\"" << top << "\" width=\"" << w << "\" height=\"" << kPanelHeight
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (double v = ay.lo; v <= ay.hi + ay.step / 2; v += ay.step) {
    const double y = top + kPanelHeight - (v - ay.lo) / (ay.hi - ay.lo) * kPanelHeight;
    out << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + w << "\" y1=\"" << fmt(y) << "\" y2=\"" << fmt(y)
        << "\" stroke=\"#ddd\"/><text x=\"" << kLeft - 6 << "\" y=\"" << fmt(y + 4)
        << "\" text-anchor=\"end\">" << fmt(v) << "</text>\n";
  }
  for (double v = tx.lo; v <= tx.hi + tx.step / 2; v += tx.step) {
    const double x = kLeft + (v - tx.lo) / (tx.hi - tx.lo) * w;
    out << "<text x=\"" << fmt(x) << "\" y=\"" << top + kPanelHeight + 16 << "\" text-anchor=\"middle\">"
        << fmt(v) << "</text>\n";
  }
  out << "<text x=\"" << kLeft << "\" y=\"" << top - 6 << "\">" << label << "</text>\n";
  return out.str();
}

}  // namespace

PlotSeries read_trace_csv(const std::string& path, const std::string& label) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream s(line); std::getline(s, line, ',');) header.push_back(line);
  auto column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw std::runtime_error(path + " has no column " + name);
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t ct = column("time_s"), cy = column("true_c"), cr = column("target_c"),
                    cu = column("heater_duty");
  PlotSeries series;
  series.label = label;
  while (std::getline(in, line)) {
    std::vector<double> v;
    for (std::stringstream s(line); std::getline(s, line, ',');)
      v.push_back(line.empty() ? NAN : std::stod(line));
    if (v.size() < header.size()) continue;
    series.time_s.push_back(v[ct]);
    series.true_c.push_back(v[cy]);
    series.target_c.push_back(v[cr]);
    series.heater_duty.push_back(100.0 * v[cu]);
  }
  return series;
}

void write_svg_plot(const std::string& path, const std::string& title,
                    const std::vector<PlotSeries>& series) {
  double t_hi = 1, y_lo = 1e9, y_hi = -1e9;
  for (const PlotSeries& s : series) {
    if (!s.time_s.empty()) t_hi = std::max(t_hi, s.time_s.back());
    for (double y : s.true_c) y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
    for (double y : s.target_c) y_hi = std::max(y_hi, y);
  }
  const Axis tx = nice_axis(0, t_hi), ay = nice_axis(y_lo, y_hi), au{0, 100, 20};
  const double target = series.empty() || series[0].target_c.empty() ? 0.0 : series[0].target_c.back();
  const Axis az{target - kZoomC, target + kZoomC, 1.0};
  const double top2 = kTop + kPanelHeight + kGap, top3 = top2 + kPanelHeight + kGap;
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\""
      << top3 + kPanelHeight + 40 << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << kWidth / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"15\">" << title
      << "</text>\n"
      << panel_frame(tx, ay, kTop, "true temperature °C (target dashed)")
      << panel_frame(tx, az, top2, "the same, target ± 5 °C (values beyond drawn on the edge)")
      << panel_frame(tx, au, top3, "heater duty % (mean per PWM period)") << "<text x=\"" << kWidth / 2
      << "\" y=\"" << top3 + kPanelHeight + 34 << "\" text-anchor=\"middle\">time since power-on, s</text>\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const PlotSeries& s = series[i];
    const char* colour = kColours[i % (sizeof kColours / sizeof *kColours)];
    out << polyline(s.time_s, s.true_c, tx, ay, kTop, colour)
        << (i == 0 || s.target_c != series[0].target_c  // one dashed target for runs that share it
                ? polyline(s.time_s, s.target_c, tx, ay, kTop, colour, "stroke-dasharray=\"4 3\"")
                : std::string())
        << polyline(s.time_s, s.true_c, tx, az, top2, colour)
        << polyline(s.time_s, s.heater_duty, tx, au, top3, colour) << "<text x=\"" << kWidth - kRight - 8
        << "\" y=\"" << kTop + kPanelHeight - 10 - 15.0 * (series.size() - 1 - i)
        << "\" text-anchor=\"end\" fill=\"" << colour << "\">" << s.label << "</text>\n";
  }
  out << "</svg>\n";
}

}  // namespace sim

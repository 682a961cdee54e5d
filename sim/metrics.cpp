#include "sim/metrics.h"

#include <algorithm>
#include <cmath>

namespace sim {
namespace {

bool in_band(double temp_c, double target_c) { return std::fabs(temp_c - target_c) <= kBandC; }

// Relative time of the last sample outside the band in [from, to), if the last sample is inside
// (nullopt when the stretch ends outside; 0 if it was never outside).
std::optional<double> last_exit(const std::vector<TraceSample>& trace, std::size_t from, std::size_t to,
                                double t_ref_s, double target_c) {
  if (from >= to || !in_band(trace[to - 1].true_c, target_c)) return std::nullopt;
  for (std::size_t i = to; i-- > from;)
    if (!in_band(trace[i].true_c, target_c)) return trace[i].t_s - t_ref_s;
  return 0.0;
}

std::size_t first_at_or_after(const std::vector<TraceSample>& trace, double t_s) {
  return static_cast<std::size_t>(std::lower_bound(trace.begin(), trace.end(), t_s,
                                                   [](const TraceSample& s, double t) { return s.t_s < t; }) -
                                  trace.begin());
}

}  // namespace

Metrics compute_metrics(const std::vector<TraceSample>& trace, double t0_s, double target_c,
                        std::optional<double> disturbance_at_s) {
  Metrics m;
  const std::size_t begin = first_at_or_after(trace, t0_s);
  const std::size_t end =
      disturbance_at_s ? first_at_or_after(trace, t0_s + *disturbance_at_s) : trace.size();
  if (begin >= end) return m;

  for (std::size_t i = begin; i < end; ++i) {
    const TraceSample& s = trace[i];
    const double error = s.true_c - target_c;
    if (!m.time_to_reach_s && in_band(s.true_c, target_c)) m.time_to_reach_s = s.t_s - t0_s;
    m.overshoot_c = std::max(m.overshoot_c, error);
    if (i > begin) m.iae_c_s += std::fabs(error) * (s.t_s - trace[i - 1].t_s);
  }
  m.settling_s = last_exit(trace, begin, end, t0_s, target_c);

  const double span_s = trace[end - 1].t_s - trace[begin].t_s;
  const std::size_t steady_begin = first_at_or_after(trace, trace[end - 1].t_s - kSteadyFraction * span_s);
  double sum = 0.0, lo = trace[steady_begin].true_c, hi = lo;
  for (std::size_t i = steady_begin; i < end; ++i) {
    sum += trace[i].true_c - target_c;
    lo = std::min(lo, trace[i].true_c);
    hi = std::max(hi, trace[i].true_c);
    m.steady_ripple_c = std::max(m.steady_ripple_c, trace[i].true_ripple_c);
  }
  m.steady_from_s = trace[steady_begin].t_s - t0_s;
  m.steady_to_s = trace[end - 1].t_s - t0_s;
  m.steady_mean_error_c = sum / double(end - steady_begin);
  m.steady_peak_to_peak_c = hi - lo;

  if (disturbance_at_s && end < trace.size()) {
    DisturbanceMetrics d;
    d.at_s = *disturbance_at_s;
    for (std::size_t i = end; i < trace.size(); ++i)
      d.max_deviation_c = std::max(d.max_deviation_c, std::fabs(trace[i].true_c - target_c));
    d.recovery_s = last_exit(trace, end, trace.size(), t0_s + d.at_s, target_c);
    m.disturbance = d;
  }
  return m;
}

}  // namespace sim

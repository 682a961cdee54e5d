// Closed-loop harness for the state-feedback tests: a PlantSim driven every 128 ms by the
// fixed-point controller (as the firmware calls it) and, optionally, by the double reference on
// an identical plant, with the metrics the tests assert on.
#pragma once

#include <cmath>
#include <initializer_list>

#include "design/seed_models.h"
#include "design/plant_sim.h"
#include "control/state_feedback.h"
#include "design/state_feedback_quantize.h"
#include "design/state_feedback_reference.h"

namespace sf_test {

using namespace design;
using control::kSfMaxDelay;

struct Plant {
  const char* name;
  LtiModel model;
  double target_c;
  double seconds;
};

// The plant bank's targets: 210 °C, 150 °C for the nearly integrating seed000 models.
inline Plant plant(int i) {
  const Plant all[] = {
      {"seed002", seed002(), 210, 300},      {"seed004", seed004(), 210, 300},
      {"seed003", seed003(), 210, 300},      {"hotend40w", two_node(), 210, 400},
      {"seed000-4", seed000_4(), 150, 2000}, {"seed000-5", seed000_5(), 150, 2500}};
  return all[i];
}
constexpr int kPlantCount = 6;

struct Metrics {
  double overshoot_c = -1e9;    // max(true − target)
  double settle_s = 0;          // last time outside ±1 °C of the target (before any event)
  double mean_error_c = 0;      // over the last quarter before any event
  double p2p_c = 0;             // same window
  double max_dev_ref_c = 0;     // |fixed − reference| true temperatures (when compared)
  double max_dip_c = 0;         // target − true after the event
  double max_rise_c = 0;        // true − target after the event (overshoot a fan step leaves)
  double final_error_c = 0;     // at the end
  double past_target_c = -1e9;  // furthest excursion beyond the target, on the side away from
                                // where the temperature came from (overshoot or undershoot)
};

struct Scenario {
  double noise_c = 0;
  double gain_error = 1;         // plant input gain / model's
  double delay_error = 1;        // plant dead time / model's
  double event_s = -1;           // time of the fan / disturbance step (-1: none)
  double event_disturbance = 0;  // duty added to the plant input at event_s
  bool event_fan = false;        // part fan to 100 % at event_s
  bool use_fan_feedforward = true;
  double target_c = 0;        // 0: the plant's default
  double first_target_c = 0;  // if > 0: the target until first_until_s, then target_c
  double first_until_s = 0;   // (metrics count from then on)
};

// Issue 3's physical bound: full power, then the steady-state duty, with the switch time chosen
// to settle into ±1 K soonest. Exact ZOH model on the 128 ms grid (dead time included).
inline double physical_bound_s(const LtiModel& m, double target_c) {
  const Zoh z = discretize(m.a, m.b, 0.128, m.delay_s);
  const double rise = target_c - m.ambient_c, steady = rise / dc_gain(m);
  const double t_full = full_power_rise_time(m, rise);
  double tdom = 0;
  Cplx ev[kMatCap];
  eigenvalues(m.a, ev);
  for (int i = 0; i < m.n; ++i) tdom = std::fmax(tdom, ev[i].im == 0 ? -1.0 / ev[i].re : 0.0);
  const int horizon = static_cast<int>((t_full + m.delay_s + 3 * tdom) / 0.128);
  auto settle = [&](int k_switch) {
    Mat x = zeros(m.n, 1);
    double line[kSfMaxDelay * 8 + 200] = {};  // u history on the 128 ms grid
    const int len = z.delay + 2;
    int last_out = 0;
    for (int k = 0; k < horizon; ++k) {
      const double u = k < k_switch ? 1.0 : steady;
      for (int j = len - 1; j > 0; --j) line[j] = line[j - 1];
      line[0] = u;
      x = z.phi * x + line[z.delay] * z.gamma_a + (z.delay > 0 ? line[z.delay - 1] : u) * z.gamma_b;
      if (std::fabs((m.c * x)(0, 0) - rise) > 1.0) last_out = k + 1;
    }
    return last_out * 0.128;
  };
  double best = 1e9;
  int best_k = 0;
  const int k_full = static_cast<int>(t_full / 0.128);
  for (int k = k_full / 4; k <= k_full * 3 / 2; k += 1 + k_full / 60) {
    const double t = settle(k);
    if (t < best) {
      best = t;
      best_k = k;
    }
  }
  for (int k = best_k - k_full / 60 - 1; k <= best_k + k_full / 60 + 1; ++k)
    best = std::fmin(best, settle(k));
  return best;
}

class Loop {
 public:
  Loop(const Plant& p, const Scenario& s) : p_(p), s_(s), design_(design_state_feedback(p.model)) {
    error_ = quantize(design_, s.use_fan_feedforward ? p.model.fan_loss_per_k : 0.0, &k_);
  }
  const char* error() const { return error_; }
  const Design& design_result() const { return design_; }
  const control::StateFeedbackConstants& constants() const { return k_; }
  control::StateFeedback& controller() { return fixed_; }

  // Runs the fixed-point controller; with `compare`, the reference on its own plant as well.
  Metrics run(bool compare) {
    fixed_.configure(k_);
    ReferenceController ref(design_, s_.use_fan_feedforward ? p_.model.fan_loss_per_k : 0.0);
    LtiModel truth = p_.model;
    truth.delay_s *= s_.delay_error;
    PlantSim a(truth), b(truth);
    for (PlantSim* q : {&a, &b}) {
      q->set_noise(s_.noise_c);
      q->set_gain_error(s_.gain_error);
    }
    const double final_target = s_.target_c > 0 ? s_.target_c : p_.target_c;
    const double window_end = s_.event_s > 0 ? s_.event_s : p_.seconds;
    Metrics m;
    double lo = 1e9, hi = -1e9, sum = 0;
    int count = 0;
    double side = 0;  // +1 approaching from below, −1 from above
    const int steps = static_cast<int>(p_.seconds / 0.128 + 0.5);
    for (int k = 0; k < steps; ++k) {
      const double t = k * 0.128;
      const bool first = s_.first_target_c > 0 && t < s_.first_until_s;
      const double target = first ? s_.first_target_c : final_target;
      const bool event = s_.event_s > 0 && t >= s_.event_s;
      for (PlantSim* q : {&a, &b}) {
        if (event && s_.event_fan) q->set_fan(1.0);
        if (event) q->set_disturbance(s_.event_disturbance);
      }
      const uint8_t fan = event && s_.event_fan ? 255 : 0;
      const control::StepInput in{static_cast<int32_t>(std::lround(target * 256)),
                                  static_cast<int32_t>(std::lround(a.measured_c() * 256)), fan};
      const uint16_t duty = fixed_.step(in);
      a.run(duty / 65535.0, 0.128);
      if (compare) {
        b.run(ref.step(target, b.measured_c(), fan / 255.0), 0.128);
        m.max_dev_ref_c = std::fmax(m.max_dev_ref_c, std::fabs(a.true_c() - b.true_c()));
      }
      const double y = a.true_c();
      if (first) continue;
      if (!event) {
        m.overshoot_c = std::fmax(m.overshoot_c, y - target);
        if (side == 0) side = y < target ? 1 : -1;
        m.past_target_c = std::fmax(m.past_target_c, side * (y - target));
        if (std::fabs(y - target) > 1.0) m.settle_s = t + 0.128;
        if (t >= 0.75 * window_end) {
          lo = std::fmin(lo, y);
          hi = std::fmax(hi, y);
          sum += y - target;
          ++count;
        }
      } else {
        m.max_dip_c = std::fmax(m.max_dip_c, target - y);
        m.max_rise_c = std::fmax(m.max_rise_c, y - target);
      }
      m.final_error_c = y - target;
    }
    m.mean_error_c = count ? sum / count : 0;
    m.p2p_c = count ? hi - lo : 0;
    return m;
  }

 private:
  Plant p_;
  Scenario s_;
  Design design_;
  control::StateFeedbackConstants k_ = {};
  const char* error_ = nullptr;
  control::StateFeedback fixed_;
};

}  // namespace sf_test

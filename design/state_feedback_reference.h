// Double-precision reference of the state-feedback controller: the same law, observer and
// predictor as control/state_feedback.cpp, straight from the Design. The fixed-point runtime is
// tested against it; `hotend-design` simulates with it. Host-only, header-only.
#pragma once

#include "design/state_feedback_design.h"

namespace design {

class ReferenceController {
 public:
  explicit ReferenceController(const Design& d, double fan_loss_per_k = 0)
      : d_(d), fan_loss_per_k_(fan_loss_per_k) {}

  void reset() {
    primed_ = false;
    phase_ = 0;
  }

  // As Controller::init_bumpless: observer at the steady state of the measured temperature
  // holding `duty`, so the next output is `duty` when the target equals the temperature.
  void init_bumpless(double measured_c, double duty) {
    const double rise = measured_c - d_.real.model.ambient_c;
    for (int i = 0; i < d_.real.model.n; ++i) x_[i] = d_.ss_share(i, 0) * rise;
    bias_ = rise / d_.dc_gain - duty;
    for (int j = 0; j <= control::kSfMaxDelay; ++j) hist_[j] = duty;
    duty_ = duty;
    net_ = duty;  // until the first law update the primed duty holds (its fan share included)
    rise_ = 0;
    fan_full_ = 0;
    primed_ = true;
    phase_ = dd_start();  // as the fixed-point runtime: predictor sum first, then the law
  }

  // One firmware period (128 ms); fan in 0..1. Returns duty 0..1 for the next period.
  double step(double target_c, double measured_c, double fan) {
    if (!primed_) {  // after reset: the plant is assumed at rest at the measured temperature
      init_bumpless(measured_c, 0.0);
      bias_ = 0;
      return duty_;  // the runtime primes in a call of its own
    }
    if (phase_ != 0) {
      const int phase = phase_;
      phase_ = phase_ + 1 >= d_.decimation ? 0 : phase_ + 1;
      if (phase >= 2 && (phase - 2) * control::kSfFirChunk >= d_.zoh.delay) {
        // An idle call: the fan's share follows the fan, from the last law update's rise.
        fan_full_ = fan_loss_per_k_ * rise_;
        duty_ = clamp01(net_ + fan_full_ * fan);
      }
      return duty_;
    }
    phase_ = d_.decimation > 1 ? 1 : 0;
    const int n = d_.real.model.n;
    const int dd = d_.zoh.delay;
    const double amb = d_.real.model.ambient_c;
    const double y = measured_c - amb;
    double y_model = 0;
    for (int j = 0; j < n; ++j) y_model += d_.real.model.c(0, j) * x_[j];
    const double e = y - y_model;
    for (int i = 0; i < n; ++i) x_[i] += d_.k_obs(i, 0) * e;
    bias_ += d_.k_obs(n, 0) * e;
    // Law in effective input (heater minus the known fan loss); the fan loss is added to the
    // applied duty with weight 1, so it passes the dead time with the fan's own effect.
    double v = d_.m * (target_c - amb) - d_.g_d * bias_;
    for (int i = 0; i < n; ++i) v -= d_.lx(0, i) * x_[i];
    for (int j = 1; j <= dd; ++j) v -= d_.h[j - 1] * hist_[j];
    // With idle calls in the law period the share follows the fan between law updates, its
    // full-fan value one law period old here (as the runtime computes it in those calls).
    const bool follows = d_.decimation > control::state_feedback_min_decimation(static_cast<uint8_t>(dd));
    const double fan_duty = follows ? fan_full_ * fan : fan_loss_per_k_ * fan * (y > 0 ? y : 0);
    rise_ = y > 0 ? y : 0;
    net_ = v;
    const double u = clamp01(v + fan_duty);
    hist_[0] = u - fan_duty;
    // Time update with the applied (clamped) effective input: nothing winds up in saturation.
    const double ua = hist_[dd] + bias_;
    const double ub = hist_[dd > 0 ? dd - 1 : 0] + bias_;
    double next[kMatCap];
    for (int i = 0; i < n; ++i) {
      double s = d_.zoh.gamma_a(i, 0) * ua + d_.zoh.gamma_b(i, 0) * ub;
      for (int j = 0; j < n; ++j) s += d_.zoh.phi(i, j) * x_[j];
      next[i] = s;
    }
    for (int i = 0; i < n; ++i) x_[i] = next[i];
    for (int j = control::kSfMaxDelay; j >= 1; --j) hist_[j] = hist_[j - 1];
    duty_ = u;
    return u;
  }

  double bias() const { return bias_; }
  static double clamp01(double u) { return u < 0 ? 0 : (u > 1 ? 1 : u); }
  int dd_start() const { return d_.zoh.delay > 0 ? 2 : 0; }
  double state(int i) const { return x_[i]; }

 private:
  const Design& d_;
  double fan_loss_per_k_;
  double x_[kMatCap] = {};
  double bias_ = 0;
  double hist_[control::kSfMaxDelay + 1] = {};  // hist_[j] = v[k−j], heater minus fan loss
  double duty_ = 0;
  double net_ = 0, rise_ = 0, fan_full_ = 0;  // the fan's share between law updates
  int phase_ = 0;
  bool primed_ = false;
};

}  // namespace design

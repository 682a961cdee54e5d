// A double-precision plant for closed-loop checks of designs (tests, `hotend-design`): the
// continuous model integrated exactly (ZOH) on a 4 ms grid, with the input dead time as a delay
// line, a part fan that raises the heat loss (through the same dead time as the heater: it cools
// the heated block, as in sim/plants.h), an unmodelled input disturbance, an ambient that
// may differ from the model's, and optional sensor noise. Host-only, header-only.
#pragma once

#include "design/expm.h"
#include "design/lti_model.h"

namespace design {

class PlantSim {
 public:
  static constexpr double kDt = 0.004;  // divides 128 ms and the seeds' dead times exactly
  static constexpr int kMaxDelaySteps = 16384;

  explicit PlantSim(const LtiModel& m) : m_(m) {
    step_ = exp_and_integral(m.a, m.b, kDt);
    x_ = zeros(m.n, 1);
    delay_steps_ = static_cast<int>(m.delay_s / kDt + 0.5);
    if (delay_steps_ >= kMaxDelaySteps) delay_steps_ = kMaxDelaySteps - 1;
    ambient_c_ = m.ambient_c;
  }

  void set_fan(double fan01) { fan_ = fan01; }
  void set_disturbance(double duty) { disturbance_ = duty; }  // added to the plant input
  void set_ambient(double c) { ambient_c_ = c; }
  void set_noise(double sigma_c) { noise_c_ = sigma_c; }
  void set_noise_seed(unsigned long long seed) { rng_ = seed; }  // another noise realisation
  // Scales the plant's input gain relative to the model (model-error tests).
  void set_gain_error(double factor) { gain_ = factor; }

  // Holds `duty` (0..1) for period_s (a multiple of kDt).
  void run(double duty, double period_s) {
    const int steps = static_cast<int>(period_s / kDt + 0.5);
    for (int s = 0; s < steps; ++s) {
      line_[head_] = duty;
      fan_line_[head_] = fan_;
      const int tail = (head_ + kMaxDelaySteps - delay_steps_) % kMaxDelaySteps;
      head_ = (head_ + 1) % kMaxDelaySteps;
      const double lost = (fan_row_ * x_)(0, 0);  // heater-duty equivalent at 100 % fan
      const double input = gain_ * line_[tail] + disturbance_ - fan_line_[tail] * lost;
      x_ = step_.phi * x_ + input * step_.gamma;
      t_s_ += kDt;
    }
  }

  double true_c() const { return ambient_c_ + (m_.c * x_)(0, 0); }
  // What the firmware would read: noisy, rounded to 1/256 °C (temp_q8).
  double measured_c() {
    double v = true_c() + noise_c_ * gaussian();
    const double q = v * 256.0;
    return static_cast<double>(static_cast<long>(q < 0 ? q - 0.5 : q + 0.5)) / 256.0;
  }
  double time_s() const { return t_s_; }
  double state(int i) const { return x_(i, 0); }

 private:
  double gaussian() {  // sum of 12 uniforms (deterministic LCG): mean 0, sigma 1
    double s = 0;
    for (int i = 0; i < 12; ++i) {
      rng_ = rng_ * 6364136223846793005ULL + 1442695040888963407ULL;
      s += static_cast<double>(rng_ >> 11) / 9007199254740992.0;
    }
    return s - 6.0;
  }

  LtiModel m_;
  ExpIntegral step_;
  Mat fan_row_ = fan_row(m_);
  Mat x_;
  double line_[kMaxDelaySteps] = {};
  double fan_line_[kMaxDelaySteps] = {};  // the fan's loss takes the heater's path
  int head_ = 0;
  int delay_steps_ = 0;
  double fan_ = 0, disturbance_ = 0, ambient_c_ = 25, noise_c_ = 0, gain_ = 1, t_s_ = 0;
  unsigned long long rng_ = 12345;
};

}  // namespace design

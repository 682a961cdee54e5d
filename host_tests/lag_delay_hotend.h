// A hotend as two lags, a dead time and a part fan, with a noisy, quantised sensor: what
// autotune_fuzz tunes (any parameters) and the host tests' regression cases of its findings.
// τ1·ẋ1 = K·u(t − L) − (1 + F·fan)·x1 (the block's rise; the fan adds loss in proportion to it,
// the plant bank's convention), τ2·ẋ2 = x1 − x2 (the sensor), reading = ambient + x2 + noise,
// rounded to the ADC step and clamped to the thermistor table's span (control/thermistor.h).
// Not design::PlantSim (exact ZOH on a 4 ms grid): under the fuzzer's ASan build it took 117 ms
// per 2,560 s of hotend against 1.3 ms here, it has no ADC step and starts at ambient only.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include <cmath>

namespace lag_delay_hotend {

struct Params {
  double k_c = 450;          // rise at 100 % duty, °C
  double tau1_s = 240;       // block
  double tau2_s = 0;         // sensor lag (0: none)
  double dead_s = 0;         // transport delay, whole periods (≤ kMaxDelayS)
  double fan_loss = 0.426;   // extra loss at 100 % fan (the bank's 0.097/0.068 − 1)
  double noise_c = 0;        // σ of the reading noise
  double quant_c = 0;        // ADC step (0: none)
  double ambient_c = 25;
  double start_rise_c = 0;   // above ambient at the start (a hot start)
  uint32_t noise_seed = 1;
};

constexpr double kMaxDelayS = 166;

class Hotend {
 public:
  Hotend(const Params& p, double period_s)
      : p_(p), period_s_(period_s), x1_(p.start_rise_c), x2_(p.start_rise_c), rng_(0x9E3779B9u ^ p.noise_seed) {
    delay_steps_ = static_cast<size_t>(std::lround(std::fmin(p.dead_s, kMaxDelayS) / period_s));
    if (delay_steps_ >= kRing) delay_steps_ = kRing - 1;  // periods under 119 ms: the delay is cut
  }

  // The reading at the end of the current period, °C.
  double reading() {
    double r = p_.ambient_c + x2_ + p_.noise_c * noise();
    if (p_.quant_c > 0) r = std::round(r / p_.quant_c) * p_.quant_c;
    return std::fmin(std::fmax(r, -5.0), 320.0);
  }

  // One period at `duty` (0..1) with the fan at `fan` (0..1).
  void run(double duty, double fan) {
    delayed_[head_] = duty;
    const double u = delayed_[(head_ + kRing - delay_steps_) % kRing];
    head_ = (head_ + 1) % kRing;
    const double dt = period_s_ / kSubsteps;
    for (int i = 0; i < kSubsteps; ++i) {
      x1_ += dt * (p_.k_c * u - (1.0 + p_.fan_loss * fan) * x1_) / p_.tau1_s;
      x2_ = p_.tau2_s > dt ? x2_ + dt * (x1_ - x2_) / p_.tau2_s : x1_;
    }
  }

 private:
  static constexpr int kSubsteps = 8;
  static constexpr size_t kRing = 1400;  // > kMaxDelayS at 128 ms

  double noise() {  // Irwin–Hall(4), scaled to unit variance: bounded, deterministic
    double s = 0;
    for (int i = 0; i < 4; ++i) {
      rng_ ^= rng_ << 13;
      rng_ ^= rng_ >> 17;
      rng_ ^= rng_ << 5;
      s += (rng_ & 0xFFFF) / 65536.0;
    }
    return (s - 2.0) * std::sqrt(3.0);
  }

  Params p_;
  double period_s_;
  double x1_, x2_;
  uint32_t rng_;
  double delayed_[kRing] = {};
  size_t head_ = 0, delay_steps_ = 0;
};

}  // namespace lag_delay_hotend

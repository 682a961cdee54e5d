// Property test of the state-feedback magnitude limits (control/state_feedback_constants.h,
// state_feedback_constants_valid): for constants at those limits -- every mantissa at ±32767 or
// −32768 where the limits allow it, each observer row's |Φ−I| + |Γ| at its largest, extreme
// shifts and ambients -- and inputs at the ends of their domain, the int32 law
// (control/state_feedback.cpp, built with -fsanitize=undefined, no recovery: any signed
// overflow aborts) must match a 64-bit transliteration step by step, and the 64-bit reference's
// intermediates must stay inside int32. Constants just beyond the limit do leave int32 in the
// reference (so the limit is needed, and this test can fail).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>

#include "control/state_feedback.h"
#include "host_tests/state_feedback_fixtures.h"

namespace {

using control::kSfMaxDelay;
using control::kSfMaxStates;
using control::StateFeedbackConstants;

// control/state_feedback.cpp's arithmetic in int64, recording the largest magnitude any
// intermediate reaches (the int32 code is exact iff that stays below 2^31).
class Reference {
 public:
  explicit Reference(const StateFeedbackConstants& k) : k_(k) {}
  int64_t peak = 0;

  int64_t x(uint8_t i) const { return x_[i]; }
  int64_t bias() const { return bias_; }

  void reset() {
    primed_ = false;
    phase_ = 0;
    duty_ = 0;
  }
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) { prime(measured_q8, duty_q16, false); }

  uint16_t step(const control::StepInput& in) {
    if (!primed_) {
      prime(in.measured_q8, 0, true);
      return duty_;
    }
    const uint8_t phase = phase_;
    phase_ = phase + 1 >= k_.decimation ? 0 : phase + 1;
    if (phase == 0) {
      law(in);
    } else if (phase == 1) {
      time_update();
    } else if ((phase - 2) * control::kSfFirChunk < k_.delay) {
      fir_chunk(static_cast<uint8_t>(phase - 2));
    } else {  // an idle call: the fan's share follows the airflow
      fan_full_ = fan_share(rise_q8_, 255);
      if (in.fan_duty != fan_seen_) follow_fan(in.fan_duty);
    }
    return duty_;
  }

 private:
  static constexpr int64_t kSignalLimit = int64_t(1) << 27;

  int64_t v(int64_t value) {  // every intermediate passes through here
    peak = std::max(peak, value < 0 ? -value : value);
    return value;
  }
  int64_t mulhi16(int16_t m, int64_t x) { return v((int64_t(m) * v(x) + 0x8000) >> 16); }
  static int64_t clamp_abs(int64_t x, int64_t limit) { return x > limit ? limit : (x < -limit ? -limit : x); }
  static int64_t pow2(int sh) { return int64_t(1) << sh; }
  static int64_t asr(int64_t x, int sh) { return x >> std::min(sh, 31); }
  int64_t shl_sat(int64_t x, int n) {
    const int64_t limit = int64_t(1) << 28;
    for (; n >= 8; n -= 8) {
      if (x >= (limit >> 8) || x <= -(limit >> 8)) return x < 0 ? -limit : limit;
      x = v(x * 256);
    }
    for (; n != 0; --n) {
      if (x >= (limit >> 1) || x <= -(limit >> 1)) return x < 0 ? -limit : limit;
      x = v(x * 2);
    }
    return x;
  }
  int64_t scale(int64_t x, int sh) { return sh > 0 ? v((asr(x, sh - 1) + 1) >> 1) : shl_sat(x, -sh); }
  static int64_t duty_signal(int16_t duty_q15, int p) { return int64_t(duty_q15) * pow2(p + 1); }
  static int exponent(uint8_t shift) { return int(shift) - 16; }
  int64_t to_q16(int64_t temp_q8) { return clamp_abs(v(temp_q8), kSignalLimit >> 8) * 256; }
  int16_t history(int j) const { return hist_[(head_ - j + kSfMaxDelay + 1) % (kSfMaxDelay + 1)]; }

  void prime(int32_t measured_q8, uint16_t duty_q16, bool zero_bias) {
    const int64_t rise = to_q16(v(int64_t(measured_q8) - k_.ambient_q8));
    for (uint8_t i = 0; i < k_.n; ++i) {
      x_[i] = scale(mulhi16(k_.ss_share[i], rise), exponent(k_.ss_share_shift));
      residual_[i] = 0;
    }
    const int64_t inv = scale(mulhi16(k_.inv_gain, rise), exponent(k_.inv_gain_shift));
    const int64_t u = duty_signal(static_cast<int16_t>(duty_q16 >> 1), k_.input_shift);
    bias_ = zero_bias ? 0 : clamp_abs(v(inv - u), pow2(16 + k_.input_shift));
    for (auto& h : hist_) h = static_cast<int16_t>(duty_q16 >> 1);
    head_ = 0;
    duty_ = duty_q16;
    net_ = duty_q16;
    rise_q8_ = 0;
    fan_full_ = 0;
    phase_ = k_.delay > 0 ? 2 : 0;
    primed_ = true;
  }

  void law(const control::StepInput& in) {
    const uint8_t n = k_.n;
    const int64_t y = to_q16(v(int64_t(in.measured_q8) - k_.ambient_q8));
    int64_t y_model = 0;
    for (uint8_t j = 0; j < n; ++j)
      if (k_.output_mask & (1u << j)) y_model = v(y_model + x_[j]);
    const int64_t e = clamp_abs(v(y - y_model), kSignalLimit);
    for (uint8_t i = 0; i < n; ++i)
      x_[i] = clamp_abs(v(x_[i] + scale(mulhi16(k_.obs_gain[i], e), exponent(k_.obs_shift[i]))), kSignalLimit);
    bias_ = clamp_abs(v(bias_ + scale(mulhi16(k_.obs_gain[n], e), exponent(k_.obs_shift[n]))),
                      pow2(16 + k_.input_shift));
    const int64_t r = to_q16(v(int64_t(in.target_q8) - k_.ambient_q8));
    int64_t acc = v(mulhi16(k_.ff_gain, r) - mulhi16(k_.bias_gain, bias_));
    for (uint8_t j = 0; j < n; ++j)
      if (k_.fb_gain[j] != 0) acc = v(acc - mulhi16(k_.fb_gain[j], x_[j]));
    const int p = k_.input_shift;
    int64_t u = scale(acc, exponent(k_.ctrl_shift) + p);
    if (k_.delay > 0) u = v(u - scale(fir_, int(k_.fir_shift) + p - 9));
    u = clamp_abs(u, kSignalLimit);
    int64_t fan = 0;
    int64_t applied = 0;
    if (k_.decimation > control::state_feedback_min_decimation(k_.delay)) {
      rise_q8_ = y >> 8;
      net_ = u;
      fan = follow_fan(in.fan_duty);
      applied = duty_;
    } else {
      fan = fan_share(y >> 8, in.fan_duty);
      applied = std::min<int64_t>(std::max<int64_t>(v(u + fan), 0), 65535);
      duty_ = static_cast<uint16_t>(applied);
    }
    head_ = head_ == kSfMaxDelay ? 0 : head_ + 1;
    hist_[head_] = static_cast<int16_t>((applied - fan) >> 1);
  }

  int64_t fan_share(int64_t rise_q8, uint8_t fan_duty) {
    if (k_.fan_gain == 0 || fan_duty == 0 || rise_q8 <= 0) return 0;
    const int64_t fan = scale(mulhi16(k_.fan_gain, v(rise_q8 * fan_duty)), exponent(k_.fan_shift) + k_.input_shift);
    return std::min<int64_t>(std::max<int64_t>(fan, 0), 65535);
  }
  int64_t follow_fan(uint8_t fan_duty) {
    fan_seen_ = fan_duty;
    const int64_t fan = v((fan_full_ * (fan_duty * 257) + 32768) >> 16);
    duty_ = static_cast<uint16_t>(std::min<int64_t>(std::max<int64_t>(v(net_ + fan), 0), 65535));
    return fan;
  }

  void time_update() {
    const int p = k_.input_shift;
    const int64_t va = clamp_abs(v(duty_signal(history(k_.delay), p) + bias_), kSignalLimit);
    const int64_t vb = k_.delay > 0 ? clamp_abs(v(duty_signal(history(k_.delay - 1), p) + bias_), kSignalLimit) : va;
    int64_t delta[kSfMaxStates];
    for (uint8_t i = 0; i < k_.n; ++i) {
      int64_t acc = mulhi16(k_.phi_diag[i], x_[i]);
      if (k_.phi_off[i] != 0) acc = v(acc + mulhi16(k_.phi_off[i], x_[k_.phi_col[i]]));
      if (k_.gamma_a[i] != 0) acc = v(acc + mulhi16(k_.gamma_a[i], va));
      if (k_.gamma_b[i] != 0) acc = v(acc + mulhi16(k_.gamma_b[i], vb));
      const int sh = exponent(k_.phi_shift[i]);
      if (sh > 0) {
        const int64_t t = v(acc + residual_[i]);
        delta[i] = t >> sh;
        residual_[i] = t & (pow2(sh) - 1);
      } else {
        delta[i] = v(acc * pow2(-sh));
      }
    }
    for (uint8_t i = 0; i < k_.n; ++i) x_[i] = clamp_abs(v(x_[i] + delta[i]), kSignalLimit);
  }

  void fir_chunk(uint8_t chunk) {
    if (chunk == 0) fir_ = 0;
    const int first = chunk * control::kSfFirChunk;
    const int count = std::min<int>(k_.delay - first, control::kSfFirChunk);
    int64_t sum = fir_;
    for (int t = 0; t < count; ++t) sum = v(sum + ((int64_t(k_.fir[first + t]) * history(first + t)) >> 8));
    fir_ = sum;
  }

  StateFeedbackConstants k_;
  int64_t x_[kSfMaxStates] = {};
  int64_t residual_[kSfMaxStates] = {};
  int64_t bias_ = 0, fir_ = 0;
  int16_t hist_[kSfMaxDelay + 1] = {};
  int head_ = 0;
  uint8_t phase_ = 0;
  uint16_t duty_ = 0;
  bool primed_ = false;
  int64_t net_ = 0, rise_q8_ = 0, fan_full_ = 0;  // the fan's share between law updates
  uint8_t fan_seen_ = 0;
};

int16_t extreme(std::mt19937& rng) {
  switch (rng() % 4) {
    case 0: return 32767;
    case 1: return -32768;
    case 2: return -32767;
    default: return static_cast<int16_t>(rng());
  }
}

// Row i's four mantissas with Σ|m| as large as state_feedback_row_fits allows at its shift.
void fill_row_at_limit(StateFeedbackConstants& k, uint8_t i, std::mt19937& rng) {
  const uint8_t shift = k.phi_shift[i];
  int16_t* row[4] = {&k.phi_diag[i], &k.phi_off[i], &k.gamma_a[i], &k.gamma_b[i]};
  uint32_t budget = shift >= 14 ? 4u * 32768u : (1u << (shift + 3));
  std::shuffle(row, row + 4, rng);  // which mantissas get the budget first
  for (int16_t* m : row) {
    const uint32_t mag = std::min<uint32_t>(budget, rng() % 2 ? 32768u : 32767u);
    budget -= mag;
    const bool negative = rng() % 2 == 0 || mag == 32768u;
    *m = static_cast<int16_t>(negative ? -static_cast<int32_t>(mag) : static_cast<int32_t>(mag));
  }
}

StateFeedbackConstants at_limits(std::mt19937& rng) {
  StateFeedbackConstants k{};
  k.n = static_cast<uint8_t>(1 + rng() % kSfMaxStates);
  k.output_mask = static_cast<uint8_t>(1 + rng() % ((1u << k.n) - 1));
  k.delay = static_cast<uint8_t>(rng() % 2 ? kSfMaxDelay : rng() % (kSfMaxDelay + 1));
  // Half the time idle calls too (the fan's share follows the airflow in them).
  k.decimation = static_cast<uint8_t>(control::state_feedback_min_decimation(k.delay) + (rng() % 2 ? 0 : 1 + rng() % 3));
  k.input_shift = static_cast<uint8_t>(rng() % 2 ? 10 : rng() % 11);
  k.ambient_q8 = rng() % 2 ? control::kSfMaxAmbientQ8 : control::kSfMinAmbientQ8;
  auto shift = [&](int max) { return static_cast<uint8_t>(rng() % 3 == 0 ? 0 : rng() % (max + 1)); };
  for (uint8_t i = 0; i < kSfMaxStates; ++i) {
    k.phi_col[i] = static_cast<uint8_t>(rng() % k.n);
    k.phi_shift[i] = shift(40);
    fill_row_at_limit(k, i, rng);
    k.fb_gain[i] = extreme(rng);
    k.ss_share[i] = extreme(rng);
  }
  for (uint8_t i = 0; i <= kSfMaxStates; ++i) {
    k.obs_gain[i] = extreme(rng);
    k.obs_shift[i] = shift(46);
  }
  k.ff_gain = extreme(rng);
  k.bias_gain = extreme(rng);
  k.ctrl_shift = shift(46);
  for (auto& h : k.fir) h = extreme(rng);
  k.fir_shift = shift(46);
  k.fan_gain = extreme(rng);
  k.fan_shift = shift(46);
  k.ss_share_shift = shift(46);
  k.inv_gain = extreme(rng);
  k.inv_gain_shift = shift(46);
  return k;
}

int32_t extreme_temp(std::mt19937& rng) {
  constexpr int32_t kDomain = int32_t(1) << 30;  // the law's input contract
  switch (rng() % 5) {
    case 0: return kDomain;
    case 1: return -kDomain;
    case 2: return static_cast<int32_t>(rng() % (2001 * 256)) - 1000 * 256;
    default: return static_cast<int32_t>(rng() % (601 * 256)) - 100 * 256;
  }
}

// Runs both for `steps` with inputs at the extremes (occasional reset and take-over); returns
// the reference's peak. Fails at the first step where they differ.
int64_t run_both(const StateFeedbackConstants& k, std::mt19937& rng, int steps, bool run_int32) {
  control::StateFeedback law;
  if (run_int32) {
    EXPECT_TRUE(law.configure(k));
  }
  Reference ref(k);
  for (int s = 0; s < steps; ++s) {
    const uint32_t event = rng() % 64;
    if (event == 0) {
      law.reset();
      ref.reset();
    } else if (event == 1) {
      const int32_t measured = extreme_temp(rng);
      const uint16_t duty = static_cast<uint16_t>(rng());
      law.init_bumpless(measured, duty);
      ref.init_bumpless(measured, duty);
    }
    // Long runs of one extreme let the states walk to their clamps.
    const control::StepInput in{extreme_temp(rng), extreme_temp(rng), static_cast<uint8_t>(rng() % 2 ? 255 : rng())};
    const uint16_t expected = ref.step(in);
    if (!run_int32) continue;
    const uint16_t got = law.step(in);
    if (got != expected || law.bias_q16p() != ref.bias()) {
      ADD_FAILURE() << "step " << s << ": duty " << got << " vs " << expected;
      return ref.peak;
    }
    for (uint8_t i = 0; i < k.n; ++i) {
      if (law.state_q16(i) != ref.x(i)) {
        ADD_FAILURE() << "step " << s << ": x" << int(i) << " " << law.state_q16(i) << " vs " << ref.x(i);
        return ref.peak;
      }
    }
  }
  return ref.peak;
}

constexpr int64_t kInt32 = int64_t(1) << 31;

TEST(StateFeedbackLimits, DesignedConstantsMatchTheReference) {
  std::mt19937 rng(1);
  for (const StateFeedbackConstants* k : {&fixtures::hotend40w_constants(), &fixtures::seed002_constants(),
                                          &fixtures::seed004_constants()}) {
    ASSERT_TRUE(control::state_feedback_constants_valid(*k));
    EXPECT_LT(run_both(*k, rng, 3000, true), kInt32);
  }
}

TEST(StateFeedbackLimits, ConstantsAtTheLimitsStayInInt32) {
  std::mt19937 rng(8);
  int64_t worst = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const StateFeedbackConstants k = at_limits(rng);
    ASSERT_TRUE(control::state_feedback_constants_valid(k)) << "trial " << trial;
    const int64_t peak = run_both(k, rng, 600, true);
    ASSERT_LT(peak, kInt32) << "trial " << trial;
    worst = std::max(worst, peak);
    if (HasFailure()) return;
  }
  // The corners reach within a factor of 2 of int32: the limits are not needlessly tight.
  EXPECT_GT(worst, kInt32 / 2);
  std::printf("largest intermediate at the limits: %lld (2^31 = %lld)\n", static_cast<long long>(worst),
              static_cast<long long>(kInt32));
}

// Past the row limit (coefficients summing to ~128 instead of <= 8) the reference leaves
// int32: the int32 law would overflow there, which is why W1 and the EEPROM loader refuse it.
TEST(StateFeedbackLimits, BeyondTheRowLimitLeavesInt32) {
  std::mt19937 rng(3);
  int64_t worst = 0;
  for (int trial = 0; trial < 100; ++trial) {
    StateFeedbackConstants k = at_limits(rng);
    for (uint8_t i = 0; i < kSfMaxStates; ++i) {
      k.phi_shift[i] = 10;  // Σ|m| = 4·32767 at 2^10: coefficients ~128
      k.phi_diag[i] = k.phi_off[i] = k.gamma_a[i] = k.gamma_b[i] = 32767;
    }
    EXPECT_FALSE(control::state_feedback_constants_valid(k));
    worst = std::max(worst, run_both(k, rng, 600, false));
  }
  EXPECT_GE(worst, kInt32);
}

}  // namespace

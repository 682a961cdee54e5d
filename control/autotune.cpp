// The M303 identification engine (see autotune.h for the phases). Units: temperatures temp_q8
// (°C × 256), duties duty_q16 (65535 = 100 %) or "q8 duty" (256 = 100 %) in the bin history,
// time in ticks (control periods) and bins (kTicksPerBin ticks). Per-step cost on AVR, estimated
// from the operation counts (not measured; 32-bit division ≈ 600 cycles, mul_div_u32 ≈ 1,300,
// log2_q16 ≈ 700, mul_q16 ≈ 60):
//   7 ticks in 8: bin and filter accumulation, the relay's compares      ≈ 200 cycles
//   bin ticks: model update + loss learning (one division) + the
//              approach law (one division)                                ≈ 2,000 cycles
//   once, probe → approach: the model history (≤ 62 mul_q16)              ≈ 5,000 cycles
//   compute, ≤ 9 steps: one stored cycle each (3 ln, 3 mul_div_u32)       ≈ 8,000 cycles
// The last three are over the 1,000-cycle aim: split them over more ticks before the firmware
// calls this from its timer-driven step (see the report on the autotune branch).
#include "control/autotune.h"

#include "control/fixed.h"
#include "control/fixed_math.h"

namespace control {
namespace {

constexpr int32_t kQ8 = 256;
constexpr int32_t kDetectQ8 = kQ8 / 2;          // response detected at 0.5 °C above the baseline
constexpr int32_t kHeadroomQ8 = 12 * kQ8;       // the probe starts at least this far below the target
constexpr int32_t kHotQ8 = 15 * kQ8;            // "hot start": this far above ambient
constexpr int32_t kCoolDropQ8 = 3 * kQ8;        // a hot start waits for this much visible decay
constexpr int32_t kAssumedSlopeQ8PerS = 20 * kQ8;  // worst-case heating rate for the first pulse
constexpr int32_t kSettleBandQ8 = kQ8 / 2;  // |target − reading| for the relay to start
constexpr int32_t kAmplitudeQ8 = kQ8 * 3 / 2;   // relay half amplitude aimed at
constexpr int32_t kHysteresisQ8 = kQ8 / 5;      // relay switches at target ± 0.2 °C (filtered)
constexpr uint16_t kMinDutyStepQ16 = 328;       // d ≥ 0.5 %
constexpr uint16_t kMaxDutyStepQ16 = 16384;     // d ≤ 25 %
constexpr uint16_t kFull = 65535;

int32_t abs32(int32_t x) { return x < 0 ? -x : x; }

uint16_t clamp_duty(int32_t x) { return fixed::sat_u16(x); }

}  // namespace

constexpr int32_t Autotune::kMeasureAmbient;
constexpr int32_t Autotune::kDefaultAmbientQ8;
constexpr int32_t Autotune::kTooHotMarginQ8;
constexpr uint8_t Autotune::kMinCycles;
constexpr uint8_t Autotune::kMaxCycles;
constexpr uint8_t Autotune::kMaxStoredCycles;
constexpr uint8_t Autotune::kRingBins;
constexpr uint8_t Autotune::kTicksPerBin;

void Autotune::configure(uint16_t period_ms, uint16_t timeout_s) {
  period_ms_ = period_ms < 10 ? 10 : (period_ms > 2000 ? 2000 : period_ms);
  timeout_ticks_ = ticks_from_s(timeout_s);
}

// s → ticks: s ≤ 65535, ·1000 < 2^26.
uint32_t Autotune::ticks_from_s(uint16_t s) const { return uint32_t{s} * 1000u / period_ms_; }

// ticks → s × 256. ticks·period_ms ≤ the timeout in ms (≤ 65,535,000 < 2^26); × 256 would not
// fit for the longest timeouts, so divide first by 1000/8 and then shift: ticks·ms·256/1000 =
// ticks·ms·32/125.
int32_t Autotune::seconds_q8(uint32_t ticks) const {
  const uint32_t ms = ticks * period_ms_;
  // ms·32 < 2^32 up to 37 h; beyond that (never in practice) the long way.
  return static_cast<int32_t>(ms < (uint32_t{1} << 27) ? (ms * 32 + 62) / 125 : fixed::mul_div_u32(ms, 32, 125));
}

bool Autotune::start(int32_t target_q8, uint8_t cycles, bool measure_fan, int32_t ambient_q8) {
  const uint16_t period_ms = period_ms_;
  const uint32_t timeout_ticks = timeout_ticks_;
  *this = Autotune();  // forget the last run, keep the configuration
  period_ms_ = period_ms;
  timeout_ticks_ = timeout_ticks;
  if (timeout_ticks_ == 0) configure(period_ms_);
  state_ = AutotuneState::kRunning;
  failure_ = AutotuneFailure::kNone;
  if (target_q8 < 50 * kQ8 || target_q8 > 275 * kQ8 || cycles < kMinCycles || cycles > kMaxCycles ||
      (ambient_q8 != kMeasureAmbient && (ambient_q8 < 0 || ambient_q8 > 60 * kQ8))) {
    fail(AutotuneFailure::kBadParameters);
    return false;
  }
  target_q8_ = target_q8;
  cycles_ = cycles;
  measure_fan_ = measure_fan;
  ambient_given_ = ambient_q8 != kMeasureAmbient;
  ambient_q8_ = ambient_given_ ? ambient_q8 : kDefaultAmbientQ8;
  // Measured cycles: the first no-fan cycle settles the bias and is not used; then cycles − 1
  // no-fan cycles; with the fan, one settling cycle and ⌈cycles/3⌉ measured ones.
  nofan_measure_ = static_cast<uint8_t>(cycles - 1);
  fan_skip_ = 1;
  fan_measure_ = static_cast<uint8_t>((cycles + 2) / 3);
  tick_ = 0;
  bin_ticks_ = 0;
  bin_sum_q8_ = 0;
  bin_duty_sum_ = 0;
  duty_q16_ = 0;
  fan_ = 0;
  start_q8_ = INT32_MIN;
  enter(Phase::kBaseline);
  return true;
}

void Autotune::fail(AutotuneFailure why) {
  state_ = AutotuneState::kFailed;
  failure_ = why;
  phase_ = Phase::kDone;
  duty_q16_ = 0;
  fan_ = 0;
}

void Autotune::abort() {
  if (state_ == AutotuneState::kRunning) fail(AutotuneFailure::kAborted);
  duty_q16_ = 0;
  fan_ = 0;
}

void Autotune::enter(Phase p) {
  phase_ = p;
  bins_ = 0;
}

int32_t Autotune::model_ago(uint8_t bins) const {
  const uint8_t i = static_cast<uint8_t>((ring_head_ + kRingBins - 1 - (bins % kRingBins)) % kRingBins);
  return int32_t{ring_[i]} * 16 + offset_q8_;
}

uint8_t Autotune::duty_ago(uint8_t bins) const {
  return duty_ring_[(ring_head_ + kRingBins - 1 - (bins % kRingBins)) % kRingBins];
}

AutotuneOutput Autotune::step(int32_t y) {
  event_ = AutotuneEvent::kNone;
  if (state_ != AutotuneState::kRunning) return {0, 0, state_, failure_, event_};
  if (y > target_q8_ + kTooHotMarginQ8) {
    fail(AutotuneFailure::kTooHot);
    return {0, 0, state_, failure_, event_};
  }
  if (++tick_ > timeout_ticks_) {
    fail(AutotuneFailure::kTimeout);
    return {0, 0, state_, failure_, event_};
  }
  if (start_q8_ == INT32_MIN) {
    start_q8_ = y;
    for (int32_t& v : yf_ring_) v = y;
  }
  // Filter for the relay: mean of the last 4 readings (σ halves; 1.5 periods of delay).
  yf_ring_[yf_head_] = y;
  yf_head_ = static_cast<uint8_t>((yf_head_ + 1) & 3);
  const int32_t yf = (yf_ring_[0] + yf_ring_[1] + yf_ring_[2] + yf_ring_[3] + 2) >> 2;

  // The duty returned by the previous step was applied during the period this reading ends.
  bin_sum_q8_ += y;  // ≤ 8 · 2^17
  bin_duty_sum_ = static_cast<uint16_t>(bin_duty_sum_ + ((uint32_t{duty_q16_} + 128) >> 8));
  ++bin_ticks_;

  switch (phase_) {
    case Phase::kProbe:
      ++probe_ticks_;
      if (heater_on_) {
        ++on_ticks_;
        if (on_ticks_ >= cap_ticks_ && !(detected_ && extend_)) {
          heater_on_ = false;
          off_tick_ = probe_ticks_;
          dev_off_q8_ = dev_q8_;
        }
      }
      duty_q16_ = heater_on_ ? kFull : 0;
      break;
    case Phase::kRelay:
      relay_tick(yf, y);
      break;
    case Phase::kCompute:
      if (compute_chunk()) {
        state_ = AutotuneState::kFinished;
        phase_ = Phase::kDone;
        event_ = AutotuneEvent::kResult;
      }
      duty_q16_ = 0;
      fan_ = 0;
      break;
    default:
      break;
  }

  if (bin_ticks_ >= kTicksPerBin) {
    y_prev2_q8_ = y_prev_q8_;
    y_prev_q8_ = y_bin_q8_;
    y_bin_q8_ = (bin_sum_q8_ + kTicksPerBin / 2) / kTicksPerBin;
    last_bin_duty_q8_ = static_cast<uint16_t>((bin_duty_sum_ + kTicksPerBin / 2) / kTicksPerBin);
    y_hist_q8_[3] = y_hist_q8_[2];
    y_hist_q8_[2] = y_hist_q8_[1];
    y_hist_q8_[1] = y_hist_q8_[0];
    y_hist_q8_[0] = y_prev_q8_;
    bin_sum_q8_ = 0;
    bin_duty_sum_ = 0;
    bin_ticks_ = 0;
    ++bins_;
    if (phase_ == Phase::kApproach || phase_ == Phase::kRelay) {
      model_bin();
    } else {
      duty_ring_[ring_head_] = static_cast<uint8_t>(last_bin_duty_q8_ > 255 ? 255 : last_bin_duty_q8_);
      ring_[ring_head_] = 0;
      ring_head_ = static_cast<uint8_t>((ring_head_ + 1) % kRingBins);
    }
    if (state_ == AutotuneState::kRunning) on_bin();
  }
  return {duty_q16_, fan_, state_, failure_, event_};
}

void Autotune::on_bin() {
  switch (phase_) {
    case Phase::kBaseline: {
      if (bins_ < 3) return;
      const int32_t slope = (y_bin_q8_ - y_prev2_q8_) / 2;  // per bin
      y0_q8_ = y_bin_q8_;
      if (!ambient_given_ && y0_q8_ < 40 * kQ8 && abs32(slope) < kQ8 / 10 && !hot_start_) {
        ambient_q8_ = y0_q8_;
      }
      if (y0_q8_ > ambient_q8_ + kHotQ8) hot_start_ = true;
      // A hot hotend must first show a clean decay (heat still in flight from the firmware's
      // last duty would otherwise look like the probe's response), and be clear of the target.
      if ((hot_start_ && !cooled_) || y0_q8_ > target_q8_ - kHeadroomQ8) {
        cool_ref_q8_ = y0_q8_;
        enter(Phase::kCool);
        return;
      }
      const int32_t rise = y0_q8_ - ambient_q8_;
      base_rate_q16_ = 0;
      if (hot_start_ && slope < 0 && rise > 10 * kQ8) {
        base_rate_q16_ = clamp_duty(static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(-slope), 65536,
                                                                           static_cast<uint32_t>(rise))));
      }
      base_rise_q8_ = rise;
      // First pulse: at most 40 % of the headroom at an assumed 20 °C/s, and 6 s.
      const int32_t room = target_q8_ - y0_q8_ - 5 * kQ8;
      uint32_t cap = fixed::mul_div_u32(static_cast<uint32_t>(room > 0 ? room : 0) * 2, 1000,
                                        static_cast<uint32_t>(5 * kAssumedSlopeQ8PerS) * period_ms_);
      const uint32_t max_cap = ticks_from_s(6);
      cap_ticks_ = static_cast<uint16_t>(cap > max_cap ? max_cap : (cap < 1 ? 1 : cap));
      start_probe();
      return;
    }
    case Phase::kCool:
      duty_q16_ = 0;
      if (y_bin_q8_ < target_q8_ - kHeadroomQ8 - kQ8 && (!hot_start_ || y_bin_q8_ < cool_ref_q8_ - kCoolDropQ8)) {
        cooled_ = true;
        enter(Phase::kBaseline);
      }
      return;
    case Phase::kProbe:
      probe_bin();
      return;
    case Phase::kApproach:
      approach_bin();
      return;
    case Phase::kRelay:
      relay_bin();
      return;
    default:
      return;
  }
}

void Autotune::start_probe() {
  enter(Phase::kProbe);
  probe_ticks_ = 0;
  on_ticks_ = 0;
  heater_on_ = true;
  extend_ = false;
  detected_ = false;
  peaked_ = false;
  dev_q8_ = dev_prev_q8_ = dev_prev2_q8_ = 0;
  slope_max_q8_ = 0;
  slope_max_bin_ = 0;
  dev_peak_q8_ = INT32_MIN;
  duty_q16_ = kFull;
}

void Autotune::probe_bin() {
  // The baseline the hotend would follow without the probe (decaying when hot).
  base_rise_q8_ -= fixed::mul_q16(base_rise_q8_, base_rate_q16_);
  dev_prev2_q8_ = dev_prev_q8_;
  dev_prev_q8_ = dev_q8_;
  dev_q8_ = y_bin_q8_ - ambient_q8_ - base_rise_q8_;
  const uint16_t k = bins_;  // bin k covers probe ticks (8(k − 1), 8k]
  if (!detected_ && dev_q8_ >= kDetectQ8) {
    detected_ = true;
    det_bin_ = k;
  }
  int32_t slope = 0;
  if (k >= 3) {
    slope = (dev_q8_ - dev_prev2_q8_) / 2;  // centred on bin k − 1
    if (slope > slope_max_q8_ + slope_max_q8_ / 32) slope_max_bin_ = k;
    if (slope > slope_max_q8_) {
      slope_max_q8_ = slope;
      slope_max_dev_q8_ = dev_prev_q8_;
      max_centre_tick_ = static_cast<int32_t>(k - 1) * kTicksPerBin - kTicksPerBin / 2;
    }
  }
  if (heater_on_) {
    if (!detected_) return;
    // Still steepening (lags filling up): keep heating past the energy cap while, even at the
    // current slope over a generous horizon (2× the detection time + 4 s), it stays 10 °C
    // below the target. Once the slope is steady, S and the tangent's dead time are known:
    // go on heating under the approach's predictor, without a cut.
    const int32_t horizon = 2 * det_bin_ + 4;
    const bool steepening = k - slope_max_bin_ < 3 || k < det_bin_ + 3;
    const bool safe = y_bin_q8_ + slope * horizon < target_q8_ - 10 * kQ8 && on_ticks_ < ticks_from_s(40);
    extend_ = steepening && safe;
    if (!extend_ && slope_max_q8_ > 0 && (on_ticks_ >= cap_ticks_ || !steepening)) {
      continuous_ = true;
      const int32_t s = slope_max_q8_;
      int32_t l = max_centre_tick_ - slope_max_dev_q8_ * kTicksPerBin / s;  // tangent: L = t − rise/S
      slope_rise_q8_ = slope_max_dev_q8_ + base_rise_q8_;
      begin_approach(s, l, 0, static_cast<uint8_t>(on_ticks_ / kTicksPerBin));
    }
    return;
  }
  const uint16_t since_off = static_cast<uint16_t>(probe_ticks_ - off_tick_);
  if (!detected_) {
    if (since_off > ticks_from_s(60)) {
      // Nothing in a minute: a weaker hotend than assumed (or a dead heater). A 4× longer
      // pulse is safe: the last one raised it by less than 0.5 °C.
      if (++retries_ > 3) {
        fail(AutotuneFailure::kNoHeating);
        return;
      }
      cap_ticks_ = static_cast<uint16_t>(cap_ticks_ * 4);
      base_rise_q8_ = y_bin_q8_ - ambient_q8_;
      base_rate_q16_ = 0;
      start_probe();
    }
    return;
  }
  if (!peaked_) {
    if (dev_q8_ > dev_peak_q8_) {
      dev_peak_q8_ = dev_q8_;
      peak_bin_ = k;
      y_peak_q8_ = y_bin_q8_;
    } else if (k - peak_bin_ >= 2 && dev_q8_ < dev_peak_q8_ - kQ8 / 16) {
      peaked_ = true;
    } else if (since_off > ticks_from_s(90)) {
      peaked_ = true;  // a plateau (near-integrating hotend): take the highest
    }
    return;
  }
  // Cut-to-peak time (the FOPDT's dead time; longer than the lag of a lag-type hotend): the
  // output's peak is at the centre of the highest bin.
  const int32_t peak_tick = static_cast<int32_t>(peak_bin_) * kTicksPerBin - kTicksPerBin / 2;
  int32_t horizon_ticks = peak_tick - static_cast<int32_t>(off_tick_);
  // Decay after the peak for a quarter of the horizon (≥ 3 bins): the loss rate 1/T.
  const int32_t quarter = horizon_ticks / (4 * kTicksPerBin);
  if (k - peak_bin_ < (quarter < 3 ? 3 : quarter)) return;
  const int32_t drop = y_peak_q8_ - y_bin_q8_;
  const int32_t mid_rise = (y_peak_q8_ + y_bin_q8_) / 2 - ambient_q8_;
  uint32_t inv_t = 0;
  if (drop > kQ8 && mid_rise > kQ8) {  // a drop under 1 °C is noise: loss unknown (learnt later)
    inv_t = fixed::mul_div_u32(static_cast<uint32_t>(drop), 65536,
                               static_cast<uint32_t>(mid_rise) * static_cast<uint32_t>(k - peak_bin_));
  }
  // S: the steepest slope of the response, or the whole rise over the pulse when the pulse was
  // too short for a clean slope.
  int32_t s = dev_peak_q8_ * kTicksPerBin / (on_ticks_ > 0 ? on_ticks_ : 1);
  if (s < slope_max_q8_) s = slope_max_q8_;
  begin_approach(s, horizon_ticks, static_cast<uint16_t>(inv_t > 16384 ? 16384 : inv_t), 0);
}

void Autotune::begin_approach(int32_t s, int32_t horizon_ticks, uint16_t inv_t_q16, uint8_t on_bins) {
  if (s < 8) s = 8;
  if (horizon_ticks < kTicksPerBin) horizon_ticks = kTicksPerBin;
  slope_q8_ = s;
  inv_t_q16_ = inv_t_q16;
  horizon_ticks_ = horizon_ticks;
  uint32_t hb = static_cast<uint32_t>(horizon_ticks + kTicksPerBin - 1) / kTicksPerBin + 1;
  horizon_bins_ = static_cast<uint8_t>(hb > kRingBins - 2 ? kRingBins - 2 : hb);
  // Approach: closed-loop time constant = the horizon (≥ 3 bins); P gain 1/(S·τ).
  tau_bins_ = static_cast<uint8_t>(horizon_bins_ < 3 ? 3 : horizon_bins_ + horizon_bins_ / 4);
  const uint32_t g = (uint32_t{1} << 24) / (static_cast<uint32_t>(s) * tau_bins_);
  gain_q8_ = static_cast<int32_t>(g > 40000 ? 40000 : g);
  // ū = loss at the target / S (0 while the loss is unknown: learnt during the heat-up).
  steady_q16_ = steady_from_model();
  // The model's history over the last L̂ bins: the undelayed state whose delayed copy is the
  // reading now, x(now − L̂) = rise, run forward with the duty of those bins (full power for the
  // last min(on_bins, L̂), else off) and the loss. Older entries are never read.
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  const uint8_t on = on_bins < horizon_bins_ ? on_bins : horizon_bins_;
  int32_t x = rise;
  for (uint8_t j = horizon_bins_ + 1; j-- > 0;) {
    if (j < horizon_bins_) x += (j < on ? s : 0) - fixed::mul_q16(x, inv_t_q16_);
    ring_[(ring_head_ + kRingBins - 1 - j) % kRingBins] = static_cast<int16_t>(fixed::clamp(x / 16, int32_t{-32000}, int32_t{32000}));
    offset_q8_ = 0;
  }
  model_q8_ = x;
  ref_rise_q8_ = rise;
  ref_slope_q8_ = 0;
  full_bins_ = on;
  duty_avg_q16_ = 0;
  settled_bins_ = 0;
  enter(Phase::kApproach);
  duty_q16_ = heater_on_ ? kFull : 0;
  heater_on_ = false;
}

int32_t Autotune::steady_from_model() const {
  const uint32_t loss = static_cast<uint32_t>(fixed::mul_q16(target_q8_ - ambient_q8_, inv_t_q16_));
  // loss ≤ 2^14 (°C/bin × 256, clamped): × 2^16 < 2^31; one 32-bit division.
  const uint32_t u = ((loss > 16383 ? 16383 : loss) << 16) / static_cast<uint32_t>(slope_q8_);
  return static_cast<int32_t>(u > kFull ? kFull : u);
}

// Every bin of the approach and the relay: the Smith predictor's model, anchored to the reading,
// and the loss learning (see approach_bin for how they are used).
void Autotune::model_bin() {
  // Smith predictor: model x' = S·u − x/T (undelayed); prediction = reading + x(now) − x(now − L̂),
  // the heat in flight. The model is anchored to the reading (its delayed state pulled towards
  // it, a quarter per bin, by shifting the whole history through offset_q8_), so its loss term
  // works on the real temperature.
  model_q8_ += static_cast<int32_t>((static_cast<uint32_t>(slope_q8_) * last_bin_duty_q8_ + 128) >> 8) -
               fixed::mul_q16(model_q8_, inv_t_q16_);
  model_q8_ = fixed::clamp(model_q8_, int32_t{-30000} * 16, int32_t{30000} * 16);
  ring_[ring_head_] = static_cast<int16_t>(fixed::clamp((model_q8_ - offset_q8_) / 16, int32_t{-32000}, int32_t{32000}));
  duty_ring_[ring_head_] = static_cast<uint8_t>(last_bin_duty_q8_ > 255 ? 255 : last_bin_duty_q8_);
  ring_head_ = static_cast<uint8_t>((ring_head_ + 1) % kRingBins);
  // Bins the duty has stayed within ±8 % of where this stretch began.
  if (abs32(static_cast<int32_t>(last_bin_duty_q8_) - steady_ref_) < 20) {
    if (steady_bins_ < 250) ++steady_bins_;
  } else {
    steady_ref_ = static_cast<int16_t>(last_bin_duty_q8_);
    steady_bins_ = 0;
  }
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  const int32_t anchor = (rise - model_ago(horizon_bins_)) / 4;
  offset_q8_ += anchor;
  model_q8_ += anchor;
  // Loss learning near the target, where the heater is not at full power: the model's slope
  // S·u(t − L̂) − x/T against the reading's 4-bin slope; the error moves 1/T by ⅛ per bin. This
  // keeps the model's steady state on the real one, so the predictor holds the target exactly.
  // Only in the approach, and while the duty has been steady (within 8 %) over L̂ + 6 bins: in
  // transients a dead time that is off by a bin would pass for a loss error.
  if (phase_ != Phase::kApproach) return;
  if (full_bins_ == 0 && rise > 20 * kQ8 && steady_bins_ >= horizon_bins_ + 6) {
    const int32_t s4 = (y_bin_q8_ - y_hist_q8_[3]) / 4;
    const int32_t centre = rise - 2 * s4;
    const int32_t model_slope = static_cast<int32_t>((static_cast<uint32_t>(slope_q8_) * duty_ago(horizon_bins_ + 2) + 128) >> 8) -
                                fixed::mul_q16(centre, inv_t_q16_);
    const int32_t err = model_slope - s4;  // > 0: more loss than the model has
    // |err| ≤ 2^18 (clamped) × 2^13 < 2^31.
    const int32_t step = static_cast<int32_t>(static_cast<uint32_t>(abs32(err) > 262143 ? 262143 : abs32(err)) * 8192u / static_cast<uint32_t>(centre));
    inv_t_q16_ = static_cast<uint16_t>(fixed::clamp(static_cast<int32_t>(inv_t_q16_) + (err > 0 ? step : -step), int32_t{0}, int32_t{16384}));
  }
}

void Autotune::approach_bin() {
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  // Loss learning while at full power (the slope falls as the loss grows): 1/T = Δslope/Δrise
  // between a reference 4-bin slope taken once the heat-up runs at full power and the latest,
  // over at least 40 °C (the same estimator at both ends: no bias from taking a maximum).
  full_bins_ = last_bin_duty_q8_ >= 255 ? static_cast<uint8_t>(full_bins_ < 250 ? full_bins_ + 1 : 250) : 0;
  if (full_bins_ > horizon_bins_ + 4) {
    const int32_t s4 = (y_bin_q8_ - y_hist_q8_[3]) / 4;
    const int32_t at = rise - 2 * s4;  // rise at the window's centre
    if (ref_slope_q8_ == 0) {
      ref_slope_q8_ = s4 > 0 ? s4 : 1;
      ref_rise_q8_ = at;
    } else if (at - ref_rise_q8_ > 40 * kQ8 && s4 < ref_slope_q8_) {
      // ref_slope − s4 ≤ a full-power slope per bin (< 2^15 for < 128 °C/s) × 2^16 < 2^31.
      const uint32_t ds = static_cast<uint32_t>(ref_slope_q8_ - s4);
      const uint32_t inv_t = ((ds > 32767 ? 32767 : ds) << 16) / static_cast<uint32_t>(at - ref_rise_q8_);
      inv_t_q16_ = static_cast<uint16_t>(inv_t > 16384 ? 16384 : inv_t);
    }
  }
  steady_q16_ = steady_from_model();
  const int32_t predicted = y_bin_q8_ + model_ago(0) - model_ago(horizon_bins_);
  const int32_t ex = fixed::clamp(target_q8_ - predicted, -200 * kQ8, 200 * kQ8);
  const int32_t u = steady_q16_ + ((ex * gain_q8_) >> 8);  // |ex·gain| ≤ 51,200 · 40,000 < 2^31
  duty_q16_ = clamp_duty(u);
  duty_avg_q16_ += (static_cast<int32_t>(duty_q16_) - duty_avg_q16_) / 4;
  settled_bins_ = abs32(target_q8_ - y_bin_q8_) < kSettleBandQ8 ? static_cast<uint8_t>(settled_bins_ + 1) : 0;
  // Crossings of the target (±0.3 °C): a slow hotend that the approach leaves swinging around it
  // goes to the relay at the second crossing, whose bias adaptation takes over.
  const int8_t side = y_bin_q8_ > target_q8_ + kQ8 * 3 / 10 ? 1 : (y_bin_q8_ < target_q8_ - kQ8 * 3 / 10 ? -1 : 0);
  if (side != 0 && side != side_) {
    if (side_ != 0) ++crossings_;
    side_ = side;
  }
  if (settled_bins_ >= horizon_bins_ + 2 || crossings_ >= 2) {
    crossings_ = 0;
    side_ = 0;
    // Relay around the smoothed duty; d for ±1.5 °C by the probe's model (in-flight rise per
    // unit duty ≈ S·L̂ bounds the FOPDT excursion K·d·(1 − e^(−L/T))).
    bias_q16_ = clamp_duty(duty_avg_q16_);
    uint32_t d = fixed::mul_div_u32(kAmplitudeQ8, 65536, static_cast<uint32_t>(slope_q8_) * horizon_bins_);
    d_q16_ = static_cast<uint16_t>(d > kMaxDutyStepQ16 ? kMaxDutyStepQ16 : (d < kMinDutyStepQ16 ? kMinDutyStepQ16 : d));
    relay_hi_ = y_bin_q8_ < target_q8_;
    half_ticks_ = 0;
    started_cycle_ = false;
    cycle_index_ = 0;
    fan_part_ = fan_pending_;
    enter(Phase::kRelay);
  }
}

// A relay whose level no longer crosses the steady duty (the fan just came on, or the bias was
// off) drifts away instead of switching. After twice the horizon plus the longest half-period so
// far, move the bias by the drift: near the target ẏ = S·(u − ū), so ū = u − ẏ/S (+50 %).
void Autotune::relay_bin() {
  uint32_t wait = static_cast<uint32_t>(horizon_ticks_) + 4 * kTicksPerBin;
  if (wait < longest_half_) wait = longest_half_;  // a slow hotend's halves are long anyway
  if (half_ticks_ < wait || uint32_t{half_ticks_} - last_nudge_ < wait) return;
  const int32_t s4 = (y_bin_q8_ - y_hist_q8_[3]) / 4;  // per bin
  const bool away = relay_hi_ ? (s4 < 0 && y_bin_q8_ < target_q8_) : (s4 > 0 && y_bin_q8_ > target_q8_);
  if (!away) return;
  last_nudge_ = half_ticks_;
  // Near the target ẏ = S·u − rise/T, so the steady duty there is ū = (u − ẏ/S)·rise_target/rise.
  const int32_t level = relay_hi_ ? bias_q16_ + d_q16_ : bias_q16_ - d_q16_;
  const uint32_t ds = static_cast<uint32_t>(abs32(s4));
  const int32_t shift = static_cast<int32_t>(((ds > 32767 ? 32767 : ds) << 16) / static_cast<uint32_t>(slope_q8_));
  const int32_t u = relay_hi_ ? level + shift : level - shift;
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  if (u <= 0 || rise <= kQ8) return;
  // u · (rise_target/rise): the ratio in Q8 (≤ 2^10 for rise ≥ ¼ of the target's), u < 2^17.
  uint32_t ratio_q8 = static_cast<uint32_t>(target_q8_ - ambient_q8_) * 256u / static_cast<uint32_t>(rise);
  if (ratio_q8 > 1024) ratio_q8 = 1024;
  const int32_t estimate = static_cast<int32_t>((static_cast<uint32_t>(u > 131071 ? 131071 : u) * ratio_q8) >> 8);
  // At most 2·d per nudge: on a hotend slower than its probe showed, the drift is not yet the
  // steady one, and large moves would build up a swing.
  const int32_t limit = 2 * static_cast<int32_t>(d_q16_);
  bias_q16_ = clamp_duty(fixed::clamp(estimate, static_cast<int32_t>(bias_q16_) - limit, static_cast<int32_t>(bias_q16_) + limit));
}

void Autotune::set_levels() {
  if (d_q16_ > bias_q16_) d_q16_ = bias_q16_ < kMinDutyStepQ16 ? kMinDutyStepQ16 : bias_q16_;
  if (d_q16_ > kFull - bias_q16_) d_q16_ = static_cast<uint16_t>(kFull - bias_q16_);
}

void Autotune::relay_tick(int32_t yf, int32_t y) {
  ++half_ticks_;
  if (half_ticks_ == 1) last_nudge_ = 0;
  cyc_sum_dev_ += y - target_q8_;  // |y − target| ≤ 25 °C·256 per tick (else too hot / failed)
  cyc_sum_duty_ += duty_q16_;      // ≤ 65535 per tick; ≤ 65,000 ticks per cycle
  const uint32_t limit = ticks_from_s(600);
  if (half_ticks_ > limit) {
    fail(AutotuneFailure::kNoOscillation);
    return;
  }
  if (relay_hi_) {
    if (yf < cyc_min_q8_) cyc_min_q8_ = yf;
    if (yf > target_q8_ + kHysteresisQ8 && half_ticks_ >= kTicksPerBin) {
      sw_hi_q8_ = yf;
      t_hi_ = half_ticks_;
      if (half_ticks_ > longest_half_) longest_half_ = half_ticks_;
      half_ticks_ = 0;
      relay_hi_ = false;
      cyc_max_q8_ = yf;
    }
  } else {
    if (yf > cyc_max_q8_) cyc_max_q8_ = yf;
    if (yf < target_q8_ - kHysteresisQ8 && half_ticks_ >= kTicksPerBin) {
      sw_lo_q8_ = yf;
      const uint16_t t_lo = half_ticks_;
      if (half_ticks_ > longest_half_) longest_half_ = half_ticks_;
      half_ticks_ = 0;
      relay_hi_ = true;
      if (started_cycle_) end_cycle(t_lo);
      if (state_ != AutotuneState::kRunning || phase_ != Phase::kRelay) return;
      started_cycle_ = true;
      cyc_sum_dev_ = 0;
      cyc_sum_duty_ = 0;
      cyc_min_q8_ = yf;
    }
  }
  set_levels();
  duty_q16_ = relay_hi_ ? static_cast<uint16_t>(bias_q16_ + d_q16_) : static_cast<uint16_t>(bias_q16_ - d_q16_);
}

void Autotune::end_cycle(uint16_t t_lo) {
  const uint32_t period = uint32_t{t_hi_} + t_lo;
  cycle_.bias = static_cast<uint8_t>((uint32_t{bias_q16_} * 255 + 32768) >> 16);
  cycle_.d = static_cast<uint8_t>((uint32_t{d_q16_} * 255 + 32768) >> 16);
  cycle_.min_q8 = cyc_min_q8_;
  cycle_.max_q8 = cyc_max_q8_;
  event_ = AutotuneEvent::kCycle;
  int32_t a_q8 = (cyc_max_q8_ - cyc_min_q8_) / 2;
  if (a_q8 < 1) a_q8 = 1;
  // Ku = 4·d/(π·a) on the 0..255 scale: d_q16·255·4·256/(65536·π·a_q8/256)... = d_q16·324.68/a_q8;
  // d_q16 ≤ 65535 and 32,468 < 2^15: product < 2^31.
  ultimate_.ku_q8 = static_cast<int32_t>(uint32_t{d_q16_} * 32468u / 100u / static_cast<uint32_t>(a_q8));
  ultimate_.tu_q8 = seconds_q8(period);
  ++cycle_index_;
  const uint8_t part = fan_part_ ? 1 : 0;
  const uint8_t skip = fan_part_ ? fan_skip_ : 1;
  const uint8_t measure = fan_part_ ? fan_measure_ : nofan_measure_;
  if (cycle_index_ > skip) {
    event_ = AutotuneEvent::kUltimate;  // cycle_ is valid too
    sum_dev_[part] += cyc_sum_dev_;
    sum_duty_[part] += cyc_sum_duty_ >> 4;
    sum_ticks_[part] += period;
    if (!fan_part_) {
      StoredCycle& c = stored_[stored_count_ % kMaxStoredCycles];
      ++stored_count_;
      c.u_hi_q16 = static_cast<uint16_t>(bias_q16_ + d_q16_);
      c.u_lo_q16 = static_cast<uint16_t>(bias_q16_ - d_q16_);
      c.max_q8 = static_cast<int16_t>(cyc_max_q8_ - target_q8_);
      c.min_q8 = static_cast<int16_t>(cyc_min_q8_ - target_q8_);
      c.switch_hi_q8 = static_cast<int16_t>(sw_hi_q8_ - target_q8_);
      c.switch_lo_q8 = static_cast<int16_t>(sw_lo_q8_ - target_q8_);
      c.t_hi = t_hi_;
      c.t_lo = t_lo;
      ku_sum_q8_ += static_cast<uint32_t>(ultimate_.ku_q8);
      tu_sum_q8_ += static_cast<uint32_t>(ultimate_.tu_q8);
      ++ku_count_;
    }
  }
  // Adapt: bias = the cycle's mean duty (centres the oscillation), d towards ±1.5 °C.
  const uint32_t mean = cyc_sum_duty_ / (period > 0 ? period : 1);
  bias_q16_ = static_cast<uint16_t>(mean > kFull ? kFull : mean);
  uint32_t d = uint32_t{d_q16_} * kAmplitudeQ8 / static_cast<uint32_t>(a_q8);  // ≤ 2^16 · 384 < 2^25
  if (d > 2u * d_q16_) d = 2u * d_q16_;
  if (d < d_q16_ / 2u) d = d_q16_ / 2u;
  d_q16_ = static_cast<uint16_t>(d > kMaxDutyStepQ16 ? kMaxDutyStepQ16 : (d < kMinDutyStepQ16 ? kMinDutyStepQ16 : d));
  if (cycle_index_ >= skip + measure) {
    if (!fan_part_ && measure_fan_) {
      // The fan's extra loss is a large step disturbance (tens of °C on a fast hotend): let the
      // approach controller ride it out and re-learn the loss, then relay again with the fan.
      fan_ = 255;
      fan_pending_ = true;
      settled_bins_ = 0;
      full_bins_ = 0;
      enter(Phase::kApproach);
    } else {
      fan_ = 0;
      compute_step_ = 0;
      enter(Phase::kCompute);
    }
  }
}

bool Autotune::compute_chunk() {
  const int32_t rise_target = target_q8_ - ambient_q8_;
  if (compute_step_ == 0) {
    // K = mean rise / mean duty over the measured no-fan cycles.
    const int32_t n = static_cast<int32_t>(sum_ticks_[0]);
    const int32_t mean_rise = rise_target + sum_dev_[0] / (n > 0 ? n : 1);
    const uint32_t mean_duty_q12 = sum_duty_[0] / static_cast<uint32_t>(n > 0 ? n : 1);  // duty_q16 >> 4
    k_q8_ = mean_duty_q12 > 0 ? static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(mean_rise), 4096, mean_duty_q12))
                              : 0;
    t_sum_q8_ = l_sum_q8_ = 0;
    lambda_sum_q16_ = 0;
    tl_count_ = 0;
    ++compute_step_;
    return false;
  }
  const uint8_t stored = stored_count_ < kMaxStoredCycles ? stored_count_ : kMaxStoredCycles;
  if (compute_step_ <= stored) {
    const StoredCycle& c = stored_[compute_step_ - 1];
    ++compute_step_;
    // Rises above ambient, °C × 256.
    const int32_t a_hi = fixed::mul_q16(k_q8_, c.u_hi_q16);
    const int32_t a_lo = fixed::mul_q16(k_q8_, c.u_lo_q16);
    const int32_t y_max = rise_target + c.max_q8, y_min = rise_target + c.min_q8;
    const int32_t s_hi = rise_target + c.switch_hi_q8, s_lo = rise_target + c.switch_lo_q8;
    // FOPDT under a relay: y_max − y_min − (s_hi − s_lo) = (a_hi − a_lo − (s_hi − s_lo))·(1 − θ),
    // θ = e^(−L/T).
    const int32_t num = y_max - y_min - (s_hi - s_lo);
    const int32_t den = a_hi - a_lo - (s_hi - s_lo);
    if (num <= 0 || den <= num || a_hi <= s_hi || a_hi <= y_min || s_lo <= a_lo || y_max <= a_lo) return false;
    const uint32_t theta_q16 = 65536u - fixed::mul_div_u32(static_cast<uint32_t>(num), 65536, static_cast<uint32_t>(den));
    if (theta_q16 == 0) return false;
    const int32_t lambda = fixed_math::ln_ratio_q16(65536, theta_q16);  // L/T, Q16
    const int32_t ln_a = fixed_math::ln_ratio_q16(static_cast<uint32_t>(a_hi - y_min), static_cast<uint32_t>(a_hi - s_hi));
    const int32_t ln_b = fixed_math::ln_ratio_q16(static_cast<uint32_t>(y_max - a_lo), static_cast<uint32_t>(s_lo - a_lo));
    const int32_t sum = 2 * lambda + ln_a + ln_b;  // period / T, Q16
    if (sum <= 0) return false;
    const int32_t period_q8 = seconds_q8(uint32_t{c.t_hi} + c.t_lo);
    const int32_t t_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(period_q8), 65536, static_cast<uint32_t>(sum)));
    int32_t l_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(t_q8), static_cast<uint32_t>(lambda), 65536));
    // Not corrected for the relay filter's 1.5-period delay: the filter also rounds the peaks
    // off (a smaller amplitude reads as a shorter L), and the two nearly cancel (measured).
    t_sum_q8_ += t_q8;
    lambda_sum_q16_ += lambda;
    l_sum_q8_ += l_q8 > 0 ? l_q8 : 0;
    ++tl_count_;
    return false;
  }
  // Fan loss: F = K_nofan / K_fan − 1.
  int32_t f_q8 = 0;
  if (measure_fan_ && sum_ticks_[1] > 0) {
    const int32_t n = static_cast<int32_t>(sum_ticks_[1]);
    const int32_t mean_rise = rise_target + sum_dev_[1] / n;
    const uint32_t mean_duty_q12 = sum_duty_[1] / static_cast<uint32_t>(n);
    const uint32_t k_fan = mean_duty_q12 > 0 ? fixed::mul_div_u32(static_cast<uint32_t>(mean_rise), 4096, mean_duty_q12) : 0;
    if (k_fan > 0) f_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(k_q8_), 25600, k_fan)) - 25600;
    if (f_q8 < 0) f_q8 = 0;
  }
  result_.model.rise_q8 = k_q8_;
  result_.model.time_constant_q8 = tl_count_ > 0 ? t_sum_q8_ / tl_count_ : 0;
  result_.model.dead_time_q8 = tl_count_ > 0 ? l_sum_q8_ / tl_count_ : 0;
  if (continuous_ && k_q8_ > slope_rise_q8_) {
    // A lag-type hotend (its response started within the first pulse and steepened smoothly):
    // the relay's FOPDT formulas misread a lag as a long time constant. T from the heat-up
    // instead: the steepest slope S = (K − rise there)/T. L then from the relay's amplitude,
    // θ = e^(−L/T) (mean of the cycles' λ = L/T).
    const int32_t t_q8 = static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(k_q8_ - slope_rise_q8_),
                                                                 static_cast<uint32_t>(seconds_q8(kTicksPerBin)),
                                                                 static_cast<uint32_t>(slope_q8_)));
    result_.model.time_constant_q8 = t_q8;
    result_.model.dead_time_q8 = tl_count_ > 0 ? static_cast<int32_t>(fixed::mul_div_u32(static_cast<uint32_t>(t_q8),
                                                   static_cast<uint32_t>(lambda_sum_q16_ / tl_count_), 65536)) : 0;
    if (result_.model.dead_time_q8 < 0) result_.model.dead_time_q8 = 0;
  }
  result_.model.fan_loss_pct_q8 = f_q8;
  result_.sensor_lag_q8 = 0;
  result_.ultimate.ku_q8 = ku_count_ > 0 ? static_cast<int32_t>(ku_sum_q8_ / ku_count_) : 0;
  result_.ultimate.tu_q8 = ku_count_ > 0 ? static_cast<int32_t>(tu_sum_q8_ / ku_count_) : 0;
  result_.ambient_q8 = ambient_q8_;
  result_.hot_start = hot_start_;
  return true;
}

}  // namespace control

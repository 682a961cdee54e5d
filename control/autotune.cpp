// The M303 identification engine (see autotune.h for the phases). Units: temperatures temp_q8
// (°C × 256), duties duty_q16 (65535 = 100 %) or "q8 duty" (256 = 100 %) in the bin history,
// time in ticks (control periods) and bins (kTicksPerBin ticks).
//
// Per-step cost. step() runs inside the firmware's control step, so no call may be expensive:
// on AVR a 32-bit division costs ≈ 620 cycles, a 32×32 multiply ≈ 105, mul_q16 ≈ 130,
// log2_q16 ≈ 470, ln_ratio_q16 ≈ 1,070 (measured in simavr). The slow logic is therefore cut
// into pieces of at most ONE 32-bit division (or one ln_ratio), one piece per step:
//   every step: checks, the 4-reading filter, bin sums, the phase's per-tick logic
//     (probe pulse, relay compares; a relay switch copies the cycle's figures)
//   the step a bin completes: only the bin means and histories (shifts, no division)
//   the next steps, one each: that bin's logic as stages (bin_stage): baseline 3, probe ≤ 3
//     (the tail's model: 5 in its last bin, 1 in the next), probe → approach 3 (the model history is generated one entry per bin as it is read,
//     not all at once), approach 6, relay 3, fan step 1 (sums, no division); a relay cycle's end 3 more (cycle_stage), taking
//     precedence; they all fit in the 7 steps before the next bin (overruns() counts misses)
//   compute: one stage per step (a division, or a logarithm or two) for ≈ 62 steps
// No 64-bit arithmetic anywhere. Measured worst steps, in cycles (simavr, ATmega2560, -Os
// -mcall-prologues, no LTO; step() called on readings recorded from the host runs of hotend40w
// cold and hot, seed002, seed000-5, fopdt-30-1, the outputs checked equal to the host's):
//   a step with no piece pending ≈ 460–530; the step that completes a bin ≤ 1,500
//   baseline ≤ 1,360; probe ≤ 1,490 (the tail's model, 2026-12-08: whole control step in simavr
//   ≤ 2,865 on seed002-lag2); hand-over ≤ 1,470; approach ≤ 1,755 (loss learning: a
//   division, a mul_q16 and a 32×16 multiply); relay ≤ 1,720 (bias nudge), a cycle's end
//   ≤ 1,640; compute ≤ 1,865 (the T division with its normalising shifts). A lag probe's
//   approach adds a mul_q16 to its stages 1 and 6 (2026-12-05; whole control step in simavr
//   ≤ 2,767 on heavy-slow, 2,760 on hotend40w-delay5)
// That is over the ~1,500 aimed at by up to ~370 cycles: the fixed part of every step (~460) is
// the next thing to trim (see the report).
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
constexpr uint8_t kSettlingCycles = 1;          // relay cycles before the measured ones
constexpr int32_t kHysteresisQ8 = kQ8 / 5;       // relay switches at target ± 0.2 °C (filtered)
constexpr int32_t kTrendNoiseQ8 = 4;            // untrusted trend: a 4-bin slope under 1/64 °C/bin is noise (σ 0.2 °C: ±0.025)
constexpr int32_t kPeakDropQ8 = kQ8 / 8;        // probe: past the peak once this far below it (smoothed)
// On a noisy sensor these thresholds grow with the reading noise σ measured before the probe's
// response (noise_floor; factors × 1/16, chosen on the host table at σ 0.2–0.5 °C over 8 noise
// realisations): detection 3 σ (a bin mean's σ is σ/√8: 8.5 of those, so a slow creep plus noise
// does not pass for a response: seed000-4 at σ 0.3 took its first pulse's creep for one, L̂ 68 s
// against 250 s, +24 °C), the peak's drop 0.875 σ (4 × the 1-2-1 smoothed bins' 0.22 σ), the
// relay's hysteresis 0.75 σ (1.5 × the 4-reading mean's σ/2), the trend's dead band 2σ/16 (1 ×
// the 4-bin slope's σ/8: its noise held seed000's approach short of the target; 3σ/16 hid 11.6 °C
// of trend over 132 bins at σ 0.5, S + 5.9 °C), an untrusted approach's "near" band 8 σ (its
// guard's false alarms hold it 2–2.5 °C short at σ 0.5), the decay that measures the loss 4 σ (the
// highest bin is itself lifted by the noise), the relay's drift away 6σ/16 (3 × the 4-bin slope's
// σ/8: a noisy bin moved fopdt-120-25's bias past the steady duty, S + 6.8 °C), the relay's trend
// guard 3σ/16 (at the approach's 2σ/16 the guard's false alarms cut ~7 % of heavy-slow's bins at
// σ 0.5, more than the relay's d of 1.6 %, so its high level never reached the target: no
// oscillation in 5 of 20 noise realisations, 0 now; seed000's figures at σ 0.1 are unchanged).
constexpr uint8_t kDetectSigmaQ4 = 48;
constexpr uint8_t kPeakDropSigmaQ4 = 14;
constexpr uint8_t kHysteresisSigmaQ4 = 12;
constexpr uint8_t kTrendSigmaQ4 = 2;
constexpr uint8_t kNearSigmaQ4 = 128;
constexpr uint8_t kLossDropSigmaQ4 = 64;
// The full-power law on a model without loss lands on the loss learnt during it, one 4-bin
// slope's difference over 40 °C: ±26 % (1 σ) at σ 0.5 °C readings, which landed fopdt-120-25
// at S + 7..12 °C on 3 of 20 noise seeds. Only on a sensor this quiet (σ ≤ 0.15 °C).
constexpr uint16_t kQuietNoiseQ8 = 38;
// A cut probe's lag rule (begin_stage) up to a measured σ of 0.35 °C: issue 7's envelope reaches
// σ 0.3 °C, whose estimate with a 0.28 °C ADC step came to 0.30 (S + 8.4 °C on L̂ then); the bank
// stays within S + 4.7 °C at σ 0.33–0.5 over three noise realisations. (The estimate reads ~10 %
// low: a true σ up to ~0.39 °C passes.)
constexpr uint16_t kLagRuleNoiseQ8 = 90;
constexpr uint8_t kDriftSigmaQ4 = 6;
// The relay's longer minimum half (relay_tick): measured σ above 0.3 °C (Q8; the estimate reads
// σ 0.3 as ≈ 0.27), on a hotend whose L̂/T (probe horizon over the learnt time constant) is ≥ 0.2.
constexpr uint16_t kLongHalfNoiseQ8 = Autotune::kNoisyQ8;
constexpr uint32_t kLongHalfLOverTQ16 = 13107;
// The settled hold's window W = L̂ + 2 bins at least C/5 (settled_hold): its drift correction
// C·Δy/W then amplifies the halves' centre-to-centre slope at most 5 ×. With the window's duty
// aligned as settled_window does, fopdt-120-25 (C/W 4.3) held on 26 of 32 noise realisations at
// σ 0.05 / 0.1 °C and K 700 C 50 D 12 (C/W 3.5) on 8 of 18 at σ 0.05–0.2, A within 0.4 % on each
// hold. (With the duty a bin further back fopdt-120-25 read A 6 % low on 3 of 9 at σ 0.1, and the
// window was held to C/3.)
constexpr uint32_t kHoldWindowOverTQ16 = 13107;
constexpr int32_t kLongHalfFarQ8 = 2 * kQ8;
constexpr uint8_t kGuardSigmaQ4 = 3;
constexpr int32_t kGuardMarginQ8 = 2 * kQ8;     // untrusted model: relay's trend limit above target
// A bin's mean reading shows the model's state (L̂ + 4 ticks)/8 bins back: its readings' centre
// is half a bin before its end (model_delayed).
constexpr int32_t kAlignTicks = 4;
constexpr int32_t kSharpQ8 = kQ8 / 2;  // a probe's peak is sharp this far above its bin (sharp_peak)
constexpr uint8_t kSharpSigmaQ4 = 48;  // ... or 3 σ
constexpr uint16_t kMinDutyStepQ16 = 328;       // d ≥ 0.5 %
constexpr uint16_t kMaxDutyStepQ16 = 16384;     // d ≤ 25 %
constexpr uint16_t kFull = 65535;
constexpr uint8_t kCycleSteps = 15;  // compute steps per stored relay cycle
constexpr uint8_t kFanSteps = 6;     // compute steps of the gain with the fan (the first: the lag fit's Σ)
constexpr int32_t kFanFallQ8 = 8 * kQ8;  // the fan step's window may end once the reading fell this far
constexpr uint8_t kFanFallSigmaQ4 = 255;  // ... 16 σ of the reading (2 °C at least) after a tangent-timed probe
constexpr int32_t kFanRiseQ8 = 2 * kQ8;  // ... and ends once the reading is this far above S
// The fan step's held duty stays below 50 %: the firmware's model-free heating watch
// (firmware/thermal_watch.h, kMinDutyQ16) runs only at ≥ 50 % and would read the step's
// open-loop fall on a weak heater (ū ≥ 50 %) as a thermistor come loose.
constexpr uint16_t kFanHeldMaxQ16 = 32767;

// The small helpers below are noinline: with LTO every use was inlined (32-bit shifts and
// compares), 660 bytes of flash in all (div2n alone 496) for a call's few cycles.
__attribute__((noinline)) int32_t abs32(int32_t x) { return x < 0 ? -x : x; }

// x / 2^n truncated toward zero, as `/` does: avr-gcc -Os compiles a signed int32 divided by a
// power-of-two constant into a library division (≈ 650 cycles); this is a few shifts. n is an
// argument, not a template parameter: -Os shifts by a constant in a loop anyway, and one copy
// instead of four (n = 1, 2, 4, 5) is 164 B less flash.
__attribute__((noinline)) int32_t div2n(int32_t x, uint8_t n) { return x < 0 ? -(-x >> n) : x >> n; }

// A member far into the object (offset > 63) costs avr-gcc pointer arithmetic on every access;
// a pointer to its struct hidden from the optimiser is loaded once and then reached with LDD.
template <typename T> T& near(T& x) {
  T* p = &x;
  asm("" : "+r"(p));
  return *p;
}

__attribute__((noinline)) uint16_t clamp_duty(int32_t x) { return fixed::sat_u16(x); }

__attribute__((noinline)) uint16_t clamp_step(uint32_t d) {
  return static_cast<uint16_t>(d > kMaxDutyStepQ16 ? kMaxDutyStepQ16 : (d < kMinDutyStepQ16 ? kMinDutyStepQ16 : d));
}

// min(x, cap) · 2^16 / den, cap < 2^16: the capped Q16 ratios of the bin logic and the compute,
// one call instead of a 32-bit compare, shift and division written out at each of five sites.
__attribute__((noinline)) uint32_t capped_ratio_q16(uint32_t x, uint16_t cap, uint32_t den) {
  return (uint32_t{x > cap ? cap : x} << 16) / den;
}

// A model value (°C × 256) as a predictor ring entry: °C × 16, saturated to ±2,000 °C.
__attribute__((noinline)) int16_t ring_entry(int32_t x_q8) {
  return static_cast<int16_t>(fixed::clamp(div2n(x_q8, 4), int32_t{-32000}, int32_t{32000}));
}

// x · 2^16 / den for x ≥ 0, den > 0, with one 32-bit division: x is shifted up as far as it
// fits and den down by the rest (x < 2^19 here: ≥ 12 bits of x, den keeps ≥ 4 of its 16+).
uint32_t div_q16(uint32_t x, uint32_t den) {
  uint8_t up = 16;
  while (up > 0 && x >= (uint32_t{1} << 30)) { x >>= 1; --up; }  // never for x < 2^19
  while (up > 0 && x < (uint32_t{1} << 30)) { x <<= 1; --up; }
  den >>= up;
  return den > 0 ? x / den : 0xFFFFFFFFu;
}

// The heat-up's tangent reads a hotend whose thermistor lags the block (two lags τ1 > τ2) with
// too short a dead time: the designs want the FOPDT of a two-point fit (C.L. Smith's 28.3 % /
// 63.2 % points, what hotend-sim designs the true-model controllers from), whose dead time is
// 1.13–1.80 × the tangent's as τ2/τ1 goes from 0.01 to 0.5; the ratio is read off x = tangent
// dead time / T (T = the heat-up's (K − rise)/S less the lag, which stays within 6 % of the fit's
// T). Points from the exact two-lag step response at τ2/τ1 = 0, 0.02, 0.05, 0.1, 0.2, 0.3 (then
// flat): x Q16, factor Q12; seed003 (τ2/τ1 = 0.5): 5.2 s → 9.4 s against the fit's 9.9 s.
// Piecewise linear in code, not a table (a table would sit in AVR RAM): lag < 2^17, factor
// < 2^13; (x − x0)·Δf < 2^13 · 2^10.
int32_t two_point_dead_time(int32_t lag_q8, int32_t x_q16) {
  int32_t x0 = 0, f0 = 4096, x1 = 1094, f1 = 4948;
  if (x_q16 > 1094) x0 = 1094, f0 = 4948, x1 = 2386, f1 = 5689;
  if (x_q16 > 2386) x0 = 2386, f0 = 5689, x1 = 4070, f1 = 6525;
  if (x_q16 > 4070) x0 = 4070, f0 = 6525, x1 = 6416, f1 = 7188;
  if (x_q16 > 6416) x0 = 6416, f0 = 7188, x1 = 7956, f1 = 7348;
  // beyond the last point: flat (1.79–1.80 up to equal lags)
  const int32_t f = x_q16 >= x1 ? f1 : f0 + (x_q16 - x0) * (f1 - f0) / (x1 - x0);
  return static_cast<int32_t>((static_cast<uint32_t>(lag_q8) * static_cast<uint32_t>(f) + 2048u) >> 12);
}

}  // namespace

constexpr int32_t Autotune::kMeasureAmbient;
constexpr int32_t Autotune::kDefaultAmbientQ8;
constexpr int32_t Autotune::kTooHotMarginQ8;
constexpr uint8_t Autotune::kMinCycles;
constexpr uint8_t Autotune::kMaxCycles;
constexpr uint8_t Autotune::kMaxStoredCycles;
constexpr uint8_t Autotune::kRingBins;
constexpr uint8_t Autotune::kTicksPerBin;

// Not on the step path: the divisions here are paid once, at M303.
void Autotune::configure(uint16_t period_ms, uint16_t timeout_s) {
  period_ms_ = period_ms < 10 ? 10 : (period_ms > 2000 ? 2000 : period_ms);
  timeout_ticks_ = ticks_from_s(timeout_s);
  t6_ = static_cast<uint16_t>(ticks_from_s(6));
  t40_ = static_cast<uint16_t>(ticks_from_s(40));
  t60_ = static_cast<uint16_t>(ticks_from_s(60));
  t90_ = static_cast<uint16_t>(ticks_from_s(90));
  t600_ = static_cast<uint16_t>(clamp_half_ticks(ticks_from_s(600)));
  // ticks → s × 256 = ticks · period_ms · 256/1000, as a whole + Q16 multiplier (period·256
  // ≤ 512,000; the remainder < 1000, × 2^16 < 2^26).
  const uint32_t ms256 = uint32_t{period_ms_} * 256u;
  tick_s_whole_ = ms256 / 1000u;
  const uint32_t frac = ((ms256 % 1000u) * 65536u + 500u) / 1000u;
  if (frac > 0xFFFFu) ++tick_s_whole_;
  tick_s_frac_ = static_cast<uint16_t>(frac > 0xFFFFu ? 0 : frac);
}

// s → ticks: s ≤ 65535, ·1000 < 2^26.
uint32_t Autotune::ticks_from_s(uint16_t s) const { return uint32_t{s} * 1000u / period_ms_; }

// A relay half-cycle's limit: at most 2^15 − 1 ticks, so that a whole cycle (two halves) fits the
// 16-bit period_ticks_ and its sums (the firmware's 128 ms: 70 min, past any tune's time limit).
uint32_t Autotune::clamp_half_ticks(uint32_t ticks) { return ticks > 0x7FFFu ? 0x7FFFu : ticks; }

// ticks → s × 256: ticks < 2^16, whole ≤ 512: products < 2^25.
int32_t Autotune::seconds_q8(uint16_t ticks) const {
  return fixed::mul_round(ticks, fixed::Multiplier{tick_s_whole_, tick_s_frac_});
}

bool Autotune::start(int32_t target_q8, uint8_t cycles, bool measure_fan, int32_t ambient_q8, int32_t hold_gain_q8) {
  const uint16_t period_ms = period_ms_ != 0 ? period_ms_ : 128;
  const uint32_t timeout_ticks = timeout_ticks_;
  // Forget the last run, keep the configuration. Byte by byte (every member is a plain integer,
  // enum or array of them, all defaulting to 0): `*this = Autotune()` made avr-gcc build a
  // 750-byte temporary on the stack.
  static_assert(__is_trivially_copyable(Autotune), "start() clears the object byte by byte");
  uint8_t* bytes = reinterpret_cast<uint8_t*>(this);
  for (uint16_t i = 0; i < sizeof(Autotune); ++i) bytes[i] = 0;
  ambient_q8_ = kDefaultAmbientQ8;
  configure(period_ms, 1800);
  if (timeout_ticks != 0) timeout_ticks_ = timeout_ticks;
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
  // C is the measurement effort: the first relay cycle settles the bias and is not used, then
  // max(2, C − 3) measured ones (with the drift correction two gave A within 1 % on the FOPDT
  // plants; C5's former four cost 2 × 4 L̂); the fan step's window is ⌈C/2⌉ × (L̂/2 + 4) bins.
  nofan_measure_ = static_cast<uint8_t>(cycles > 5 ? cycles - 3 : 2);
  // K ≥ 1/16 °C per unit duty kept (< 4,096 °C: SteadyHold's K ≤ 4,000), else none.
  hold_gain_q4_ = static_cast<uint16_t>(hold_gain_q8 >= 16 && hold_gain_q8 < (1L << 20) ? hold_gain_q8 >> 4 : 0);
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

// i mod kRingBins for i < 2·kRingBins (every index the ring is reached by: < 143).
static __attribute__((noinline)) uint8_t wrap_ring(uint8_t i) { return i >= Autotune::kRingBins ? static_cast<uint8_t>(i - Autotune::kRingBins) : i; }

uint8_t Autotune::ring_index(uint8_t bins) const {
  // Subtractions, not `%`: avr-gcc calls a 16-bit division for each (≈ 200 cycles), and the
  // aligned predictor reads the ring four times a bin. bins ≤ 72 here.
  while (bins >= kRingBins) bins = static_cast<uint8_t>(bins - kRingBins);
  return wrap_ring(static_cast<uint8_t>(ring_head_ + kRingBins - 1 - bins));
}

// The reading's 4-bin slope (°C × 256 per bin), ending at the last bin: one call for its four users.
__attribute__((noinline)) int32_t Autotune::slope4_q8() const { return div2n(y_bin_q8_ - y_hist_q8_[3], 2); }

__attribute__((noinline)) int32_t Autotune::model_ago(uint8_t bins) const { return int32_t{ring_[ring_index(bins)]} * 16 + offset_q8_; }

// The model's state the last bin's reading shows: (L̂ + kAlignTicks)/8 bins ago, interpolated
// between whole bins (the whole-bin horizon is up to 1.5 bins long: in a fast heat-up that is
// tens of °C of heat taken for in flight, and a deadbeat approach then fell short by as much).
// Entries differ by < 2^20 (±2,000 °C), × frac < 2^8.
int32_t Autotune::model_delayed() const {
  // (The slow law, tuned on the whole-bin horizon, keeps it: its plants' peaks are flat or
  // their models unsure, and the bin is their timing's resolution anyway. Not after a
  // tangent-timed flat probe's deadbeat, landed 4: there the whole bin, 1.1 bins longer than
  // fopdt-delay25's D + ½ tick, pulled the anchored model 2 °C above the reading as it landed,
  // and the slow law held the duty under ū until the reading dipped 1.4 °C.)
  if (appr_.landed == 2 || appr_.landed == 3) return model_ago(horizon_bins_);
  const uint32_t j_q8 = static_cast<uint32_t>(horizon_ticks_ + kAlignTicks) << 5;  // ÷ 8 bins, × 256
  uint8_t whole = static_cast<uint8_t>(j_q8 >> 8);
  if (whole > kRingBins - 2) whole = kRingBins - 2;
  const int32_t a = model_ago(whole);
  return a + div2n((model_ago(static_cast<uint8_t>(whole + 1)) - a) * static_cast<int32_t>(j_q8 & 0xFF), 8);
}

// A cold cut probe's sharp peak: its highest reading 0.5 °C (3 σ of a noisy one) above its bin's
// mean (stage 4 tells the same from the deviations). seed002/004's peak bins lie 1–2 °C below;
// seed000's flat top, with σ 0.02 °C readings, 0.06 °C (3 σ alone called it sharp: its L̂ then
// the noise's, and the design after U1 overshot 22 °C).
bool Autotune::sharp_peak() const {
  return !hot_start_ && probe_.retries == 0 && probe_.y_peak_q8 < probe_max_q8_ - noise_floor(kSharpQ8, kSharpSigmaQ4);
}

uint8_t Autotune::duty_ago(uint8_t bins) const { return duty_ring_[ring_index(bins)]; }

// The bin just completed into the histories: its mean duty and the model's entry (0 outside the
// approach and the relay). One copy for bin_end and model_bin.
__attribute__((noinline)) void Autotune::push_bin(int16_t model_entry) {
  duty_ring_[ring_head_] = static_cast<uint8_t>(last_bin_duty_q8_ > 255 ? 255 : last_bin_duty_q8_);
  ring_[ring_head_] = model_entry;
  ring_head_ = wrap_ring(static_cast<uint8_t>(ring_head_ + 1));
}

// The model's rise per bin at a bin's mean duty (256 = 100 %), rounded: S < 2^15, × 256 < 2^23.
__attribute__((noinline)) int32_t Autotune::heat_q8(uint16_t duty_q8) const {
  return static_cast<int32_t>((static_cast<uint32_t>(slope_q8_) * duty_q8 + 128) >> 8);
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
  if (phase_ == Phase::kBaseline || phase_ == Phase::kCool || (phase_ == Phase::kProbe && !probe_.detected)) {
    measure_noise(y);
  }
  // Filter for the relay: mean of the last 4 readings (σ halves; 1.5 periods of delay).
  yf_ring_[yf_head_] = y;
  yf_head_ = static_cast<uint8_t>((yf_head_ + 1) & 3);
  const int32_t yf = (yf_ring_[0] + yf_ring_[1] + yf_ring_[2] + yf_ring_[3] + 2) >> 2;

  // The duty returned by the previous step was applied during the period this reading ends.
  bin_sum_q8_ += y;  // ≤ 8 · 2^17
  bin_duty_sum_ = static_cast<uint16_t>(bin_duty_sum_ + ((uint32_t{duty_q16_} + 128) >> 8));
  ++bin_ticks_;

  bool ended = false;
  switch (phase_) {
    case Phase::kProbe:
      ++probe_ticks_;
      if (heater_on_) {
        ++probe_.on_ticks;
        if (probe_.on_ticks >= probe_.cap_ticks && !(probe_.detected && probe_.extend)) {
          heater_on_ = false;
          probe_.off_tick = probe_ticks_;
        }
      }
      // Between the decision and the approach (begin stages) the pulse goes on as it was.
      duty_q16_ = heater_on_ ? kFull : 0;
      // The highest single reading after the cut: the FOPDT response's sharp peak, which a bin
      // mean rounds off by up to ~4 % of its height (seed002: rising 16 °C/s, falling 2.6).
      if (!heater_on_ && !probe_.peaked && y > probe_max_q8_) {
        probe_max_q8_ = y;
        probe_.max_tick = probe_ticks_;  // a sharp peak's time, to the tick (the bins: ±4)
      }
      break;
    case Phase::kRelay:
      ended = relay_tick(yf, y);
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

  // One piece of slow work per step, never on a step that completed a bin or a relay cycle.
  if (phase_ == Phase::kCompute || phase_ == Phase::kDone) {
    bin_ticks_ = 0;  // the compute has a piece of its own every step
  } else if (bin_ticks_ >= kTicksPerBin) {
    if (stage_ != 0 && overruns_ < 255) ++overruns_;
    bin_end();
    stage_ = 1;
    if (probe_pending_) {
      // The probe starts on a bin boundary: its timing (dead time, peak) counts in whole bins.
      // Its baseline is this bin (a hot hotend's decay runs on from here).
      probe_pending_ = false;
      // A cold hotend's baseline over the last 4 bins (σ halved on a noisy sensor); a hot one
      // decays by up to ~1 °C a bin: its last bin.
      probe_.base_rise_q8 = (hot_start_ || probe_.retries != 0 ? y_bin_q8_ : div2n(y_bin_q8_ + y_hist_q8_[0] + y_hist_q8_[1] + y_hist_q8_[2] + 2, 2)) -
                      ambient_q8_;
      start_probe();
      stage_ = 0;
    }
  } else if (ended) {
    // end_cycle ran this step: its stages start with the next one.
  } else if (stage_ != 0 && state_ == AutotuneState::kRunning) {
    stage_ = bin_stage(stage_);  // first: they must be done before the next bin
  } else if (cycle_stage_ != 0) {
    cycle_stage_ = cycle_stage(cycle_stage_);  // ≥ 16 steps to the next cycle's end
  } else if (fd_.fit.stage != 0) {
    fd_.fit.stage = fit_stage(fd_.fit.stage);
  }
  return {duty_q16_, fan_, state_, failure_, event_};
}

void Autotune::bin_end() {
  y_prev2_q8_ = y_prev_q8_;
  y_prev_q8_ = y_bin_q8_;
  y_bin_q8_ = (bin_sum_q8_ + kTicksPerBin / 2) >> 3;  // ÷ kTicksPerBin (8), rounded
  last_bin_duty_q8_ = static_cast<uint16_t>((bin_duty_sum_ + kTicksPerBin / 2) >> 3);
  y_hist_q8_[3] = y_hist_q8_[2];
  y_hist_q8_[2] = y_hist_q8_[1];
  y_hist_q8_[1] = y_hist_q8_[0];
  y_hist_q8_[0] = y_prev_q8_;
  bin_sum_q8_ = 0;
  bin_duty_sum_ = 0;
  bin_ticks_ = 0;
  ++bins_;
  if (phase_ != Phase::kApproach && phase_ != Phase::kRelay) {
    push_bin(0);
  }
  fit_bin();
}

// The probe's response time L̂ outlasts the model history (seed000's higher-order hotends; no
// other bank plant, host rig at σ 0.02–0.5 °C): the one cause of an untrusted model the two-lag
// fit serves. A retried probe or a plateau alone (a noisy FOPDT: fopdt-delay25 at ADC σ 8 LSB)
// keeps the FOPDT model and never spends steps on the fit. (hb as begin_stage computes it.)
bool Autotune::long_response() const {
  return (static_cast<uint32_t>(horizon_ticks_) + kTicksPerBin - 1) / kTicksPerBin + 1 > kRingBins - 2;
}

// ∫u and ∫y from the probe on (before it the heater was off and a cold hotend at ambient: all
// ≈ 0), the same first-order filter (16 bins) over ∫u, y and ∫y, and a sample for the sums from
// the approach and the relay once the last one is done. Filtering every term alike keeps the
// fit's equation exact, and the filtered y's change per bin is ẏ with ~1/8 of the 4-bin slope's
// noise variance (σ 0.5 °C on seed000-4, offline: τ2 122 s for 176 from the 4-bin slope, 195 s
// filtered). A cold start only (a hot one is not at rest). Ranges over at most kFitMaxTicks
// (8,000 bins; the fit is dropped past them): ∫u ≤ 2^21 (Q8 duty × bins), ∫y ≤ 2^26 (°C × 16 ×
// bins; rise < 2^9 °C), each filter state 16 × that: < 2^31.
__attribute__((noinline)) void Autotune::fit_bin() {
  LagFit& f = near(fd_.fit);
  if (hot_start_ || phase_ < Phase::kProbe || phase_ > Phase::kRelay || tick_ > kFitMaxTicks) return;
  // From the probe's baseline: a cold hotend at rest a little off the ambient (given, or within
  // 15 °C) would otherwise add a ramp to ∫y that two lags do not have.
  const int32_t rise = y_bin_q8_ - ambient_q8_ - near(probe_).base_rise_q8;
  f.iu_q8 += last_bin_duty_q8_;
  f.iy_q4 += div2n(rise, 4);
  f.su += f.iu_q8 - div2n(f.su, 4);
  f.siy += f.iy_q4 - div2n(f.siy, 4);
  const int32_t dy_q16 = 16 * rise - f.sy;  // the filtered y's change this bin, °C × 2^16
  f.sy += div2n(dy_q16, 4);
  // Samples only where the fit can be used (fit_solve's condition).
  if (!long_response() || phase_ < Phase::kApproach || f.stage != 0 || rise < 30 * kQ8 || f.samples == 0xFFFF) return;
  f.x[0] = f.su;
  f.x[1] = f.sy;
  f.x[2] = dy_q16;
  f.x[3] = f.siy;
  f.stage = 1;
}

// One piece of the latched sample's products (control/lag_fit.h), on a step with no other piece.
uint8_t Autotune::fit_stage(uint8_t stage) {
  LagFit& f = near(fd_.fit);
  const uint8_t next = lag_fit_accumulate(store_.fit, f.x, stage);
  if (next == 0) ++f.samples;
  return next;
}

// One piece of the fit's solution (control/lag_fit.h): x_q8 becomes K, τ1, τ2.
uint8_t Autotune::fit_solve(uint8_t stage) {
  LagFit& f = near(fd_.fit);
  return lag_fit_solve(store_.fit, static_cast<uint16_t>(kTicksPerBin * period_ms_), f.x, stage);
}

// Stages 1..9 belong to the phase; 20..22 are the probe → approach hand-over in any phase.
uint8_t Autotune::bin_stage(uint8_t stage) {
  if (stage >= 20) return begin_stage(stage);
  switch (phase_) {
    case Phase::kBaseline:
      if (stage == 1) note_decay();
      return baseline_stage(stage);
    case Phase::kCool:
      duty_q16_ = 0;
      note_decay();
      if (y_bin_q8_ < target_q8_ - kHeadroomQ8 - kQ8 && (!hot_start_ || y_bin_q8_ < cool_ref_q8_ - kCoolDropQ8)) {
        cooled_ = true;
        enter(Phase::kBaseline);
      }
      return 0;
    case Phase::kProbe:
      return probe_stage(stage);
    case Phase::kApproach:
      return approach_stage(stage);
    case Phase::kRelay:
      return relay_stage(stage);
    case Phase::kFan:
      fan_stage();
      return 0;
    default:
      return 0;
  }
}

// The first point of a hot start's first cool-down (Autotune::CoolDecay): the bin after the
// first one 1 °C below where it began (the switch-off has reached the reading all through it).
void Autotune::note_decay() {
  CoolDecay& d = fd_.decay;
  if (!hot_start_ || probe_again_ || d.tick_a != 0 || y_prev_q8_ >= cool_ref_q8_ - kQ8) return;
  d.rise_a_q8 = y_bin_q8_ - ambient_q8_;
  d.tick_a = tick_;
}

uint8_t Autotune::baseline_stage(uint8_t stage) {
  if (bins_ < 3) return 0;
  const int32_t rise = y0_q8_ - ambient_q8_;
  if (stage == 1) {
    const int32_t slope = div2n(y_bin_q8_ - y_prev2_q8_, 1);  // per bin
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
      return 0;
    }
    pending_q8_ = slope;
    return 2;
  }
  if (stage == 2) {
    // Decay rate of a hot start: −slope/rise per bin, Q16 (−slope clamped < 2^15: fits).
    probe_.base_rate_q16 = 0;
    const int32_t slope = pending_q8_;
    if (hot_start_ && slope < 0 && rise > 10 * kQ8) {
      probe_.base_rate_q16 = clamp_duty(static_cast<int32_t>(
          capped_ratio_q16(static_cast<uint32_t>(-slope), 32767, static_cast<uint32_t>(rise))));
      // A hot start's first cool-down ends here (CoolDecay): its last point, and the span from
      // the first in whole bins (the stages run a step or two after their bin ended: rounded).
      // At most a few hundred bins: the cool-down is bounded by the timeout.
      CoolDecay& d = fd_.decay;
      if (!probe_again_ && d.tick_a != 0) {
        d.rise_b_q8 = rise;
        d.bins = static_cast<uint16_t>((tick_ - d.tick_a + kTicksPerBin / 2) / kTicksPerBin);
      }
    }
    probe_.base_rise_q8 = rise;
    return 3;
  }
  // First pulse: at most 40 % of the headroom at an assumed 20 °C/s, and 6 s:
  // room·2/5/(20 °C/s) in ms / period; room·2000 ≤ 2^17·2000 < 2^28.
  const int32_t room = target_q8_ - y0_q8_ - 5 * kQ8;
  const uint32_t den = static_cast<uint32_t>(5 * kAssumedSlopeQ8PerS) * period_ms_;
  const uint32_t cap = (static_cast<uint32_t>(room > 0 ? room : 0) * 2000u + den / 2) / den;
  const uint32_t max_cap = t6_;
  probe_.cap_ticks = static_cast<uint16_t>(cap > max_cap ? max_cap : (cap < 1 ? 1 : cap));
  probe_pending_ = true;
  return 0;
}

void Autotune::start_probe() {
  Probe& p = near(probe_);
  enter(Phase::kProbe);
  probe_ticks_ = 0;
  p.on_ticks = 0;
  heater_on_ = true;
  p.extend = false;
  p.detected = false;
  p.peaked = false;
  p.dev_q8 = p.dev_prev_q8 = p.dev_prev2_q8 = 0;
  p.slope_max_q8 = 0;
  p.slope_max_bin = 0;
  p.dev_peak_q8 = INT32_MIN;
  p.slope_rise_q8 = INT32_MIN;  // the smoothed peak until the probe takes the tangent path
  p.area_q8 = 0;
  p.fit_r_q8 = 0;
  p.lag_q4 = 0;
  appr_.lag_q4 = 0;
  scratch_.heat[0].centre = scratch_.heat[1].centre = 0;
  probe_max_q8_ = INT32_MIN;
  duty_q16_ = kFull;
}

// Stage 1 is the probe's bin logic; 2 (tangent) or 3–4 (after the peak) finish its model, then
// the hand-over stages 20–22.
uint8_t Autotune::probe_stage(uint8_t stage) {
  Probe& p = near(probe_);
  if (stage == 2) {
    // Tangent dead time: L = t − rise/S at the steepest point (one division).
    horizon_ticks_ = p.max_centre_tick - p.slope_max_dev_q8 * kTicksPerBin / slope_q8_;
    // Taken before a long sensor lag had filled, the tangent's dead time falls short of the lag
    // the heat-up measured (flight_stage: τ2 20 s read 15.7 bins, the tangent 8.5), and the
    // approach's predictor with it (S + 5..25 °C). Where the measured lag is over 1.5 × the
    // tangent's (the bank's lag-type plants: 0.9–1.2 ×), the approach takes the heat in flight
    // behind it too (stage 6). L̂ stays the tangent's: the relay and compute read it, and on a
    // two-lag hotend (60 / 30 s) the lag, which takes the block for an integrator, reads long.
    // (While the loss is learnt near the target only, the approach takes any measured lag: stage 6.)
    appr_.lag_q4 = int32_t{p.lag_q4} > 3 * horizon_ticks_ ? p.lag_q4 : 0;
    return 6;
  }
  if (stage == 6) {
    lag_fit_stage();
    return 20;
  }
  if (stage == 7) {
    flight_stage();
    return 0;
  }
  if (stage >= 8) return tail_stage(stage);
  const uint16_t k = bins_;  // bin k covers probe ticks (8(k − 1), 8k]
  if (stage == 3) {
    // Loss rate from the decay after the peak: drop / (mid rise · bins), Q16 (drop < 2^15).
    // A sharp peak (its highest reading 3 σ above its bin, as stage 4 tells) from the bin after
    // the peak's: the peak's own bin rounds it off (seed004: 1/T 22 % low from the peak bin over
    // 5 bins, ū 30 % low, and the deadbeat approach landed 25 °C short). A flat one from its bin.
    const bool sharp = sharp_peak();
    if (!sharp) p.max_tick = 0;  // L̂ to the tick only on a sharp peak (stage 4, the hand-over)
    const int32_t from = sharp ? p.y_after_q8 : p.y_peak_q8;
    const int32_t drop = from - y_bin_q8_;
    const int32_t mid_rise = div2n(from + y_bin_q8_, 1) - ambient_q8_;
    uint32_t inv_t = 0;
    // A drop under 1 °C (or 4 σ of a noisy reading: the highest bin is itself lifted by the noise)
    // is noise: loss unknown (learnt during the heat-up).
    if (drop > noise_floor(kQ8, kLossDropSigmaQ4) && mid_rise > kQ8) {
      const uint32_t num = static_cast<uint32_t>(drop > 32767 ? 32767 : drop) << 16;
      const uint32_t den = static_cast<uint32_t>(mid_rise) * static_cast<uint32_t>(k - p.peak_bin - (sharp ? 1 : 0));
      inv_t = (num + den / 2) / den;
    }
    inv_t_q16_ = static_cast<uint16_t>(inv_t > 16384 ? 16384 : inv_t);
    // A cold pulse whose peak fell by 1/16 of its height or more in the window (T under ~4 ×
    // the cut-to-peak time: a dead-time hotend, whose heat-up runs open loop within its dead time)
    // also reads its tail, over the fourth window after the peak (the bin logic below; compute:
    // decay_step). A thermistor lag τ2 behind the block rounds the peak (an FOPDT's is sharp) and
    // slows the early decay, and every C the tune reads takes it for a longer block (≈ τ1 +
    // 2.4 τ2, docs/autotune.md); by then the block's own e^(−t/τ1) is nearly all that is left
    // (24/6/16 s τ1/τ2/D, σ 0.1 °C: 25.3–25.6 s; the third window read 27.2–28.5, the second
    // ~33). Costs three windows (15–20 s). Not where the response showed within 8 bins of the
    // pulse (a dead time that short is no open-loop heat-up; fopdt-60-3's noise passed the 1/16
    // at σ 0.3 °C, and its relay then read D 16 % long), nor on a drop within the noise (no loss
    // read above: fopdt-slow's), nor where the cut-to-peak time outlasts the model history
    // (long_response(): the compute would not read it, after minutes of waiting). A sharp peak
    // too (since 2026-12-08; tail_stage then models the approach): behind a 1 s lag the peak can
    // pass for an FOPDT's on the noise (24/1/20, σ 0.1 °C, one realisation in 8: S 8 % low from
    // it, the deadbeat to S + 10.3 °C); it costs seed002 / seed004 the three windows (simavr
    // 164 → 173 s, 148 → 169 s; the tail's model as good as the sharp peak's there).
    const uint16_t window = static_cast<uint16_t>(k - p.peak_bin);
    if (hot_start_ || p.retries != 0 || untrusted_ || inv_t == 0 || p.det_bin < 8 ||
        drop < p.dev_peak_q8 >> 4 || 4 * window + 1 > kRingBins - 2) {
      return 4;
    }
    p.fit_p_q6 = window;  // the tail's wait and span (bin logic below)
    p.lag_q4 = 0;         // the heat-up's lag is done with; the tail's 1/T from stage 10
    return 0;
  }
  if (stage == 4) {
    // The pulse's peak height above a steady baseline. A sharp peak (fast FOPDT) is the highest
    // reading: the bins round it off by more than 3 σ, and few readings lie near its top to lift
    // it by their noise. A flat one (the highest bin within 3 σ of it; slow hotends: many
    // readings near the top, whose highest is lifted by ~2 σ, and the measured σ reads ~10 %
    // low) is the highest bin (σ/√8). The max is a real reading here (the cut path has readings
    // between the cut and the peak), so the subtraction cannot wrap.
    probe_max_q8_ -= ambient_q8_ + p.base_rise_q8;
    // (Its time, p.max_tick, was kept in stage 3 only where sharp_peak() held: a hot start's or a
    // retry's highest reading is the decaying start, not the peak.)
    if (hot_start_ || p.retries != 0 || p.dev_peak_q8 > probe_max_q8_ - 3 * static_cast<int32_t>(noise_q8_)) {
      probe_max_q8_ = p.dev_peak_q8;
    }
    // S: that height over the pulse (a hot start or a retry: the highest bin, against its own
    // decaying or tail-lifted baseline). The bin alone read seed002's S 3.6 % low, ū as much
    // high: the approach overshot by 3.7 °C at σ 0 and up to 5.2 °C at σ 0.5.
    const int32_t peak = hot_start_ || p.retries != 0 ? p.dev_peak_q8 : probe_max_q8_;
    pending_q8_ = peak * kTicksPerBin / (p.on_ticks > 0 ? p.on_ticks : 1);
    return 5;
  }
  if (stage == 5) {
    appr_.full_bins = 0;
    if (tail_timed()) return 20;  // S, 1/T and L̂ from the tail (stage 13)
    // The loss already acts during the pulse: the peak is S·T·(1 − e^(−x)), x = on/T, not S·on.
    // Undo it with x/(1 − e^(−x)) ≈ 1 + x/2 + x²/12 (x ≤ 2, Q16: x² as (x/16)²/256 < 2^27;
    // ÷12 as ·5461/2^16). Else S is ~10 % low on FOPDT hotends, ū ~10 % high, and the approach
    // overshoots by that share of the rise until the loss is re-learnt.
    const uint32_t factor = pulse_loss_factor_q16(inv_t_q16_);
    const int32_t s = fixed::mul_round(pending_q8_, fixed::Multiplier{factor >> 16, static_cast<uint16_t>(factor)});
    slope_q8_ = s < p.slope_max_q8 ? p.slope_max_q8 : s;
    // Cut-to-peak time (the FOPDT's dead time): the peak is at the centre of the highest bin.
    horizon_ticks_ = (p.max_tick != 0 ? static_cast<int32_t>(p.max_tick) : static_cast<int32_t>(p.peak_bin) * kTicksPerBin - kTicksPerBin / 2) -
                     static_cast<int32_t>(p.off_tick);
    // The peak height (stage 4) for compute's C; 0 when the baseline was not steady (hot start:
    // decaying; a retry: the earlier pulses' tails).
    if (hot_start_ || p.retries != 0) probe_max_q8_ = 0;
    // A flat peak is timed to its highest bin, which the noise picks anywhere on the plateau: an
    // FOPDT of C 300 s read L̂ 12.3 s for 10, the deadbeat landed 1.2–3 °C short and crept to the
    // relay for 40 s. Where the response's rise is the pulse's own ramp (its peak within 9/8 of
    // the steepest slope × the pulse: no lag spreads it; FOPDT hotends read 0.99–1.07 at σ
    // 0.02–0.3 °C, seed002 behind a 2 s thermistor lag 1.17, the bank's lag hotends 1.9–6),
    // the tangent at the steepest point meets the baseline at the pulse's start + D (fopdt-slow:
    // 10.0 s, fopdt-60-3 2.9 s for 3, fopdt-delay25 25.0 s for 25). The slope is > 0 on a cut
    // probe's peak; the height is 0 after a hot start or a retry (no tangent), and an untrusted
    // probe (a plateau taken for the peak) keeps its trend-guarded path. Readings < 2^17 (Q8):
    // 8 × peak < 2^20, the slope < 2^16, a cold pulse's on ticks < 2^13 (< 40 s in all at ≥ 10 ms
    // periods): slope × on × 9/8 < 2^30; dev·8 < 2^20.
    const uint32_t ramp = static_cast<uint32_t>(p.slope_max_q8) * p.on_ticks;
    if (p.max_tick == 0 && !untrusted_ && p.slope_max_q8 > 0 && probe_max_q8_ > 0 &&
        8u * static_cast<uint32_t>(probe_max_q8_) <= ramp + (ramp >> 3)) {
      const int32_t tangent = p.max_centre_tick - p.slope_max_dev_q8 * kTicksPerBin / p.slope_max_q8 -
                              static_cast<int32_t>(p.off_tick - p.on_ticks);
      if (tangent > 0 && tangent < horizon_ticks_) {
        horizon_ticks_ = tangent;
        p.peak_bin = 0;  // tangent_timed(); a cut probe's peak bin is ≥ 1, and nothing reads it after here
      }
    }
    return 20;
  }
  // The baseline the hotend would follow without the probe (decaying when hot).
  p.base_rise_q8 -= fixed::mul_q16(p.base_rise_q8, p.base_rate_q16);
  p.dev_prev2_q8 = p.dev_prev_q8;
  p.dev_prev_q8 = p.dev_q8;
  p.dev_q8 = y_bin_q8_ - ambient_q8_ - p.base_rise_q8;
  if (!p.detected && p.dev_q8 >= noise_floor(kDetectQ8, kDetectSigmaQ4)) {
    p.detected = true;
    p.det_bin = k;
  }
  int32_t slope = 0;
  if (k >= 3) {
    slope = div2n(p.dev_q8 - p.dev_prev2_q8, 1);  // centred on bin k − 1
    if (slope > p.slope_max_q8 + div2n(p.slope_max_q8, 5)) p.slope_max_bin = k;
    if (slope > p.slope_max_q8) {
      p.slope_max_q8 = slope;
      p.slope_max_dev_q8 = p.dev_prev_q8;
      p.max_centre_tick = static_cast<int32_t>(k - 1) * kTicksPerBin - kTicksPerBin / 2;
    }
  }
  // Σ dev over bins 1..k − 2, on after a cut too (the tail model's pulse area, stage 11):
  // ≤ 2^17 per bin over at most a few hundred bins of probe: < 2^26.
  p.area_q8 += p.dev_prev2_q8;
  if (heater_on_) {
    heat_sample(k, slope);
    if (!p.detected) return 0;
    // Still steepening (lags filling up): keep heating past the energy cap while, even at the
    // current slope over a generous horizon (2× the detection time + 4 s), it stays 10 °C
    // below the target. Once the slope is steady, S and the tangent's dead time are known:
    // go on heating under the approach's predictor, without a cut.
    const int32_t horizon = 2 * p.det_bin + 4;
    const bool steepening = k - p.slope_max_bin < 3 || k < p.det_bin + 3;
    const bool safe = y_bin_q8_ + slope * horizon < target_q8_ - 10 * kQ8 && p.on_ticks < t40_;
    // A sensor lag behind a strong heater: the heat in flight would carry the reading near the
    // target even if the heater went off now. Cut now (a cut probe, whose lag rule then
    // approaches on D + τ2), not on into the tangent path, whose dead time falls far short of
    // such a lag (8.8 bins against 24 for τ2 25 s). The heat in flight is the block's rise less
    // the reading's, a·t − y: τ·ẏ once the lag is measured (flight_stage, from the last bin; a
    // quarter added, as the block's own loss bends its heat-up and τ reads up to 20 % short),
    // else at the 20 °C/s the first pulse assumes: while the response still rises as t² the data
    // bound a/τ only, not a (K 1,300 °C, τ1 150 s, τ2 25 s: heated 24 s past the cap, S + 25 °C).
    // 20 × s·256 (< 2^26) < 2^31. Not extended, the pulse ends at the next tick (step(): counted
    // in on_ticks and off_tick as any cut), this bin's duty being out already.
    const int32_t flight = p.lag_q4 != 0 ? (slope * p.lag_q4) >> 4
                                         : (kAssumedSlopeQ8PerS >> 8) * seconds_q8(p.on_ticks) - p.dev_q8;
    if (y_bin_q8_ + flight + div2n(flight, 2) >= target_q8_ - 10 * kQ8) {
      p.extend = false;
      return 0;
    }
    p.extend = steepening && safe;
    if (!p.extend && p.slope_max_q8 > 0 && (p.on_ticks >= p.cap_ticks || !steepening)) {
      p.continuous = true;
      p.extend = true;  // the heater stays on through the hand-over stages
      p.slope_rise_q8 = p.slope_max_dev_q8 + p.base_rise_q8;
      slope_q8_ = p.slope_max_q8;
      inv_t_q16_ = p.base_rate_q16;  // a hot start's decay is the loss rate; cold: learnt at full power
      appr_.full_bins = static_cast<uint8_t>(p.on_ticks / kTicksPerBin > 250 ? 250 : p.on_ticks / kTicksPerBin);
      return 2;
    }
    return 7;
  }
  const uint16_t since_off = static_cast<uint16_t>(probe_ticks_ - p.off_tick);
  if (!p.detected) {
    if (since_off > t60_) {
      // Nothing in a minute: a weaker hotend than assumed (or a dead heater). A 4× longer
      // pulse is safe: the last one raised it by less than 0.5 °C.
      if (++p.retries > 3) {
        // A hot start's baseline decays on, and its extrapolation (the decay rate of 3 bins)
        // drifts from the reading over four minutes of retries: once, a new baseline where it
        // has cooled to (heavy-slow, seed000 from S − 30..S + 20 °C: false "no heating"). Only
        // with the hold's K: without it, seed000's second probe at σ 0.1 read a model that took
        // it to S + 6.8..17.8 °C (docs/autotune.md, "A steady hold").
        if (held_start() && !probe_again_) {
          probe_again_ = true;
          p.retries = 0;
          heater_on_ = false;
          enter(Phase::kBaseline);
          return 0;
        }
        fail(AutotuneFailure::kNoHeating);
        return 0;
      }
      p.cap_ticks = static_cast<uint16_t>(p.cap_ticks * 4);
      p.base_rate_q16 = 0;
      probe_pending_ = true;
      heater_on_ = false;
    }
    return 0;
  }
  if (!p.peaked) {
    // The peak (timing, height) is the highest bin, but it counts as past only once the
    // deviations smoothed 1-2-1 (bin noise × 0.6, each against its own bin's baseline) are 1/8 °C
    // below their own highest: a 1/16 °C drop on one bin (σ 0.07 °C per bin at σ = 0.2 °C
    // readings) passed for seed000-4's peak at 41 s (89–122 s at σ 0.1), a short dead time
    // that made its model trusted (S + 17.5 °C). Sum ≤ 4 · 2^17.
    const int32_t dev_s = div2n(p.dev_prev2_q8 + 2 * p.dev_prev_q8 + p.dev_q8 + 2, 2);
    int32_t& smooth_peak_q8 = p.slope_rise_q8;  // unused on this (the cut) path: no RAM of its own
    if (dev_s > smooth_peak_q8) smooth_peak_q8 = dev_s;
    if (k == p.peak_bin + 1) p.y_after_q8 = y_bin_q8_;  // a sharp peak's decay starts here (stage 3)
    if (p.dev_q8 > p.dev_peak_q8) {
      p.dev_peak_q8 = p.dev_q8;
      p.peak_bin = k;
      p.y_peak_q8 = y_bin_q8_;
    } else if ((k - p.peak_bin >= 2 && dev_s < smooth_peak_q8 - noise_floor(kPeakDropQ8, kPeakDropSigmaQ4)) || since_off > t90_) {
      // (after 90 s: a plateau, a near-integrating or very slow hotend: take the highest, and
      // do not trust the model it gives)
      if (since_off > t90_) untrusted_ = true;
      p.peaked = true;
    }
    return 0;
  }
  // Decay after the peak for a quarter of the cut-to-peak time (≥ 3 bins): the loss rate 1/T
  // (stage 3). The cut path has no lag fit: its three figures hold the window (bins) where stage 3
  // asked for the tail (else 0), and the tail's two rises, no RAM of their own.
  const uint16_t since = static_cast<uint16_t>(k - p.peak_bin);
  const uint16_t window = static_cast<uint16_t>(p.fit_p_q6);  // < 18 bins (stage 3: 4w + 1 < 70)
  if (window == 0) {
    const int32_t peak_tick = static_cast<int32_t>(p.peak_bin) * kTicksPerBin - kTicksPerBin / 2;
    const int32_t quarter = (peak_tick - static_cast<int32_t>(p.off_tick)) >> 5;  // ÷ (4·kTicksPerBin)
    return static_cast<int32_t>(since) < (quarter < 3 ? 3 : quarter) + (sharp_peak() ? 1 : 0) ? 0 : 3;
  }
  // The tail: two bins' sums, one window apart (their centres 3w − ½ and 4w − ½ bins after the peak).
  const uint16_t end_a = static_cast<uint16_t>(3 * window), end_b = static_cast<uint16_t>(end_a + window);
  if (since + 1 == end_a || since == end_a) p.fit_q_q8 = (since == end_a ? p.fit_q_q8 : 0) + p.dev_q8;
  if (since + 1 == end_b || since == end_b) p.fit_r_q8 = (since == end_b ? p.fit_r_q8 : 0) + p.dev_q8;
  if (since < end_b) return 0;
  return since == end_b ? 8 : 13;  // the tail's model (stages 8–12 now, 13 the next bin)
}

// x/(1 − e^(−x)), x = on/T (the pulse over the time constant, 1/T per bin Q16 < 2^15), Q16: a
// pulse of `on` bins at full power raises an FOPDT by S·T·(1 − e^(−x)), not S·on (probe stage 5,
// tail_stage). ≈ 1 + x/2 + x²/12 (x ≤ 2, Q16: x² as (x/16)²/256 < 2^27; ÷12 as ·5461/2^16).
__attribute__((noinline)) uint32_t Autotune::pulse_loss_factor_q16(uint16_t inv_t_q16) const {
  uint32_t x = (uint32_t{probe_.on_ticks} * inv_t_q16) >> 3;  // < 2^16 · 2^15
  if (x > 131072) x = 131072;
  const uint32_t x16 = x >> 4;
  return 65536 + x / 2 + ((((x16 * x16) >> 8) * 5461u) >> 16);
}

// A cold cut probe whose peak (flat or sharp) decays fast (a dead time, maybe behind a thermistor
// lag τ2) read its tail (stage 3, the bin logic): two 2-bin sums a, b one window w apart, where the
// block's own e^(−t/τ1) is nearly all that is left. Its peak's S (the highest bin over the pulse)
// and early 1/T are both blunted by τ2 (seed002 behind a 2 s lag: S 15.9 per bin for 19.2,
// T 38 s for 24; the approach's model put ~120 °C in flight at 35 °C and crawled on the slow law
// for 218 s). The tail gives the FOPDT that its step response tends to, K(1 − e^(−(t − L)/T)):
//   T = w / ln(a/b) (stages 8–10);
//   K·on = ∫ rise dt, the pulse's area, whatever the lags and delay: the bins so far plus the
//     tail's y_c·T beyond the centre of b (stage 11);
//   S = K/T; the undelayed model's peak X = S·on / (x/(1 − e^(−x))) (stages 11–12);
//   L = t_c − T·ln(X/y_c), y_c = b/2 at b's centre t_c after the cut (stage 13), D + τ2
//     to within τ1·ln(τ1/(τ1 − τ2)) − τ2 (24/2/18.7 s: L 20.7 s for 20.8, S and T within 0.2 %
//     in a double-precision check; an FOPDT's L within 0.1 s).
// Taken where 0 < L < the cut-to-peak time; the probe then counts as tangent_timed() (L̂ a dead
// time, not a peak) and tail_timed() (the deadbeat approach, begin_stage). Each stage at most one
// division or logarithm; 8–12 run in the bin the tail ends (with stage 1: 6 steps), 13 in the next
// with 4, 5 and the hand-over (7). The figures live in the cut path's fields that are free by now:
// y_after_q8 (ln, then S), y_peak_q8 (T, bins × 256), slope_rise_q8 (X), lag_q4 (1/T; 0 where the
// model is not taken).
__attribute__((noinline)) uint8_t Autotune::tail_stage(uint8_t stage) {
  Probe& p = near(probe_);
  const uint32_t w = static_cast<uint32_t>(p.fit_p_q6);  // 3..17 bins (stage 3: 4w + 1 ≤ 70)
  if (stage == 8) {
    if (!tail_fell()) return 4;
    // a/b in (8/7, 4] (tail_fell): ln in Q16 within 8,750..90,852.
    p.y_after_q8 = fixed_math::ln_ratio_q16(static_cast<uint32_t>(p.fit_q_q8), static_cast<uint32_t>(p.fit_r_q8));
    return 9;
  }
  const uint32_t ln = static_cast<uint32_t>(p.y_after_q8);
  if (stage == 9) {
    p.y_peak_q8 = static_cast<int32_t>(((w << 24) + ln / 2) / ln);  // T ≤ 17/0.1335 bins: < 2^15 (Q8)
    return 10;
  }
  if (stage == 10) {
    p.lag_q4 = static_cast<uint16_t>((ln + w / 2) / w);  // 1/T per bin, Q16 < 2^15 (w ≥ 3)
    return 11;
  }
  if (stage == 11) {
    // The pulse's area in °C × 256 × bins: bins 1..end_b − 1 (area_q8 is two bins behind the one
    // just done, dev_prev_q8 the last of them) and y_c·T = (b/2)·(T_q8/256) beyond the centre of
    // b, which is the boundary of its two bins (b < 2^18, T_q8 < 2^15: each term < 2^26). Over
    // T: S·on (°C × 256, < 2^26), kept for stage 12; S = S·on / on per bin (S·on·8 < 2^29).
    const int32_t total = p.area_q8 + p.dev_prev_q8 + (fixed::mul_q16(p.fit_r_q8, static_cast<uint16_t>(p.y_peak_q8)) << 7);
    const int32_t lossless = total > 0 ? fixed::mul_q16(total, p.lag_q4) : 0;
    const uint32_t on = p.on_ticks > 0 ? p.on_ticks : 1;
    p.slope_rise_q8 = lossless;
    p.y_after_q8 = static_cast<int32_t>((static_cast<uint32_t>(lossless) * kTicksPerBin + on / 2) / on);
    return 12;
  }
  if (stage == 12) {
    p.slope_rise_q8 = static_cast<int32_t>(div_q16(static_cast<uint32_t>(p.slope_rise_q8), pulse_loss_factor_q16(p.lag_q4)));
    return 0;
  }
  // Stage 13. L = t_c − T·ln(X/y_c) in probe ticks: t_c is the boundary of b's bins (end_b − 1
  // and end_b, their readings' mean half a tick after it: rounded up), T·ln = T_q8·ln_q16/2^21
  // (ln < 16 as Q12: T_q8 · ln_q12 < 2^15 · 2^16; no X/y_c that large reaches here).
  const uint16_t end_b = static_cast<uint16_t>(p.peak_bin + 4 * w);
  const int32_t t_c = static_cast<int32_t>(end_b) * kTicksPerBin - (kTicksPerBin - 1) - static_cast<int32_t>(p.off_tick);
  const int32_t peak_t = static_cast<int32_t>(p.peak_bin) * kTicksPerBin - kTicksPerBin / 2 - static_cast<int32_t>(p.off_tick);
  const int32_t x2 = 2 * p.slope_rise_q8;
  int32_t l = 0;
  if (x2 > p.fit_r_q8 && p.fit_r_q8 > 0) {
    const uint32_t ln_q12 = static_cast<uint32_t>(fixed_math::ln_ratio_q16(static_cast<uint32_t>(x2), static_cast<uint32_t>(p.fit_r_q8))) >> 4;
    l = ln_q12 < 65536 ? t_c - static_cast<int32_t>((static_cast<uint32_t>(p.y_peak_q8) * ln_q12) >> 17) : 0;
  }
  if (l > 0 && l < peak_t && p.y_after_q8 > 0) {
    slope_q8_ = p.y_after_q8 < p.slope_max_q8 ? p.slope_max_q8 : (p.y_after_q8 > 32767 ? 32767 : p.y_after_q8);
    inv_t_q16_ = p.lag_q4 > 16384 ? 16384 : p.lag_q4;  // the probe's and the approach's clamp
    horizon_ticks_ = l;
    p.peak_bin = 0;  // tangent_timed(), tail_timed()
    p.max_tick = 0;
    p.y_after_q8 = peak_t - l;  // the peak's lateness against L (ticks): a lag's sign
  } else {
    p.lag_q4 = 0;
  }
  return 4;
}

// The heat-up's samples for the lag fit: at bin centres 2, 4, 8, 16, … the last two (no division).
// Bin k's slope is centred on bin k − 1, whose integral is Σ dev over the bins before it + half its own.
__attribute__((noinline)) void Autotune::heat_sample(uint16_t k, int32_t slope) {
  const uint16_t c = static_cast<uint16_t>(k - 1);
  if (k < 3 || c > 255 || (c & (c - 1)) != 0) return;
  const Probe& p = near(probe_);
  scratch_.heat[0] = scratch_.heat[1];
  scratch_.heat[1] = {p.dev_prev_q8, slope, p.area_q8 + div2n(p.dev_prev_q8, 1), static_cast<uint8_t>(c)};
}

// The heat-up sample the two stages below pair with bin `ca`'s centre: the later power-of-two
// one (heat_sample keeps two) while it lies at most 2/3 of the way there, else the earlier.
const Autotune::HeatSample& Autotune::earlier_heat(uint16_t ca) const {
  return 3u * scratch_.heat[1].centre <= 2u * ca ? scratch_.heat[1] : scratch_.heat[0];
}

// Two lags τ1, τ2 heated at full power from a steady baseline obey K − y = Σ·ẏ + Π·ÿ (Σ = τ1 + τ2,
// Π = τ1·τ2), and integrated from the pulse's start, K·t − ∫y = Σ·y + Π·ẏ. The tangent's
// (K − y)/ẏ is Σ + Π·ÿ/ẏ: too long before the inflection, where the probe hands over (seed003:
// 48 s against 42.5), and the fan step's ẏ/S reads the fan loss as long. Two samples, a (this
// bin's centre) and b (an earlier power-of-two one, at most 2/3 of the way), eliminate Π: with
// r = ẏ_b/ẏ_a, Σ = (K·(r·t_a − t_b) − (r·∫_a − ∫_b)) / (r·y_a − y_b), K from the relay (compute:
// lag_sigma). t at bin centres: the bin's readings end its ticks, its mean sits half a bin before
// its end, with ∫ to there by the same bin means (within 0.5 % noise-free on seed003, hotend40w,
// light-fast and hotend80w; the heat-up's time origin, the pulse's first tick, is exact here).
// One division; 0 < r < 1 (the slope still rising), t_a < 64 bins (≤ 40 s at full power).
__attribute__((noinline)) void Autotune::lag_fit_stage() {
  Probe& p = near(probe_);
  p.fit_r_q8 = 0;
  const uint16_t ca = static_cast<uint16_t>(bins_ - 1);
  const HeatSample& b = earlier_heat(ca);
  const int32_t slope_a = div2n(p.dev_q8 - p.dev_prev2_q8, 1);
  if (ca > 63 || b.centre < 2 || b.slope_q8 <= 0 || b.slope_q8 >= slope_a) return;
  const uint16_t r = static_cast<uint16_t>(capped_ratio_q16(static_cast<uint32_t>(b.slope_q8), 65535, static_cast<uint32_t>(slope_a)));
  // mul_q16 takes any int32 (the areas < 2^23, the rises < 2^17, t < 2^12).
  p.fit_p_q6 = fixed::mul_q16(int32_t{ca} * 64 - 32, r) - (int32_t{b.centre} * 64 - 32);
  p.fit_q_q8 = fixed::mul_q16(p.area_q8 + div2n(p.dev_prev_q8, 1), r) - b.area_q8;
  const int32_t den = fixed::mul_q16(p.dev_prev_q8, r) - b.dev_q8;
  // A denominator under 1/8 of the rise: the two samples say too little apart (noise).
  if (p.fit_p_q6 > 0 && 8 * den > p.dev_prev_q8) p.fit_r_q8 = den;
}

// The sensor's lag while the probe heats on (for its next bin's heat in flight): at full power
// from rest an integrating block read through a first-order sensor lag τ obeys y + τ·ẏ = a·t (a
// dead time D reads as τ + D), so two heat-up points (this bin's centre and an earlier
// power-of-two one, as lag_fit_stage takes them) give τ = (y_a·t_b − y_b·t_a)/(ẏ_b·t_a − ẏ_a·t_b),
// and the heat in flight is τ·ẏ (block loss only lowers it). t in half bins (< 2^9), rises
// < 2^17, slopes < 2^15: num < 2^26, den < 2^25, 16·num < 2^30; τ capped at 255 bins (× ẏ < 2^27).
// A bin that fails the test below keeps the last estimate (the 20 °C/s bound serves only before
// the first).
// Envelope hotends (autotune_fuzz): K 1,284 °C, τ1 88 s, τ2 18 s, D 1 s read τ 17–20 bins.
__attribute__((noinline)) void Autotune::flight_stage() {
  Probe& p = near(probe_);
  const uint16_t ca = static_cast<uint16_t>(bins_ - 1);
  const HeatSample& b = earlier_heat(ca);
  const int32_t slope_a = div2n(p.dev_q8 - p.dev_prev2_q8, 1);
  if (ca > 255 || b.centre < 2 || b.slope_q8 <= 0 || slope_a <= 0) return;
  const int32_t ta = 2 * static_cast<int32_t>(ca) - 1;
  const int32_t tb = 2 * static_cast<int32_t>(b.centre) - 1;
  const int32_t num = p.dev_prev_q8 * tb - b.dev_q8 * ta;
  const int32_t den = b.slope_q8 * ta - slope_a * tb;
  // Early on (the slope still nearly ∝ t) den is a small difference of large terms: its noise
  // read a 4 s lag as 4,679 bins and cut a 3.5 °C/s hotend's pulse (tune 180 → 489 s). Only
  // where the slope has visibly levelled off: den ≥ ẏ_b·t_a/16 (< 2^24; the 18 s lag above reads
  // ≥ 1/10 of it from 12 s on).
  if (num <= 0 || 16 * den < b.slope_q8 * ta) return;
  const int32_t tau_q4 = 16 * num / den;
  p.lag_q4 = static_cast<uint16_t>(tau_q4 > 4080 ? 4080 : (tau_q4 < 1 ? 1 : tau_q4));
}

// The model's history restarts from the reading now, x(now − L̂) = rise, with the last `on` of
// the L̂ bins at full power and the present loss 1/T: model_anchor writes entry j as it is first
// read. Returns (1 − 1/T)^hb (Q16, 65536 without loss), the power by squaring (≤ 12 multiplies;
// every product ≤ 2^16 · 65535 < 2^32).
uint32_t Autotune::seed_history(uint8_t on, uint16_t a_q16) {
  Approach& ap = near(appr_);
  uint32_t p = 65536;
  uint16_t base = static_cast<uint16_t>(65536u - a_q16);  // a ≥ 1 here, or unused
  for (uint8_t n = a_q16 != 0 ? horizon_bins_ : 0; n != 0; n >>= 1) {
    if (n & 1) p = (p * base + 0x8000u) >> 16;
    base = static_cast<uint16_t>((uint32_t{base} * base + 0x8000u) >> 16);
  }
  offset_q8_ = 0;
  ap.fill_x_q8 = y_bin_q8_ - ambient_q8_;
  ap.fill_j = horizon_bins_;
  ap.fill_on = on;
  ap.fill_a_q16 = a_q16;
  ap.fill_head = ring_head_;
  return p;
}

// Probe → approach hand-over, from S (slope_q8_), L̂ (horizon_ticks_), 1/T (inv_t_q16_) and the
// bins at full power just before (appr_.full_bins): 20 the gain, 21 the steady duty, 22 the model.
uint8_t Autotune::begin_stage(uint8_t stage) {
  Approach& ap = near(appr_);
  if (stage == 20) {
    ap.blunted = false;
    // After a hold, S/(1/T) must come out as the hold's K. A hot start's short pulse reads S low
    // behind a sensor lag (seed003 from 110 °C: S 1,189 against ≈ 2,070; two-node-80W from
    // S − 10: 684 against 1,256) while its decay gives 1/T within ~10 %: S = K/T where that is
    // steeper (never lowered: a low S errs towards overshoot), and over 1.5 × steeper is a
    // missed lag, as stage 4 finds at full power: the trend guard. K in Q8 < 2^20, × 1/T (≤ 2^14,
    // Q16) / 2^16 < 2^18 (mul_q16: exact, no 64-bit product).
    if (held_start()) {
      const int32_t s_held = fixed::mul_q16(int32_t{hold_gain_q4_} << 4, inv_t_q16_);
      if (s_held > slope_q8_) {
        if (2 * s_held > 3 * slope_q8_) ap.blunted = true;
        slope_q8_ = s_held > 32767 ? 32767 : s_held;
      }
    }
    if (slope_q8_ < 8) slope_q8_ = 8;
    if (horizon_ticks_ < kTicksPerBin) horizon_ticks_ = kTicksPerBin;
    const uint32_t hb = (static_cast<uint32_t>(horizon_ticks_) + kTicksPerBin - 1) / kTicksPerBin + 1;
    horizon_bins_ = static_cast<uint8_t>(hb > kRingBins - 2 ? kRingBins - 2 : hb);
    if (long_response()) untrusted_ = true;  // the response outlasts the model's history
    // A probe that needed a longer pulse (nothing in a minute after the first) is a slow or weak
    // hotend whose peak is small against the noise: at σ 0.5 a noise dip passed for seed000-4's
    // peak 22 s after the retry's cut (against ~250 s), and its predictor heated to S + 24 °C.
    // An untrusted model's L̂ (this, a plateau taken for the peak, or one past the history) is
    // no measure of the trend guard's horizon either: the longest.
    if (near(probe_).retries != 0 && !hot_start_) untrusted_ = true;
    guard_bins_ = static_cast<uint8_t>(horizon_bins_ > 62 || untrusted_ ? 132 : 2 * horizon_bins_ + 8);
    // A cold cut probe whose flat peak comes over 1.5 × later after the cut than its response
    // showed after the pulse began: a dead time D delays both alike, a sensor lag τ2 shows at once
    // but peaks late (two lags τ1 ≫ τ2 at 2–3 τ2: compute's lag rule, τ2 = peak/2.5). So D ≈ the
    // detection time and τ2 ≈ (L̂ − D)/2.5, and at a steady heating rate the heat in flight is
    // rate × (D + τ2), not rate × L̂: the approach runs on D + τ2 = (2L̂ + 3D)/5 (its gain, loss
    // learning and hand-over) and takes 2/5 of the L̂ model's heat in flight plus 3/5 of the last
    // D's (step 6). On L̂ the predictor over-predicted it: heavy-slow's full power (D 5 s, L̂ 66 s)
    // cut 80 °C short and its P law crawled (approach 1,038 s); two-node-delay5's (7 s, 22 s) P
    // law crawled the last 10 °C. The relay, the time limits and compute keep L̂. Not on a noisy
    // sensor (measured σ above 0.35 °C, kLagRuleNoiseQ8): at σ 0.5 °C a loss learnt at full power
    // a third high carried the faster P law to S + 6..7.6 °C (heavy-slow, two-node-delay5), 1–2 °C
    // before. Up to σ 0.3 it is needed: at σ 0.15–0.3 on L̂ a lag-type hotend's P law parked up to
    // S + 16 °C (issue 7's envelope, autotune_fuzz: 17 of 600 sampled hotends, all within
    // S + 2.3 °C after; heavy-slow at σ 0.2 tuned in 1,061 s instead of 1,599).
    const uint16_t det_bin = near(probe_).det_bin;
    // (Not a tail-timed probe: its L̂ is the tail's dead time, lag included, not a late peak; and
    // its landing keeps its figures in det_bins and det_flight_q8.)
    ap.lag_probe = !tail_timed() && !probe_.continuous && !hot_start_ && probe_.retries == 0 && probe_.max_tick == 0 &&
                   noise_q8_ <= kLagRuleNoiseQ8 && 2 * horizon_ticks_ > 3 * kTicksPerBin * static_cast<int32_t>(det_bin);
    ap.det_bins = static_cast<uint8_t>(det_bin < horizon_bins_ ? det_bin + 1 : horizon_bins_);
    // ÷5 (rounded up) as ·13108/2^16, exact for numerators < 2^14 (here ≤ 354; a division costs ~200
    // cycles).
    ap.bins = ap.lag_probe ? static_cast<uint8_t>(((2u * horizon_bins_ + 3u * ap.det_bins + 4u) * uint32_t{13108}) >> 16) : horizon_bins_;
    extend_timeout();
    set_approach_gain();
    return 21;
  }
  if (stage == 21) {
    // ū = loss at the target / S (0 while the loss is unknown: learnt during the heat-up).
    ap.steady_q16 = steady_from_model();
    return 22;
  }
  // The model's history over the last L̂ bins: the undelayed state whose delayed copy is the
  // reading now, x(now − L̂) = rise, run forward with the duty of those bins (full power for the
  // last `on`, else off) and the loss. model_bin writes entry j as it is first read; the state
  // now is closed-form: rise + S·on without loss (the tangent probe), rise·(1 − 1/T)^L̂ with it
  // (the cut probe, on = 0), the power by squaring (≤ 12 16×16 multiplies).
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  const uint8_t on = ap.full_bins < horizon_bins_ ? ap.full_bins : horizon_bins_;
  const uint32_t p = seed_history(on, inv_t_q16_);
  model_q8_ = (p >= 65536 ? rise : fixed::mul_q16(rise, static_cast<uint16_t>(p))) + slope_q8_ * on;
  ap.ref_rise_q8 = rise;
  ap.ref_slope_q8 = 0;
  ap.loss_estimates = 0;
  // A trusted cold tangent probe's loss is unknown (ū = 0; a hot start's comes from its decay)
  // until learnt at full power (stage 4) or, where the heat-up is too short for that (seed003:
  // 128 °C at the hand-over, 82 °C below the target), near the target (stage 3).
  ap.near_only = probe_.continuous && !untrusted_ && inv_t_q16_ == 0;
  ap.full_bins = on;
  ap.duty_avg_q16 = 0;
  ap.settled_bins = 0;
  ap.near_bins = 0;
  // The deadbeat needs a model to trust: a cold cut probe with a sharp (FOPDT-like) peak, or one
  // whose tail gave its FOPDT (tail_stage), and a loss rate (ū = 0 would hold nothing once
  // landed). Not on a flat peak otherwise, even one timed like an
  // FOPDT's (cut-to-peak within 1.25 × pulse-to-response: fopdt-120-25's relay started 150 s
  // sooner): a light 80 W block behind a 20 s transport delay peaks flat with that timing, and
  // the deadbeat landed it at S + 3.6 °C with the relay biased above its steady duty: S + 25 °C
  // (aborted) in 6 of 9 host runs at σ 0.1–0.5 (test: FlatPeakBehindATransportDelay...).
  const bool fopdt_like = probe_.max_tick != 0 || tail_timed();
  // A cold cut probe whose decay was too slow to show the loss (1/T = 0): the same full-power
  // law on a model without loss, which over-predicts the rise and so lands short, then the slow
  // law (its P law around ū = 0 held fopdt-120-25 60 °C short for 90 s, until the loss was learnt).
  // Both only after a cold start's single cut pulse: a retried one keeps its first pulse's max_tick.
  const bool cold_cut = !probe_.continuous && !hot_start_ && probe_.retries == 0;
  const bool no_loss = inv_t_q16_ == 0 && noise_q8_ <= kQuietNoiseQ8;
  ap.landed = untrusted_ || !cold_cut || !(fopdt_like || no_loss) ? 2 : 0;
  enter(Phase::kApproach);
  duty_q16_ = heater_on_ ? kFull : 0;
  heater_on_ = false;
  return 0;
}

// A fixed limit is wrong for a hotend whose heat-up alone takes 25 min (seed000): once the
// probe has measured the response time L̂, the limit becomes the larger of the configured one and
// now + (cycles in total + 4) × 6 L̂ (a relay cycle takes ≈ 4 L̂ on a dead-time hotend, the
// approach a few L̂), but never more than 4 × the configured limit, so a stuck tune still ends.
// L̂ < 2^16 ticks × 6 × ≤ 31 < 2^24; 4 × limit < 2^32 for limits < 2^30 ticks.
void Autotune::extend_timeout() {
  const uint32_t l_ticks = horizon_ticks_ > 0xFFFF ? 0xFFFFu : static_cast<uint32_t>(horizon_ticks_);
  const uint32_t cycles = uint32_t{cycles_} + (measure_fan_ ? 2u : 0u) + 4u;
  const uint32_t span = tick_ + cycles * 6u * l_ticks;
  const uint32_t ceiling = timeout_ticks_ < (uint32_t{1} << 30) ? 4u * timeout_ticks_ : timeout_ticks_;
  if (span > timeout_ticks_) timeout_ticks_ = span < ceiling ? span : ceiling;
  // Likewise a relay half-cycle may last 12 L̂ before the relay counts as stuck (600 s at least:
  // seed000-4's fan half-cycle outlasted 600 s, and 8 L̂ = 975 s once its L̂ was 122 s).
  const uint32_t half = 12u * l_ticks;
  if (half > t600_) t600_ = static_cast<uint16_t>(clamp_half_ticks(half));
}

// Approach: closed-loop time constant = 1.25 × its response time (≥ 3 bins); P gain 1/(S·τ). One
// division: S ≤ 2^15 (clamped where it is learnt) × τ ≤ 87 < 2^22.
uint8_t Autotune::approach_tau() const {
  const uint8_t hb = appr_.bins;
  return static_cast<uint8_t>(hb < 3 ? 3 : hb + hb / 4);
}

void Autotune::set_approach_gain() {
  const uint8_t tau = approach_tau();
  const uint32_t g = (uint32_t{1} << 24) / (static_cast<uint32_t>(slope_q8_) * tau);
  appr_.gain_q8 = static_cast<int32_t>(g > 40000 ? 40000 : g);
}

// Untrusted model: the reading a bin ahead by its 4-bin trend over guard_bins_ (rising only).
// The slope less a dead band, kTrendNoiseQ8 or 2σ/16 of the measured reading noise: σ = 0.2 °C
// readings give the 4-bin slope σ ≈ 6 (Q8 per bin), × 132 bins ≈ ±3 °C of trend, which held
// seed000-5's approach short of the target until the time limit. |s4| < 2^15 per bin, × ≤ 132.
int32_t Autotune::trend_q8(uint8_t sigma_q4) const {
  const int32_t s4 = slope4_q8() - noise_floor(kTrendNoiseQ8, sigma_q4);
  return s4 > 0 ? y_bin_q8_ + s4 * guard_bins_ : y_bin_q8_;
}

// The reading noise from the mean |second difference| of successive readings (σ·√6·√(2/π) =
// 1.954 σ for Gaussian noise; a drift or a smooth heat-up hardly moves it at 128 ms): σ =
// Σ / (1.954 n) ≈ Σ · 131 / 2^(10 + log2 n), at n = 16, 32 and 64 readings, then the sum is
// halved so the estimate keeps following over the last 32–64. Each term is capped at 2 °C (the
// kink where a dead-time hotend's response starts is one such term), which reads σ 0.5 °C 9 %
// low (the factors below were chosen with it): Σ ≤ 64 · 512 < 2^16.
// The first two readings after start() have no two predecessors yet: skipped.
__attribute__((noinline)) void Autotune::measure_noise(int32_t y) {
  if (tick_ < 3) return;
  const int32_t d2 = y - 2 * yf_ring_[(yf_head_ + 3) & 3] + yf_ring_[(yf_head_ + 2) & 3];
  noise_sum_ = static_cast<uint16_t>(noise_sum_ + (abs32(d2) > 2 * kQ8 ? 2 * kQ8 : abs32(d2)));
  ++noise_n_;
  const uint8_t shift = noise_n_ == 16 ? 14 : (noise_n_ == 32 ? 15 : (noise_n_ == 64 ? 16 : 0));
  if (shift == 0) return;
  noise_q8_ = static_cast<uint16_t>((uint32_t{noise_sum_} * 131u * 4u) >> shift);  // < 2^24
  if (noise_n_ == 64) {
    noise_sum_ >>= 1;
    noise_n_ = 32;
  }
}

// A threshold that is `fixed_q8` on a quiet sensor and sigma_q4/16 × the reading noise on a
// noisy one (σ ≤ 262 with the 2 °C cap, × < 2^8: < 2^17).
__attribute__((noinline)) int32_t Autotune::noise_floor(int32_t fixed_q8, uint8_t sigma_q4) const {
  const int32_t scaled = static_cast<int32_t>((uint32_t{noise_q8_} * sigma_q4) >> 4);
  return scaled > fixed_q8 ? scaled : fixed_q8;
}

// One 32-bit division: loss ≤ 2^14 (°C/bin × 256, clamped), × 2^16 < 2^31.
int32_t Autotune::steady_from_model() const {
  // A hot start after a steady hold: ū = (S − ambient)/K from the hold's K, not loss/S from a
  // probe that read S and 1/T off a decaying baseline (two-node-80W from S − 10: ū 0.30 against
  // 0.157, S + 6.0..6.8 °C; docs/autotune.md, "A steady hold"). The rise (≤ 250 °C: < 2^16 in Q8,
  // capped there) × 2^16 < 2^32; K ≥ 1 in Q4, × 16 in Q8.
  if (held_start() && target_q8_ > ambient_q8_) {
    const uint32_t u = capped_ratio_q16(static_cast<uint32_t>(target_q8_ - ambient_q8_), 65535, uint32_t{hold_gain_q4_} << 4);
    return static_cast<int32_t>(u > kFull ? kFull : u);
  }
  const uint32_t loss = static_cast<uint32_t>(fixed::mul_q16(target_q8_ - ambient_q8_, inv_t_q16_));
  const uint32_t u = capped_ratio_q16(loss, 16383, static_cast<uint32_t>(slope_q8_));
  return static_cast<int32_t>(u > kFull ? kFull : u);
}

// Every bin of the approach and the relay (their stage 1): the Smith predictor's model (a mul_q16
// and a 32×16 multiply, no division); model_anchor (stage 2) anchors it to the reading.
void Autotune::model_bin() {
  Approach& ap = near(appr_);
  // Smith predictor: model x' = S·u − x/T (undelayed); prediction = reading + x(now) − x(now − L̂),
  // the heat in flight. The model is anchored to the reading (its delayed state pulled towards
  // it, a quarter per bin, by shifting the whole history through offset_q8_), so its loss term
  // works on the real temperature.
  model_q8_ += heat_q8(last_bin_duty_q8_) -
               fixed::mul_q16(model_q8_, inv_t_q16_);
  model_q8_ = fixed::clamp(model_q8_, int32_t{-30000} * 16, int32_t{30000} * 16);
  push_bin(ring_entry(model_q8_ - offset_q8_));
  // Bins the duty has stayed within ±8 % of where this stretch began.
  if (abs32(static_cast<int32_t>(last_bin_duty_q8_) - ap.steady_ref) < 20) {
    if (ap.steady_bins < 250) ++ap.steady_bins;
  } else {
    ap.steady_ref = static_cast<int16_t>(last_bin_duty_q8_);
    ap.steady_bins = 0;
  }
}

// After a tail-timed probe's deadbeat, until its full-power ramp has passed through the reading
// (approach stage 6): neither the anchor nor the predictor follows the reading.
__attribute__((noinline)) bool Autotune::ramp_in_reading() const {
  return phase_ == Phase::kApproach && appr_.landed == 4 && tail_timed() && bins_ < appr_.det_bins;
}

// The stage after model_bin: the pre-approach history entry about to be read, and the anchor.
// One mul_q16.
void Autotune::model_anchor() {
  Approach& ap = near(appr_);
  // The pre-approach history entries read below (model_delayed: up to 2 bins short of the
  // whole-bin horizon), one recursion step per bin, 3 in the first to be that far ahead.
  for (uint8_t n = ap.fill_j == horizon_bins_ ? 3 : 1; n != 0 && ap.fill_j > 0; --n) {
    --ap.fill_j;
    ap.fill_x_q8 += (ap.fill_j < ap.fill_on ? slope_q8_ : 0) - fixed::mul_q16(ap.fill_x_q8, ap.fill_a_q16);
    ring_[wrap_ring(static_cast<uint8_t>(ap.fill_head + kRingBins - 1 - ap.fill_j))] = ring_entry(ap.fill_x_q8);
  }
  const int32_t err = y_bin_q8_ - ambient_q8_ - model_delayed();
  // A tail-timed probe's landing (approach stage 6 of the last bin; no lag probe: det_bins and
  // det_flight_q8 are free): the reading's offset from the model now, held until the ramp has
  // passed through the reading: L̂ + 3 bins on, and 4 × the peak's lateness against L more (its
  // ticks / 2, as bins: measured; at 1 × or ½ × the hold failed into the relay on up to 3 of 8
  // more realisations of 24/2/18.7, 24/2/20 and 30/3/25, and max − S rose to 1.4–2.6 °C).
  int32_t anchor = div2n(err, 2);
  if (ap.landed == 4 && tail_timed()) {
    if (ap.det_bins == 0) {
      const uint16_t end = static_cast<uint16_t>(bins_ + horizon_bins_ + 3 + (probe_.y_after_q8 >> 1));
      ap.det_bins = static_cast<uint8_t>(end > 255 ? 255 : end);
      ap.det_flight_q8 = err + ambient_q8_;
    }
    if (ramp_in_reading()) anchor = 0;
  }
  offset_q8_ += anchor;
  model_q8_ += anchor;
  // An untrusted model's relay: heater off while the trend would carry the reading
  // past target + 2 °C.
  guard_off_ = untrusted_ && trend_q8(kGuardSigmaQ4) > target_q8_ + kGuardMarginQ8;
}

// Stage 4's (and 10's) S re-learnt at full power: taken once 1/16 steeper (1/32 after a lag-type
// probe); the next stage, 8 (the gain for the new S) or 5.
uint8_t Autotune::relearn_slope(int32_t s_full) {
  Approach& ap = near(appr_);
  if (s_full <= slope_q8_ + div2n(slope_q8_, ap.lag_probe ? 5 : 4)) return 5;
  // A hot start's pulse (short: little room below the target) that peaked at under ⅔ of
  // this rate was blunted by a sensor lag, whose heat in flight the model, built on the
  // pulse's short cut-to-peak time, leaves out: seed003 (lags 28 and 14 s) from 110–160 °C
  // overshot to S + 7.2..15.3 °C (its pulses read 1.9–4.8 × low). The reading's own trend
  // then bounds the approach, as on an untrusted model (stage 6): S + 0.6..2.7 °C. It costs
  // the two-node hotends, which re-learn 1.3–2.3 × from a hot start and stayed within
  // S + 1.6 °C without it, 50–200 s (hotend40w 200 → 240 °C: 241 → 294 s); at 3 × they were
  // spared but seed003 from 120–135 °C still went to S + 10..13 °C.
  if (hot_start_ && 2 * s_full > 3 * slope_q8_) ap.blunted = true;
  slope_q8_ = s_full;
  return 8;
}

uint8_t Autotune::approach_stage(uint8_t stage) {
  Approach& ap = near(appr_);
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  switch (stage) {
    case 1:
      model_bin();
      // A lag probe's heat in flight over the last D, for step 6 (here: the shortest step). Used
      // once the last D bins are the approach's own: the history before it is filled lazily,
      // oldest first (model_anchor), so its recent entries are not there yet.
      if (ap.lag_probe) ap.det_flight_q8 = fixed::mul_q16(model_ago(0) - model_ago(ap.det_bins), 39322);
      return 2;
    case 2:
      model_anchor();
      return 3;
    case 3: {
      // Loss learning near the target, where the heater is not at full power: the model's slope
      // S·u(t − L̂) − x/T against the reading's 4-bin slope; the error moves 1/T by ⅛ per bin (¼
      // while near_only). This keeps the model's steady state on the real one, so the predictor
      // holds the target exactly. Only while the duty has been steady (within 8 %, ū's own
      // changes aside while near_only: case 5) over L̂ + 6 bins: in transients a dead time that is
      // off by a bin would pass for a loss error.
      const uint8_t hb = ap.bins;
      ap.unlearnt = ap.steady_bins < hb + 6;
      if (ap.full_bins == 0 && rise > 20 * kQ8 && !ap.unlearnt) {
        const int32_t s4 = slope4_q8();
        const int32_t centre = rise - 2 * s4;
        const int32_t model_slope = heat_q8(duty_ago(hb + 2)) -
                                    fixed::mul_q16(centre, inv_t_q16_);
        const int32_t err = model_slope - s4;  // > 0: more loss than the model has
        // ⅛ of the error per bin, ¼ where the loss is learnt near the target only (near_only): its
        // P law around ū = 0 stalls far short (seed003: 36 °C) and waits on this.
        // |err| ≤ 2^18 (clamped) × 2^14 < 2^32; centre > 20 °C (5,120 in Q8) keeps the quotient
        // < 2^20, and 32 × step < 2^25.
        const uint32_t rate = ap.near_only ? 16384u : 8192u;
        const int32_t step = static_cast<int32_t>(static_cast<uint32_t>(abs32(err) > 262143 ? 262143 : abs32(err)) * rate / static_cast<uint32_t>(centre));
        if (32 * step > inv_t_q16_) ap.unlearnt = true;
        inv_t_q16_ = static_cast<uint16_t>(fixed::clamp(static_cast<int32_t>(inv_t_q16_) + (err > 0 ? step : -step), int32_t{0}, int32_t{16384}));
      }
      return 4;
    }
    case 4:
      // Loss learning while at full power (the slope falls as the loss grows): 1/T = Δslope/Δrise
      // between a reference 4-bin slope taken once the heat-up runs at full power and the latest,
      // over at least 40 °C (the same estimator at both ends: no bias from taking a maximum).
      ap.full_bins = last_bin_duty_q8_ >= 255 ? static_cast<uint8_t>(ap.full_bins < 250 ? ap.full_bins + 1 : 250) : 0;
      if (ap.full_bins > horizon_bins_ + 4) {
        const int32_t s4 = slope4_q8();
        const int32_t at = rise - 2 * s4;  // rise at the window's centre
        if (ap.ref_slope_q8 == 0) {
          ap.ref_slope_q8 = s4 > 0 ? s4 : 1;
          ap.ref_rise_q8 = at;
        } else if (at - ap.ref_rise_q8 > 40 * kQ8 && s4 < ap.ref_slope_q8) {
          // ref_slope − s4 ≤ a full-power slope per bin (< 2^15 for < 128 °C/s) × 2^16 < 2^31.
          const uint32_t ds = static_cast<uint32_t>(ap.ref_slope_q8 - s4);
          uint32_t inv_t = capped_ratio_q16(ds, 32767, static_cast<uint32_t>(at - ap.ref_rise_q8));
          if (inv_t > 16384) inv_t = 16384;
          // Each estimate has the latest slope's noise: the first is taken, later ones move it by
          // ¼ (one at σ 0.3 °C read fopdt-120-25's 1/T 24 % high, ū 20 %: the slow law held S + 9.5 °C).
          if (ap.loss_estimates != 0) inv_t = static_cast<uint32_t>(inv_t_q16_ + div2n(static_cast<int32_t>(inv_t) - inv_t_q16_, 2));
          const bool first = ap.loss_estimates == 0;
          ap.loss_estimates = 1;
          ap.near_only = false;  // learnt at full power: the approach's usual rules
          inv_t_q16_ = static_cast<uint16_t>(inv_t);
          // The deadbeat on a model without loss (a flat cut probe that showed none) built its
          // history without it, and over-predicted the heat in flight by the loss over L̂ bins
          // (fopdt-120-25: cut at 137 °C, landed 20 °C short, then a P law's 110 s creep):
          // rebuild it with the loss just learnt (stage 9).
          // (Not after a tail-timed probe: its S comes from the pulse's area over T, loss and all.)
          if (first && inv_t != 0 && ap.landed == 0 && probe_.max_tick == 0 && !ap.lag_probe && !tail_timed()) return 9;
        }
        // A probe cut short while the lags were still filling (a hot start has little room
        // below the target) leaves S low, so the steady duty ū = loss/S comes out high and the
        // approach overshoots. At full power with the lags filled, ẏ = S − rise/T: a steeper
        // S shown here replaces it (never lowered: a low S only errs towards overshoot), once
        // 1/16 steeper, or 1/32 after a lag-type probe: a lag blunts a short pulse's peak, and
        // two-node-delay5's probe read S 585 (Q8 per bin) against 628, re-learnt here on half the
        // noise seeds only (622: C 249 or 265 s by K/S; docs/autotune.md, "d held…").
        // at·(1/T) < 2^17, s4 < 2^15: the sum < 2^18, clamped to 2^15 as the probe's S.
        // After a hold, the exact rate (stage 10: its own division, the loss learning above has
        // one), while the rise is under ¾ K (there the quotient is under 4 × s4).
        if (held_start() && s4 > 0 && 4 * (at >> 4) < 3 * int32_t{hold_gain_q4_}) return 10;
        return relearn_slope(fixed::clamp(s4 + fixed::mul_q16(at, inv_t_q16_), int32_t{0}, int32_t{32767}));
      }
      return 5;
    case 8:
      set_approach_gain();
      // (After a hold ū is the hold's, whatever S: stage 5 has nothing to do, and after stage 10
      // this bin has no step left for it.)
      return held_start() ? 6 : 5;
    case 10: {
      // After a hold K is known, and at full power ẏ = S·(1 − rise/K) exactly, whatever 1/T the
      // probe read (none, from above the target: hotend40w 230 → 210 °C re-learnt S 465 against
      // 629, and its loss, learnt to match, gave T 368 s against 245.6). The same 4-bin slope and
      // rise as stage 4 (this bin's), which sent only s4 > 0 and a rise under ¾ K here: the
      // divisor is over K/4 > 0. s4 < 2^15 × K (Q4) < 2^16: < 2^31.
      const int32_t s4 = slope4_q8();
      const int32_t at_q4 = (rise - 2 * s4) >> 4;
      const int32_t k_q4 = hold_gain_q4_;
      const uint32_t s_full = (static_cast<uint32_t>(s4) * static_cast<uint32_t>(k_q4)) / static_cast<uint32_t>(k_q4 - at_q4);
      return relearn_slope(s_full > 32767u ? 32767 : static_cast<int32_t>(s_full));
    }
    case 9: {
      // The probe showed no loss (landed 0 on a flat probe means no_loss), so its S went without
      // the pulse's own loss (probe stage 5; a tangent-timed probe or not):
      // the peak is S·T·(1 − e^(−x)), x = on/T, ≈ S·on·(1 − x/2). Now that 1/T is known, S·(1 +
      // x/2): fopdt-delay25's S read 1.7 % low, and the deadbeat, on an exact L̂, landed 1 °C
      // over. x/2 < 2^15 (clamped: on < 2^13 ticks, 1/T ≤ 2^14), S < 2^15: the product < 2^31.
      const uint32_t x = (uint32_t{near(probe_).on_ticks} * inv_t_q16_) >> 4;
      slope_q8_ += fixed::mul_q16(slope_q8_, static_cast<uint16_t>(x > 32767 ? 32767 : x));
      // At full power over the whole history (case 4 learns only after hb + 4 such bins):
      // x(now) = rise·p + S·(1 − p)·T, p = (1 − 1/T)^hb. S < 2^15 × (1 − p) < 2^16 < 2^31; the
      // quotient clamped as the model is (±30,000 °C·16).
      const uint32_t p = seed_history(horizon_bins_, inv_t_q16_);
      const uint32_t held = (static_cast<uint32_t>(slope_q8_) * (65536u - p)) / inv_t_q16_;
      model_q8_ = (p >= 65536 ? rise : fixed::mul_q16(rise, static_cast<uint16_t>(p))) + static_cast<int32_t>(held > 480000u ? 480000u : held);
      return 5;
    }
    case 5: {
      // A duty change that is ū's alone (the loss learnt near the target) keeps the duty "steady"
      // for stage 3: else each step of the learning held off the next for L̂ + 6 bins (seed003:
      // the approach crawled 205 → 209.5 °C over 40 s). ū's change < 2^16, ÷ 2^8 < 2^8.
      // (The change is floored, so ū's steps under 1/256 are not followed and small rises
      // accumulate until the band restarts the window. Following them exactly was slower: seed003
      // at σ 0.1 °C 237 → 253 s, σ 0.5 267 → 276 s over 8 realisations.)
      const int32_t u = steady_from_model();
      if (ap.near_only) ap.steady_ref = static_cast<int16_t>(ap.steady_ref + ((u - ap.steady_q16) >> 8));
      ap.steady_q16 = u;
      return 6;
    }
    case 6: {
      // (A lag probe's heat in flight: 2/5 of the L̂ model's + 3/5 of the last D's; each < 2^20.)
      int32_t in_flight = model_ago(0) - model_delayed();
      if (ap.lag_probe && bins_ > ap.det_bins) in_flight = fixed::mul_q16(in_flight, 26214) + ap.det_flight_q8;
      // Behind a first-order sensor lag τ the block leads the reading by τ·ẏ at any duty (the
      // 4-bin slope < 2^15 per bin, × τ < 2^12 bins × 16). While the loss is learnt near the
      // target only, behind any lag the heat-up measured, not only one over 1.5 × L̂: that
      // learning at ¼ per bin raised ū while the lag still held heat back (an envelope hotend,
      // K 700 °C, τ1 100 s, τ2 15 s: S + 5.5 °C without).
      const uint16_t lag_q4 = ap.near_only ? probe_.lag_q4 : ap.lag_q4;
      if (lag_q4 != 0) {
        const int32_t lag_flight = (slope4_q8() * lag_q4) >> 4;
        if (lag_flight > in_flight) in_flight = lag_flight;
      }
      // After a tail-timed probe's deadbeat: the model is an FOPDT's, the hotend maybe a dead
      // time behind a thermistor lag, whose reading leads the model's delayed copy where the
      // full-power ramp starts to show and lags it where it ends (24/2/18.7 s: +16 °C for a few
      // bins). The P law took that for a landing error and cut the duty to 0.36 (a 1.6 °C dip L̂
      // later, then 0.9 °C over). Until the landing's ramp has passed through the reading, the
      // correction stays the one model_anchor took in the bin after the landing.
      if (ap.landed == 4 && ramp_in_reading()) in_flight = model_ago(0) - y_bin_q8_ + ap.det_flight_q8;
      const int32_t predicted = y_bin_q8_ + in_flight;
      int32_t ex = fixed::clamp(target_q8_ - predicted, -200 * kQ8, 200 * kQ8);
      if (untrusted_ || ap.blunted) {
        // The reading's own trend over the guard horizon must stay below the target: an
        // approach no faster than distance / guard, whatever the model says. (Also after a hot
        // start's pulse that missed a sensor lag: stage 4.)
        const int32_t guard = target_q8_ - trend_q8(kTrendSigmaQ4);
        if (guard < ex) ex = guard;
      }
      int32_t gain = ap.gain_q8;
      // Landed: twice the slow law's gain (τ ≈ 0.6 L̂; the aligned predictor holds it on a
      // trusted FOPDT-like model) takes the last few °C in ~L̂ instead of 2–3 L̂.
      if (ap.landed == 1 || ap.landed == 4) gain = gain > 20000 ? 40000 : 2 * gain;
      if (ap.landed == 0) {
        // A trusted cut probe's first approach: deadbeat on the model (gain 1/S: full power until
        // the undelayed prediction is within a bin's heat of the target, that bin's exact duty),
        // then the slow law from the first unsaturated bin on.
        const uint32_t fast = static_cast<uint32_t>(gain) * approach_tau();
        gain = static_cast<int32_t>(fast > 40000 ? 40000 : fast);
        // The duty set now starts ¾ of a bin late (this is the bin's 6th step): the heat the
        // present duty still adds above ū's until then counts as in flight too.
        const int32_t late = heat_q8(static_cast<uint16_t>(duty_q16_ >> 8)) - heat_q8(static_cast<uint16_t>(ap.steady_q16 >> 8));
        ex -= late - div2n(late, 2);
      }
      ex = fixed::clamp(ex, -200 * kQ8, 200 * kQ8);  // again after the deadbeat's heat in flight
      const int32_t u = ap.steady_q16 + ((ex * gain) >> 8);  // |ex·gain| ≤ 51,200 · 40,000 < 2^31
      if (u < kFull && ap.landed == 0) {
        ap.landed = probe_.max_tick != 0 ? 1 : (tangent_timed() ? 4 : 3);
        if (tail_timed()) ap.det_bins = 0;  // the next bin's model_anchor takes the landing's figures
      }
      duty_q16_ = clamp_duty(u);
      ap.duty_avg_q16 += div2n(static_cast<int32_t>(duty_q16_) - ap.duty_avg_q16, 2);
      // Above the target with the trend carrying it past S + 2 °C: heater off, as in the relay.
      // An untrusted model's ū can be far off (seed000-4 at σ 0.2: ū 0.52 for a steady 0.28),
      // and the P law's gain then parks the reading that far above (S + 11.6 °C before). Not in the
      // average the relay's bias starts from (its zeros there failed seed000-4's relay at σ 0.1).
      if (guard_off_ && y_bin_q8_ > target_q8_) duty_q16_ = 0;
      // (An untrusted model's P law may stall short of the target: the relay takes over nearer.)
      // Where the loss is learnt near the target only, not while that learning still moves 1/T
      // (or waits on a moving duty): a relay started on a ū 10 % low swung 4 °C below and then
      // drifted to S + 3.4 °C (seed003, σ 0.04). A loss never learnt (held with the heater off)
      // has nothing to wait for.
      const bool learning = ap.near_only && ap.unlearnt && inv_t_q16_ != 0;
      // After a tangent-timed flat probe's landing (law 4) the window takes ±1 °C once the reading
      // has kept within 2 °C for L̂ + 2 bins: a 1.5 % error in the 1/T learnt at full power parks
      // the predictor's reading up to 0.9 °C off (fopdt-delay25, σ 0.1 °C), and the approach then
      // left by its stall rule with a settling relay cycle (+100 s). Not from the landing on: a
      // fast hotend (K 900, C 200, D 3) was still swinging, and its relay read D +17 %.
      const bool tangent_landed = ap.landed == 4 && ap.near_bins > ap.bins + 2;
      ap.settled_bins = abs32(target_q8_ - y_bin_q8_) < (untrusted_ ? 4 * kSettleBandQ8 : (tangent_landed ? 2 * kSettleBandQ8 : kSettleBandQ8)) && !learning
                          ? static_cast<uint8_t>(ap.settled_bins + 1)
                          : 0;
      settled_window();
      // A P law on a slightly wrong loss stalls short of the target, and the loss learning's
      // resolution (≈ 0.02 °C/bin of slope) may not move it (heavy-slow in simavr: 209.0 °C for
      // an hour). Within 2 °C for 3 (L̂ + 2) bins is near enough: the relay's bias takes over.
      ap.near_bins = abs32(target_q8_ - y_bin_q8_) < (untrusted_ ? noise_floor(4 * kSettleBandQ8, kNearSigmaQ4) : 4 * kSettleBandQ8) ? static_cast<uint8_t>(ap.near_bins < 255 ? ap.near_bins + 1 : 255) : 0;
      // Crossings of the target (±0.3 °C): a slow hotend that the approach leaves swinging around
      // it goes to the relay at the second crossing, whose bias adaptation takes over.
      const int8_t side = y_bin_q8_ > target_q8_ + kQ8 * 3 / 10 ? 1 : (y_bin_q8_ < target_q8_ - kQ8 * 3 / 10 ? -1 : 0);
      if (side != 0 && side != ap.side) {
        if (ap.side != 0) ++ap.crossings;
        ap.side = side;
      }
      if (y_bin_q8_ > target_q8_ + kQ8) ap.overshot = true;
      const uint8_t hb = ap.bins;
      return ap.settled_bins >= hb + 2 || ap.near_bins >= 3 * (hb + 2) || ap.crossings >= 2 ? 7 : 0;
    }
    default: {
      if (settled_hold()) return 0;
      ap.crossings = 0;
      ap.side = 0;
      // Relay around the smoothed duty; d for ±1.5 °C by the probe's model (in-flight rise per
      // unit duty ≈ S·L̂ bounds the FOPDT excursion K·d·(1 − e^(−L/T))): 384·2^16 < 2^25.
      bias_q16_ = clamp_duty(ap.duty_avg_q16);
      d_q16_ = clamp_step((static_cast<uint32_t>(kAmplitudeQ8) << 16) / (static_cast<uint32_t>(slope_q8_) * horizon_bins_));
      // Settled on the target at the steady duty (the last L̂ + 2 bins within ±0.5 °C): the first
      // half goes low, and the cycle from its end on is measured, for once that half has lasted
      // L̂ the in-flight heat is the relay's own, as in any later cycle. Likewise after the
      // deadbeat on a flat FOPDT probe's model (landed 3), whose history stage 9 rebuilt with the
      // loss learnt at full power: fopdt-120-25 −100 s, its D as close. A heat-up too short for
      // that estimate settles on the loss learnt near the target instead, as well: 10 such tunes
      // of a 180-tune FOPDT grid read D within 3.5 % without the settling cycle. Not after a lag probe's (heavy-slow's
      // D came out 17.8–22.8 s against 25.7), nor after one that went 1 °C past the target (an FOPDT
      // of C 300 s, D 35 s settled from S + 2.4 °C, still drifting: D +35 %). Otherwise a settling
      // cycle first (an approach that left by its crossings or its stall).
      const bool settled = ap.settled_bins >= ap.bins + 2;
      settling_cycles_ = settled && !untrusted_ && (ap.landed == 1 || (ap.landed >= 3 && !ap.lag_probe && !ap.overshot) || probe_.continuous) ? 0 : kSettlingCycles;
      relay_hi_ = settling_cycles_ != 0 && y_bin_q8_ < target_q8_;
      stall_ref_q8_ = y_bin_q8_;  // the first half's stall test measures progress from here
      half_ticks_ = 0;
      started_cycle_ = false;
      cycle_index_ = 0;
      enter(Phase::kRelay);
      return 0;
    }
  }
}

// The approach's settled window (its last L̂ + 2 bins within ±0.5 °C, ±1 °C after a tangent-timed
// landing) as a measurement, per bin: Σ (y − target) (q8) and Σ duty (q8) taken about L̂ earlier
// (the reading shows it then: an FOPDT's T·ẏ + y = K·u(t − D)), and the first half's Σ (y − target)
// for the window's drift (compute: K·ū = rise + T·ẏ). Restarted whenever the reading leaves the
// band. |y − target| ≤ 1 °C and duty ≤ 255 per bin, ≤ 72 bins: both sums < 2^16. In the relay's per-cycle figures, which the
// relay sets before it first reads them (relay_tick): cyc_min_q8_ the Σ (y − target),
// cyc_max_q8_ the Σ duty, cyc_sum_dev_ the first half's (the first two within one LDD's reach).
uint8_t Autotune::hold_half_bins(const Approach& ap) { return static_cast<uint8_t>((ap.bins + 2) / 2); }

void Autotune::settled_window() {
  const Approach& ap = near(appr_);
  if (ap.settled_bins == 0) {
    cyc_min_q8_ = 0;
    cyc_max_q8_ = 0;
    return;
  }
  // L̂ in bins, rounded, less one: L̂/8 − f bins back, f 0.5–1.5 by L̂'s fraction (≥ 0: L̂ ≥ 8 ticks;
  // a shift: avr-gcc -Os calls a 32-bit division for `/ 8`, +500 cycles). Measured, not derived
  // (docs/autotune.md, "The settled hold after a tangent-timed landing"): where the duty still
  // moves through the window, f near 0 read fopdt-120-25's A down to −3.8 %; f 0.5–1.5 (D 24.1–25.5 s)
  // within −0.4..+0.4 %. The steps pair each reading with its own period's duty (step()): the
  // extra bin's source is not pinned down.
  const int32_t shift = ((horizon_ticks_ + kTicksPerBin / 2) >> 3) - 1;
  cyc_min_q8_ += y_bin_q8_ - target_q8_;
  cyc_max_q8_ += duty_ago(static_cast<uint8_t>(shift < horizon_bins_ ? shift : horizon_bins_));
  if (ap.settled_bins == hold_half_bins(ap)) cyc_sum_dev_ = cyc_min_q8_;
}

// On a dead-time-dominated FOPDT hotend (L̂ + 2 bins ≥ C/5) each relay cycle lasts ≥ 4 L̂ (seed002: 70 s),
// and the relay's three (a low half of ≥ L̂ and two measured cycles) took 160 s of seed002's
// 332 s tune. Where the model needs nothing the relay alone gives: a cold start's sharp cut
// probe (C from the pulse's peak, D its cut-to-peak time: within 0.5 % and 0.2 % on seed002), its
// deadbeat approach landed and settled on the target without going past it, and C ≤ 5 (more
// asks for the relay), the settled window gives A (K·ū = rise + T·ẏ over it) and the fan step
// follows at once. Likewise after a flat probe timed by its ramp's tangent (landed 4: D from the
// tangent, C from the pulse's peak as after a sharp one): fopdt-120-25's relay took 234 s of its
// 461 s tune (two cycles of ~105 s on its 25 s dead time). compute_chunk then has no relay cycle
// (ku_count_ 0): D from L̂, no Ku/Tu. The window's sums go to the relay's (per tick: × 8; duty
// q16 >> 4 = q8 × 16: < 2^16 × 128 < 2^23). No division (the step's budget).
__attribute__((noinline)) bool Autotune::settled_hold() {
  Approach& ap = near(appr_);
  if (ap.settled_bins < ap.bins + 2 || untrusted_ || hot_start_ || probe_.continuous || (ap.landed != 1 && ap.landed != 4) ||
      ap.lag_probe || ap.overshot || cycles_ > 5 || uint32_t{ap.bins + 2u} * inv_t_q16_ < kHoldWindowOverTQ16) {
    return false;
  }
  const uint16_t ticks = uint16_t{ap.settled_bins} * kTicksPerBin;
  first_ticks_ = static_cast<uint16_t>(hold_half_bins(ap) * kTicksPerBin);
  last_ticks_ = static_cast<uint16_t>(ticks - first_ticks_);
  sum_ticks_[0] = ticks;
  sum_dev_[0] = cyc_min_q8_ * kTicksPerBin;
  first_dev_ = cyc_sum_dev_ * kTicksPerBin;
  last_dev_ = sum_dev_[0] - first_dev_;
  sum_duty_[0] = static_cast<uint32_t>(cyc_max_q8_) << 7;
  // The fan step holds the approach's smoothed duty (near ū: the window is settled; compute
  // reads the fall against the duty held, whatever it is).
  bias_q16_ = clamp_duty(ap.duty_avg_q16);
  end_nofan();
  return true;
}

// A relay whose level no longer crosses the steady duty (the fan just came on, or the bias was
// off) drifts away instead of switching. After twice the horizon plus the longest half-period so
// far, move the bias by the drift: near the target ẏ = S·(u − ū), so ū = u − ẏ/S (+50 %).
// Stages 1–2 the model, 3 the drift (one division), 4 the ratio to the target's rise (one division).
uint8_t Autotune::relay_stage(uint8_t stage) {
  if (stage == 1) {
    model_bin();
    return 2;
  }
  if (stage == 2) {
    model_anchor();
    return 3;
  }
  if (stage == 3) {
    uint32_t wait = static_cast<uint32_t>(horizon_ticks_) + 4 * kTicksPerBin;
    if (wait < longest_half_) wait = longest_half_;  // a slow hotend's halves are long anyway
    if (half_ticks_ < wait || uint32_t{half_ticks_} - last_nudge_ < wait) return 0;
    // Moving away only beyond the noise: a 4-bin slope past 3 σ of its own noise (σ/8), else a
    // noisy bin (σ 0.5 °C: one in ~14) moved fopdt-120-25's levels past the steady duty, a swing
    // to S + 6.8 °C. Or stalled: on the far side and, since the switch or the last nudge (≥ 2 ×
    // the wait), approaching at under a quarter of the S·d a level d off ū gives (a slow mode
    // creeping at 0.005 °C/s; the noise used to nudge such a relay by chance).
    // S·d < 2^15 · 2^14 >> 16 < 2^13, × since < 2^16: < 2^29; progress < 2^15, × 32 < 2^20.
    const int32_t s4 = slope4_q8();  // per bin
    const int32_t ds_min = noise_floor(0, kDriftSigmaQ4);
    const bool far = relay_hi_ ? y_bin_q8_ < target_q8_ : y_bin_q8_ > target_q8_;
    const bool away = relay_hi_ ? s4 < -ds_min : s4 > ds_min;
    const int32_t progress = relay_hi_ ? y_bin_q8_ - stall_ref_q8_ : stall_ref_q8_ - y_bin_q8_;
    const uint32_t since = uint32_t{half_ticks_} - last_nudge_;
    const uint32_t rate = (static_cast<uint32_t>(slope_q8_) * d_q16_) >> 16;  // q8 per bin
    const bool stalled = since >= 2 * wait && 4 * int32_t{kTicksPerBin} * progress < static_cast<int32_t>(rate * since);
    if (!far || !(away || stalled)) return 0;
    stall_ref_q8_ = y_bin_q8_;
    last_nudge_ = half_ticks_;
    // Near the target ẏ = S·u − rise/T, so the steady duty there is ū = (u − ẏ/S)·rise_target/rise.
    const int32_t level = relay_hi_ ? bias_q16_ + d_q16_ : bias_q16_ - d_q16_;
    // (A stall's slope, within the noise, is taken as 0: noise over a slow hotend's small S moved
    // the bias by several d.)
    const uint32_t ds = away ? static_cast<uint32_t>(abs32(s4)) : 0u;
    const int32_t shift = static_cast<int32_t>(capped_ratio_q16(ds, 32767, static_cast<uint32_t>(slope_q8_)));
    pending_q8_ = s4 < 0 ? level + shift : level - shift;
    return 4;
  }
  // A switch since stage 3 (which nudges only ≥ its wait, ≥ 32 ticks, into a half): the nudge was
  // for the half that ended. The new half keeps its levels, and so does the record cycle_stage 2
  // writes of the cycle that switch completed.
  if (half_ticks_ < kTicksPerBin) return 0;
  const int32_t u = pending_q8_;
  const int32_t rise = y_bin_q8_ - ambient_q8_;
  if (u <= 0 || rise <= kQ8) return 0;
  // u · (rise_target/rise): the ratio in Q8 (≤ 2^10 for rise ≥ ¼ of the target's), u < 2^17.
  uint32_t ratio_q8 = static_cast<uint32_t>(target_q8_ - ambient_q8_) * 256u / static_cast<uint32_t>(rise);
  if (ratio_q8 > 1024) ratio_q8 = 1024;
  const int32_t estimate = static_cast<int32_t>((static_cast<uint32_t>(u > 131071 ? 131071 : u) * ratio_q8) >> 8);
  const bool unknown = bias_unknown_;
  bias_unknown_ = false;
  if (unknown && cycle_index_ == 0) {
    // The relay's first cycle, on a bias that said nothing (set_levels: levels 0 and 2d; a high
    // half's nudge, a low half's level is 0): on a strong heater (K 1,300 °C, d 0.5 %, ū 14 %) the
    // reading fell from S to S − 120 °C at 1 % a nudge (below), and the relay ended `did not
    // hold`. The fall with the heater all but off is the loss, but read through a lag's transient
    // (τ2 21 s: ū +35 %): levels 0 and the estimate (1.5 × it swung to S + 14.8 °C; the estimate
    // as the bias put both levels above ū: S + 25 °C), and this cycle becomes a settling one
    // (if it was to be measured), which finds the bias and d. (estimate < 2^20.)
    if (settling_cycles_ == 0) settling_cycles_ = kSettlingCycles;
    d_q16_ = clamp_step(static_cast<uint32_t>(estimate) / 2u);
    bias_q16_ = d_q16_;
    return 0;
  }
  // At most 2·d per nudge: on a hotend slower than its probe showed, the drift is not yet the
  // steady one, and large moves would build up a swing.
  const int32_t limit = 2 * static_cast<int32_t>(d_q16_);
  bias_q16_ = clamp_duty(fixed::clamp(estimate, static_cast<int32_t>(bias_q16_) - limit, static_cast<int32_t>(bias_q16_) + limit));
  return 0;
}

// Levels bias ± d within 0..100 %. A bias under the smallest d says nothing of the steady duty
// (an approach that held the target with the heater off, its loss never learnt): it becomes d,
// levels 0 and 2d, which must straddle the steady duty. (Before, d = 0.5 % above a bias of 0.2 %
// wrapped the low level bias − d to 99.7 %: full power in the low half, a 4 °C/s hotend heated
// from S to the S + 25 °C abort. Levels 0 and 1 % then held no oscillation.)
void Autotune::set_levels() {
  if (bias_q16_ < kMinDutyStepQ16) {
    bias_q16_ = d_q16_;
    bias_unknown_ = true;
  }
  if (d_q16_ > bias_q16_) d_q16_ = bias_q16_;
  if (d_q16_ > kFull - bias_q16_) d_q16_ = static_cast<uint16_t>(kFull - bias_q16_);
}

bool Autotune::relay_tick(int32_t yf, int32_t y) {
  bool ended = false;
  ++half_ticks_;
  if (half_ticks_ == 1) last_nudge_ = 0;
  cyc_sum_dev_ += y - target_q8_;  // |y − target| ≤ 25 °C·256 per tick (else too hot / failed)
  cyc_sum_duty_ += duty_q16_;      // ≤ 65535 per tick; < 2^16 ticks per cycle (two halves)
  if (half_ticks_ > t600_) {
    fail(AutotuneFailure::kNoOscillation);
    return false;
  }
  const int32_t hysteresis = noise_floor(kHysteresisQ8, kHysteresisSigmaQ4);
  // With a trusted model no relay half is shorter than half the probe's response time L̂: the
  // last switch cannot have shown in the reading sooner, so an earlier crossing is noise (at
  // σ 0.3–0.5 °C seed002's and fopdt-120-25's relays chattered in 3–9 s cycles, whose figures
  // drove d up: +10 to +22 °C). An untrusted L̂ (seed000: 250 s) is too uncertain to wait for
  // in full, but a quarter of it is safe (heavy-slow at σ 0.5: a 1 s half after a noise crossing
  // left the next cycle's bias 10 % below the steady duty, and the relay stopped switching).
  // (The first half after a settled approach lasts ≥ L̂: the first cycle's in-flight heat is
  // then the low level's alone, as in any later cycle; seed002 at L̂/2: T 26.8 s against 24.)
  // On a noisy sensor (σ > 0.3 °C) a trusted dead-time-dominated hotend (L̂/T ≥ 0.2, L̂ in whole
  // bins) gets halves of at least L̂: an FOPDT relay's half lasts longer than its dead time, and
  // at L̂/2 the noise ended halves early (seed004, seed002, fopdt-120-25 at σ 0.5: cycles of
  // ~2·L̂/2, D read 35–60 % short on 7 of 120 tunes). Not on lag-type hotends (their L̂ is a lag,
  // whose relay halves are shorter: hotend30w and hotend40w-delay5 overshot more after U1), nor
  // below 0.3 °C, where nothing changes. Except while the mean is 2 °C past the target (8 σ of the
  // mean at σ 0.5): no noise crossing, the level is off (seed004 realisation 8 at σ 0.5, both
  // levels above the steady duty: S + 6.44 °C with halves of L̂, 5.33 with this exception).
  // Neither input changes during the relay (noise_q8_ stops at the probe's response, 1/T at the
  // approach's end). L̂ ≤ 254 bins, 1/T < 2^16: the product < 2^24. Likewise at any noise where L̂
  // is a tangent-timed dead time (probe stage 5: the response is the pulse's own ramp, no lag):
  // no crossing within D of a switch is the switch's (fopdt-delay25 at σ 0.3 °C, one realisation:
  // halves of 12 s on noise crossings, D read 10 s for 25); the same 2 °C exception. (A tail-timed
  // L̂ is a dead time too, a short lag's included: its relay, where the hold fails, keeps the rule.)
  const bool first_settled_half = settling_cycles_ == 0 && !started_cycle_;
  const bool noisy_dead_time = !untrusted_ && !first_settled_half && noise_q8_ > kLongHalfNoiseQ8 &&
                               uint32_t{horizon_bins_} * inv_t_q16_ >= kLongHalfLOverTQ16 &&
                               abs32(yf - target_q8_) <= kLongHalfFarQ8;
  const bool dead_time = tangent_timed() && abs32(yf - target_q8_) <= kLongHalfFarQ8;
  const int32_t hl = untrusted_ ? horizon_ticks_ >> 2
                                : (first_settled_half || noisy_dead_time || dead_time ? horizon_ticks_ : horizon_ticks_ >> 1);
  const int32_t min_half = hl > kTicksPerBin ? hl : kTicksPerBin;
  if (relay_hi_) {
    if (yf < cyc_min_q8_) cyc_min_q8_ = yf;
    if (yf > target_q8_ + hysteresis && half_ticks_ >= min_half) {
      sw_hi_q8_ = yf;
      stall_ref_q8_ = yf;
      t_hi_ = half_ticks_;
      if (half_ticks_ > longest_half_) longest_half_ = half_ticks_;
      half_ticks_ = 0;
      relay_hi_ = false;
      cyc_max_q8_ = yf;
    }
  } else {
    if (yf > cyc_max_q8_) cyc_max_q8_ = yf;
    if (yf < target_q8_ - hysteresis && half_ticks_ >= min_half) {
      sw_lo_q8_ = yf;
      stall_ref_q8_ = yf;
      const uint16_t t_lo = half_ticks_;
      if (half_ticks_ > longest_half_) longest_half_ = half_ticks_;
      half_ticks_ = 0;
      relay_hi_ = true;
      if (started_cycle_) {
        end_cycle(t_lo);
        ended = true;
      }
      started_cycle_ = true;
      cyc_sum_dev_ = 0;
      cyc_sum_duty_ = 0;
      cyc_min_q8_ = yf;
    }
  }
  set_levels();
  duty_q16_ = relay_hi_ ? static_cast<uint16_t>(bias_q16_ + d_q16_) : static_cast<uint16_t>(bias_q16_ - d_q16_);
  if (guard_off_) duty_q16_ = 0;
  return ended;
}

// The switch that completes a cycle: copy its figures (no division); cycle_stage does the rest.
void Autotune::end_cycle(uint16_t t_lo) {
  period_ticks_ = static_cast<uint16_t>(t_hi_ + t_lo);
  cyc_a_q8_ = div2n(cyc_max_q8_ - cyc_min_q8_, 1);
  if (cyc_a_q8_ < 1) cyc_a_q8_ = 1;
  cyc_duty_done_ = cyc_sum_duty_;
  cycle_.min_q8 = cyc_min_q8_;
  cycle_.max_q8 = cyc_max_q8_;
  cycle_.bias = static_cast<uint8_t>((uint32_t{bias_q16_} * 255 + 32768) >> 16);
  cycle_.d = static_cast<uint8_t>((uint32_t{d_q16_} * 255 + 32768) >> 16);
  ++cycle_index_;
  if (cycle_index_ > settling_cycles_) {
    // The first and last measured cycles' sums: the relay's drift between them (compute).
    if (first_ticks_ == 0) {
      first_dev_ = cyc_sum_dev_;
      first_ticks_ = period_ticks_;
    }
    last_dev_ = cyc_sum_dev_;
    last_ticks_ = period_ticks_;
    sum_dev_[0] += cyc_sum_dev_;
    sum_duty_[0] += cyc_sum_duty_ >> 4;
    sum_ticks_[0] += period_ticks_;
  }
  cycle_stage_ = 1;
}

// 1: Ku; 2: Tu and the event; 3: the bias; 4: d and what comes next. ≤ one division each.
uint8_t Autotune::cycle_stage(uint8_t stage) {
  const uint32_t a = static_cast<uint32_t>(cyc_a_q8_);
  if (stage == 1) {
    // Ku = 4·d/(π·a) on the 0..255 scale = d_q16·324.68/a_q8 (× 256 for q8); d_q16 ≤ 65535 and
    // 32,468 < 2^15: product < 2^31; 100·a < 2^23.
    ultimate_.ku_q8 = static_cast<int32_t>(uint32_t{d_q16_} * 32468u / (100u * a));
    return 2;
  }
  if (stage == 2) {
    ultimate_.tu_q8 = seconds_q8(period_ticks_);
    event_ = AutotuneEvent::kCycle;
    if (cycle_index_ > settling_cycles_) {
      event_ = AutotuneEvent::kUltimate;  // cycle_ is valid too
      ku_sum_q8_ += static_cast<uint32_t>(ultimate_.ku_q8);
      tu_sum_q8_ += static_cast<uint32_t>(ultimate_.tu_q8);
      ++ku_count_;
      // The cycle for compute's T/L fit, here rather than in end_cycle, whose step also runs the
      // relay's tick (seed002-lag2's largest step, 2,962 cycles, was that switch; now 2,731). This
      // stage runs ≤ 7 steps after the switch (bin_end and the relay's ≤ 4 bin stages first), the
      // next switch is ≥ 8 ticks away, a nudge decided before the switch is dropped (relay_stage
      // 4) and stage 3 moves the bias: the levels, switch readings and t_hi are the cycle's
      // still. Its extremes moved on: cycle_'s copies.
      StoredCycle& c = scratch_.stored[stored_count_ % kMaxStoredCycles];
      ++stored_count_;
      c.u_hi_q16 = static_cast<uint16_t>(bias_q16_ + d_q16_);
      c.u_lo_q16 = static_cast<uint16_t>(bias_q16_ - d_q16_);
      c.max_q8 = static_cast<int16_t>(cycle_.max_q8 - target_q8_);
      c.min_q8 = static_cast<int16_t>(cycle_.min_q8 - target_q8_);
      c.switch_hi_q8 = static_cast<int16_t>(sw_hi_q8_ - target_q8_);
      c.switch_lo_q8 = static_cast<int16_t>(sw_lo_q8_ - target_q8_);
      c.t_hi = t_hi_;
      c.t_lo = static_cast<uint16_t>(period_ticks_ - t_hi_);
    }
    return 3;
  }
  if (stage == 3) {
    // Adapt: bias = the cycle's mean duty (centres the oscillation), the trend guard's zeros
    // included. Keeping the bias after a guarded cycle instead finished seed000-4's tune on two
    // more noise realisations on the host (σ 0.5 °C), but in simavr left its relay off-centre
    // (bias 77 for three cycles): D 38 s where it read 66, and the state feedback U1 designed on
    // it held a 18 °C limit cycle (9 °C overshoot, then settled, with the bias adapted).
    const uint32_t mean = cyc_duty_done_ / (period_ticks_ > 0 ? period_ticks_ : 1u);
    bias_q16_ = static_cast<uint16_t>(mean > kFull ? kFull : mean);
    return 4;
  }
  // d towards ±1.5 °C: ≤ 2^16 · 384 < 2^25. Not once the measuring began without a settling
  // cycle: the next cycle's levels must be this one's, or its start is not the periodic one
  // the T/L formulas read (seed002, one noise realisation: T 28.0 s against 24). Nor, on a
  // lag-type hotend (tangent probe), once the measured cycles began: a new d starts a transient
  // whose slow lag carries its heat across the cycle's ends (K·ū = ȳ + Σ·Δy/W + Π·Δẏ/W over a
  // window W), and seed003's K read 2.2 % high, the fan-step's F 52 % against 42.6 (now 0.6 %,
  // 45.4 %). Nor on a cut probe's hotend, for the same reason (each new d starts a transient the
  // formulas read as part of the periodic cycle): at σ 0.3 °C over 20 noise seeds K read up to
  // 2.0 % off on the FOPDT plants (now 0.8 %), 2.0 / 3.4 % high on heavy-slow / two-node-delay5
  // (now 0.6 / 0.6 %), F 50.2 / 48.4 % against 42.9 / 42.6 (now 48.1 / 44.7): docs/autotune.md,
  // "d held over the measured cycles of a cut probe". Not on an untrusted cut probe's (a response
  // past the model history: seed000; a retried probe; a plateau), whose relay D moved with it
  // (seed000-4: 74 → 76–90 s).
  if (settling_cycles_ != 0 && (cycle_index_ <= settling_cycles_ || (!probe_.continuous && untrusted_))) {
    uint32_t d = uint32_t{d_q16_} * kAmplitudeQ8 / a;
    if (d > 2u * d_q16_) d = 2u * d_q16_;
    if (d < d_q16_ / 2u) d = d_q16_ / 2u;
    d_q16_ = clamp_step(d);
  }
  if (cycle_index_ >= settling_cycles_ + nofan_measure_) end_nofan();
  return 0;
}

// The no-fan measurement is done (the relay's cycles, or settled_hold's window). The relay's bin
// stages (if any) do not belong to the next phase; 1/T as it stands is the drift correction's
// (compute), with or without F. The fan step (F1): fan 100 %, the heater held at bias_q16_ (the
// last cycle's mean duty, or the settled approach's), open loop: the fan's loss (F ≥ 0) makes
// the reading fall, and the fall gives F (fan_stage; a held duty above the steady one can make it
// rise instead: that ends the step).
__attribute__((noinline)) void Autotune::end_nofan() {
  stage_ = 0;
  inv_t_nofan_q16_ = inv_t_q16_;
  if (measure_fan_) {
    fan_ = 255;
    if (bias_q16_ > kFanHeldMaxQ16) bias_q16_ = kFanHeldMaxQ16;  // (compute reads the held duty here)
    duty_q16_ = bias_q16_;
    enter(Phase::kFan);
  } else {
    enter_compute();
  }
}

// The fan step (F1). Near the no-fan steady state the hotend obeys K·u(t − L) = (1 + F)·rise +
// T·ẏ: once the held duty u and the fan show in the reading, its level and slope give F, open
// loop, in a few dead times (the hold it replaces waited for the approach law to bring the
// reading back from the dip and then held ⌈C/2⌉ × (L̂ + 2) bins: seed002 211 s, now 28 s).
// From L̂ + 2 bins after the fan came on (2 L̂ + 2 on a lag-type hotend: its sensor lag must pass
// too; after a tail-timed probe the peak's lateness against L more, in whole bins: on L̂ + 2 alone
// the lag's transient read F 12 % low on 24/6/16, and U1's fan dip was 5.6 °C) a window of
// ⌈C/2⌉ × (L̂/2 + 4) bins: length in bins (< 2^10 for L̂ < 256).
uint16_t Autotune::fan_wait_bins() const {
  const uint16_t late = tail_timed() ? static_cast<uint16_t>((probe_.y_after_q8 + 7) >> 3) : 0;
  return static_cast<uint16_t>((probe_.continuous ? 2u : 1u) * horizon_bins_ + 2u + late);
}

uint16_t Autotune::fan_span_bins() const {
  return static_cast<uint16_t>(((cycles_ + 1u) >> 1) * ((horizon_bins_ >> 1) + 4u));
}

// One piece per bin, no division: bins_ counts the bins since the fan came on. The window's bin
// means summed (|y − target| < 2^16 per bin, < 2^11 bins), its first bin kept for its change.
void Autotune::fan_stage() {
  const uint16_t wait = fan_wait_bins();
  // The held duty is the last cycle's mean, which can sit above the steady duty (a drifting or
  // noisy relay): with a fan that hardly cools, the reading then rises. The step ends 2 °C above
  // S, wait included (F from what the window has, ≈ 0; no window: F 0).
  const bool rising = y_bin_q8_ > target_q8_ + kFanRiseQ8;
  if (bins_ < wait && !rising) return;
  if (rising && bins_ <= wait) {
    pending_q8_ = 0;
    fan_span_ = 0;
    enter_compute();
    return;
  }
  if (bins_ == wait) pending_q8_ = y_bin_q8_;
  sum_dev_[1] += y_bin_q8_ - target_q8_;
  ++sum_ticks_[1];
  // The window ends early once the reading has fallen kFanFallQ8 past its first bin (a fast
  // hotend's slope is plain by then, and the dip stays small): its span is then the bins so far.
  // After a tangent-timed probe (an FOPDT: no lag whose transient the window must outlast;
  // K·u = (1 + F)·rise + T·ẏ holds over any span) once it has fallen 16 σ of the reading, 2 °C
  // at least: the fall's noise is then under 1/30 of it (σ_bin = σ/√8, two bins; at 8 σ, F at
  // σ 0.3 °C read ±12 %, at 16 σ ±9 %). fopdt-slow's window took 30 bins to fall 8 °C, now ~8.
  // noise_q8_ < 2^9, × 255 ÷ 16: < 2^17.
  int32_t fall_end = kFanFallQ8;
  if (tangent_timed() && !tail_timed()) {  // (a tail-timed probe's hotend may have a lag)
    const int32_t noisy = noise_floor(kFanFallQ8 / 4, kFanFallSigmaQ4);
    if (noisy < fall_end) fall_end = noisy;
  }
  const int32_t fall = pending_q8_ - y_bin_q8_;
  if (!rising && bins_ < wait + fan_span_bins() && (fall < fall_end || bins_ < wait + 4)) return;
  fan_span_ = static_cast<uint16_t>(bins_ - wait);
  pending_q8_ = -fall;  // Δ over the span (compute)
  enter_compute();
}

void Autotune::enter_compute() {
  fan_ = 0;
  duty_q16_ = 0;
  // A hot start's decay (or a cold probe's tail) first (decay_step); not where the response
  // outlasted the model history (seed000's higher-order hotends: no first-order decay or lag to
  // read; their figures stay 0 from start()).
  compute_step_ = (hot_start_ || probe_tail()) && !long_response() ? 0 : kCoolDecaySteps;
  enter(Phase::kCompute);
}

// The full-power slope S = K/T (per bin, °C × 256) the fan step's fall is read against; relay_t
// the relay's mean T (s × 256; 0: none). On a hot start whose first cool-down's T is at least ¾
// of the relay's (an FOPDT: 0.75–1.0 × on the bank; a thermistor lag slows the first decay, and
// the relay reads a lag as a long T: 0.28–0.7 ×), K·(1/T): the S the approach learnt at full
// power soon after a switch-on read 24–31 % steep there (seed002, seed004, fopdt-120-25 after a
// hold), and F 15–18 % low with it. K < 2^19 and relay T < 2^23: each mul_q16 fits.
__attribute__((noinline)) int32_t Autotune::fan_slope_q8(int32_t k_q8, int32_t relay_t_q8) const {
  const uint16_t rate_q16 = static_cast<uint16_t>(store_.c.decay_q24 >> 8);
  if (rate_q16 == 0) return slope_q8_;
  const int32_t s = fixed::mul_q16(k_q8, rate_q16);  // K/T per bin (K < 2^19)
  // A cold probe's tail: K/τ1 where over 1/16 above the probe's S, which a lag blunts (its peak).
  if (!hot_start_) return s - slope_q8_ > slope_q8_ >> 4 ? s : slope_q8_;
  if (relay_t_q8 <= 0 || 3 * fixed::mul_q16(relay_t_q8, rate_q16) > 4 * seconds_q8(kTicksPerBin)) return slope_q8_;
  return s;
}

// The compute's first steps (hot starts, and cold ones whose cut probe read its tail): the first
// cool-down (CoolDecay; cold: the tail) as 1/T per bin (Q24) and T (s × 256), both 0 where there
// is none. An FOPDT's state is first order: once the
// heater has been off for a dead time, the reading decays as e^(−t/T) whatever heated it before
// (a steady hold, or M109's heat still in flight), and ln(rise_a/rise_b) over the span in bins is
// its 1/T. The whole span (3–10 bins on the bank) matters: the baseline's 2-bin slope read
// fopdt-120-25's T 1.6–3.7 % long at σ 0.1 °C, and its model-following heat-up overshoots
// ~1.4 °C per 1 %. One logarithm or division per step: ln < 2^20 (rise_a < 2^18),
// × 2^8 < 2^28; s per bin (q8) < 2^9, × 2^8 × 2^16 (div_q16 normalises) ÷ 1/T.
void Autotune::decay_step(uint8_t s) {
  Compute& v = near(store_.c);
  // A cold cut probe's tail instead (probe_stage: two bins' rises above its baseline, summed, one
  // window apart; each sum < 2^18). Only a tail that fell by over 1/8 (its ln is then within ~1 %
  // at σ 0.1 °C on a 40 °C pulse) and still stood at over a quarter of the peak (not noise on a
  // pulse that has gone; then a/b < 4, a sum being at most two peaks, and 1/T per bin < ln 4 / 3
  // bins < ½: rate_q16 in fan_slope_q8 < 2^15).
  const Probe& p = probe_;
  CoolDecay d = fd_.decay;
  if (!hot_start_) {
    d.rise_a_q8 = p.fit_q_q8;
    d.rise_b_q8 = p.fit_r_q8;
    d.bins = static_cast<uint16_t>(probe_tail() && tail_fell() ? p.fit_p_q6 : 0);
  }
  if (s == 0) {
    v.t_decay_q8 = 0;  // here: the span's ln, Q16
    v.decay_q24 = 0;
    if (d.bins >= 2 && d.rise_b_q8 > 0 && d.rise_a_q8 > d.rise_b_q8) {
      v.t_decay_q8 = fixed_math::ln_ratio_q16(static_cast<uint32_t>(d.rise_a_q8), static_cast<uint32_t>(d.rise_b_q8));
    }
  } else if (s == 1) {
    if (v.t_decay_q8 > 0) v.decay_q24 = static_cast<int32_t>((static_cast<uint32_t>(v.t_decay_q8) << 8) / d.bins);
  } else {
    v.t_decay_q8 = v.decay_q24 > 0 ? static_cast<int32_t>(div_q16(static_cast<uint32_t>(seconds_q8(kTicksPerBin)) << 8,
                                                                   static_cast<uint32_t>(v.decay_q24)))
                                   : 0;
  }
}

// Compute steps 10–13 of a hot start whose relay saw a lag (compute_chunk). A first-order
// sensor lag τ behind the block K/(1 + sT) has |G(jω)| = K/(ωT·√(1 + ω²τ²)) = 1/Ku at the relay's
// ω = 2π/Tu (ωT ≫ 1): with X = (K/T)·Ku·Tu/(2π·255) (Ku on Marlin's 0..255 scale),
// τ = √(X² − 1)·Tu/(2π). τ replaces D (and is the design's thermistor lag) where it is longer and
// under T/2 (a longer one is no first-order lag behind this block). One division per step, all
// 32-bit: K/T in Q11 (K·256 < 2^20, << 11 < 2^31); Ku·Tu/1602.2 in Q16 (each Q8 < 2^16: the
// product fits); X in Q12 where their product fits and X < 16 (else no lag is taken: τ > 2.4 Tu).
__attribute__((noinline)) void Autotune::relay_lag_stage(uint8_t s) {
  Compute& v = near(store_.c);
  HotendModel& m = near(result_.model);
  const AutotuneUltimate& u = result_.ultimate;
  if (u.ku_q8 <= 0 || u.ku_q8 >= 65536 || u.tu_q8 <= 0 || u.tu_q8 >= 65536 || m.time_constant_q8 < 256) return;
  if (s == 10) {
    v.ln = static_cast<int32_t>((static_cast<uint32_t>(v.k_q8) << 11) / static_cast<uint32_t>(m.time_constant_q8));
  } else if (s == 11) {
    v.lambda = static_cast<int32_t>(static_cast<uint32_t>(u.ku_q8) * static_cast<uint32_t>(u.tu_q8) / 1602u);  // 255·2π
  } else if (s == 12) {
    const uint32_t r = static_cast<uint32_t>(v.ln), g = static_cast<uint32_t>(v.lambda);
    v.ln = 0;  // √(X² − 1), Q12 (0: none)
    // A product of over 32 bits (bit lengths summing past 32) is an X of 16 or more: none.
    if (r == 0 || g == 0 || __builtin_clzl(r) + __builtin_clzl(g) < 32) return;
    const uint32_t x_q12 = (r * g + (uint32_t{1} << 14)) >> 15;  // Q11 × Q16 → Q12
    // X² − 1 in Q24 (< 2^32), its root Q12 < 2^16.
    if (x_q12 > 4096 && x_q12 < 65536) v.ln = fixed_math::isqrt_u32(x_q12 * x_q12 - (uint32_t{1} << 24));
  } else {
    // τ = root × Tu ÷ 2π (root Q12 < 2^16 × tu_q8 < 2^16: < 2^32; ÷ 2π·4096).
    const int32_t tau_q8 = static_cast<int32_t>((static_cast<uint32_t>(v.ln) * static_cast<uint32_t>(u.tu_q8) + 12868u) / 25736u);
    if (tau_q8 > m.dead_time_q8 && 2 * tau_q8 < m.time_constant_q8) {
      m.dead_time_q8 = tau_q8;
      result_.sensor_lag_q8 = tau_q8;
    }
  }
}

// Σ = (K·p − q)/r from the hand-over's lag fit (lag_fit_stage), bins × 64; 0 when there is none
// or it falls outside ½–1 × the tangent's (K − rise)/S, which overstates it by Π·ÿ/ẏ ≥ 0 (so
// beyond: noise). K·p: K < 2^19 (q8), p < 2^12: < 2^31. One division.
__attribute__((noinline)) int32_t Autotune::lag_sigma_q6(int32_t k_q8) const {
  const Probe& p = probe_;
  if (!p.continuous || p.fit_r_q8 <= 0 || k_q8 <= p.slope_rise_q8 || slope_q8_ <= 0 || slope_q8_ >= 8192) return 0;
  const int32_t num = static_cast<int32_t>((static_cast<uint32_t>(k_q8) * static_cast<uint32_t>(p.fit_p_q6)) >> 6) - p.fit_q_q8;
  if (num <= 0 || num >= (int32_t{1} << 25)) return 0;
  const uint32_t sigma = (static_cast<uint32_t>(num) << 6) / static_cast<uint32_t>(p.fit_r_q8);
  if (sigma >= 65536) return 0;
  const uint32_t tangent_q8 = static_cast<uint32_t>(k_q8 - p.slope_rise_q8);  // (K − rise)/S · S
  const uint32_t fit_q8 = (sigma * static_cast<uint32_t>(slope_q8_)) >> 6;    // < 2^29
  return fit_q8 <= tangent_q8 && 2 * fit_q8 >= tangent_q8 ? static_cast<int32_t>(sigma) : 0;
}

// The final arithmetic, one piece per step (at most one 32-bit division or two logarithms):
// 0–5 K (0–2 the drift); 15 per stored cycle (the noise lift, then T, L from the relay); 6 for the
// lag fit's Σ and K with the fan (step);
// 10 for F, the averages, the probe's C and the result. Before them, on a long-response cold
// tune, the two-lag fit: up to 35 pieces of its last sample, then 42 of its solution.
bool Autotune::compute_chunk() {
  // First the fit (a long-response cold tune with enough samples): its last sample, its
  // solution, then the storage it shares with the compute is cleared. Any other tune goes on to
  // the compute in the same step (its timing as without the fit).
  LagFit& f = near(fd_.fit);
  if (f.stage != 0) {
    f.stage = fit_stage(f.stage);
    return false;
  }
  if (f.solve != 0xFF) {
    if (long_response() && !hot_start_ && f.samples >= kMinFitSamples && tick_ <= kFitMaxTicks) {
      f.solve = fit_solve(static_cast<uint8_t>(f.solve + 1)) == 0 ? 0xFF : static_cast<uint8_t>(f.solve + 1);
      if (f.solve == 0xFF) store_.c = Compute{};
      return false;
    }
    // Sums begun but too few samples: the compute's storage still holds them.
    if (f.samples != 0) store_.c = Compute{};
    f.x[1] = 0;
    f.solve = 0xFF;
  }
  Compute& v = near(store_.c);
  const int32_t rise_target = target_q8_ - ambient_q8_;
  const uint8_t stored = stored_count_ < kMaxStoredCycles ? stored_count_ : kMaxStoredCycles;
  constexpr uint8_t k0 = 6;  // compute steps of the no-fan gain
  uint8_t s = compute_step_++;
  if (s < kCoolDecaySteps) {
    decay_step(s);
    return false;
  }
  s = static_cast<uint8_t>(s - kCoolDecaySteps);
  if (s < k0 || (s >= k0 + kCycleSteps * stored && s < k0 + kFanSteps + kCycleSteps * stored)) {  // fan: subs 0–5
    // Gain = mean rise / mean duty over the measured cycles [0] or the fan step [1].
    const uint8_t part = s < k0 ? 0 : 1;
    const uint8_t sub = s < k0 ? s : static_cast<uint8_t>(s - k0 - kCycleSteps * stored);
    const int32_t n = static_cast<int32_t>(sum_ticks_[part]) > 0 ? static_cast<int32_t>(sum_ticks_[part]) : 1;
    // A window whose mean still drifts (the slow mode of a lag-type hotend: 2 relay cycles of 5 s
    // on light-fast's 88 s read K 7.6 % high) reads the wrong gain: K·ū = rise + T·ẏ over it.
    // ẏ: the first and last measured cycles' means (centre to centre). T: the learnt 1/T (the
    // relay's, kept when the fan came on). (The fan step's window reads its own ẏ: sub 2.)
    // Cycle sums: |dev| ≤ 2^13 per tick × ≤ 2^16 ticks.
    // first_ticks_ + last_ticks_ in 32 bits: each is up to 2^16 − 1 ticks, and int is 16 bits on AVR.
    if (sub == 0 && part == 0) {
      v.a_hi = first_ticks_ > 0 ? first_dev_ / first_ticks_ : 0;
    } else if (sub == 0) {
      v.sigma_q6 = lag_sigma_q6(v.k_q8);
      // The relay's T for fan_slope_q8 (a hot start's: its lag fit, if any, took this step's division).
      v.lambda = v.sigma_q6 == 0 && hot_start_ && v.tl_count > 0 ? v.t_sum_q8 / v.tl_count : 0;
    } else if (sub == 1 && part == 1) {
      // A lag-type hotend's S is its sensor's steepest heat-up slope, where the fall's ẏ/S wants
      // the duty that drives the two lags' Σ·ẏ: the factor Σ·S/K, Q16 (Σ·S < 2^29 >> 6; div_q16
      // scales; seed003 read F 52 % against 42.6 without it). No lag fit: the tangent's own
      // (K − rise there)/K (light-fast read F +20 % without either).
      uint32_t x = 0;  // the factor's numerator, °C × 256 like K (0: none, factor 1)
      if (v.sigma_q6 > 0) {
        x = (static_cast<uint32_t>(v.sigma_q6) * static_cast<uint32_t>(slope_q8_)) >> 6;
      } else if (probe_.continuous && v.k_q8 > probe_.slope_rise_q8 && probe_.slope_rise_q8 > 0) {
        x = static_cast<uint32_t>(v.k_q8 - probe_.slope_rise_q8);
      }
      const uint32_t r = x > 0 ? div_q16(x, static_cast<uint32_t>(v.k_q8)) : 65535u;
      v.a_lo = static_cast<int32_t>(r > 65535 ? 65535 : r);
    } else if (sub == 1) {
      v.a_lo = (last_ticks_ > 0 ? last_dev_ / last_ticks_ : 0) - v.a_hi;
      v.a_hi = (static_cast<int32_t>(sum_ticks_[0]) - div2n(int32_t{first_ticks_} + last_ticks_, 1)) >> 3;  // span, bins
    } else if (sub == 2) {
      // Relay: T·ẏ = Δ · 2^16 / (span · 1/T): |Δ| clamped to 2^13, × 2^16 < 2^30; span < 2^13
      // bins × 1/T ≤ 2^14 < 2^27 (≥ 1, else no correction). Fan step: its fall ẏ as duty,
      // −ẏ/S (duty_q16) = |Δ| · 2^16 / (span · S) (× the lag factor): |Δ| < 2^16 (capped), × 2^16
      // < 2^32; span < 2^10 bins × S < 2^15 < 2^25; capped at 2^17 (F0: span 0, no division).
      const int32_t d = part == 0 ? v.a_lo : pending_q8_;
      const uint32_t den = part == 0 ? static_cast<uint32_t>(v.a_hi) * inv_t_nofan_q16_
                                     : uint32_t{fan_span_} * static_cast<uint32_t>(fan_slope_q8(v.k_q8, v.lambda));
      const uint32_t c = static_cast<int32_t>(den) > 0 ? capped_ratio_q16(static_cast<uint32_t>(abs32(d)), part == 0 ? 8192 : 65535, den) : 0;
      v.a_hi = part == 0 ? static_cast<int32_t>(c > 8192 ? 8192 : c)
                         : fixed::mul_q16(static_cast<int32_t>(c > 131072 ? 131072 : c), static_cast<uint16_t>(v.a_lo));
      if ((d < 0) != (part == 1)) v.a_hi = -v.a_hi;
    } else if (sub == 3) {
      v.mean_q8 = rise_target + sum_dev_[part] / n + (part == 0 ? v.a_hi : 0);
    } else if (sub == 4) {
      // duty_q16 >> 4; the fan step's is the duty that would hold its mean rise with the fan:
      // ū_F = u − ẏ/S (near a steady state ẏ = S·(u − ū_F): K·u = (1 + F)·rise + T·ẏ, S = K/T),
      // u the held duty, bias_q16_. F = K·ū_F/rise − 1 against the model's own K: the fan
      // feedforward's duty at the target, ū·(1 + F), is then the measured ū_F whatever K's error
      // (the last relay cycle's own rise/duty instead: σ 0.1 °C closer, but at σ 0.3 two-node-80W
      // F 13–70 % against 26–64 %: one cycle's figures).
      v.duty = part == 0 ? static_cast<int32_t>(sum_duty_[0] / static_cast<uint32_t>(n)) : (bias_q16_ >> 4) + div2n(v.a_hi, 4);
    } else {
      // mean rise < 2^17 (≤ 300 °C above ambient), × 2^12 < 2^29.
      const int32_t g = v.duty > 0 && v.mean_q8 > 0
                            ? static_cast<int32_t>(((static_cast<uint32_t>(v.mean_q8) << 12) + static_cast<uint32_t>(v.duty) / 2) /
                                                   static_cast<uint32_t>(v.duty))
                            : 0;
      if (part == 0) v.k_q8 = g;
      v.mean_q8 = g;  // the fan part's gain is read by the next step
    }
    return false;
  }
  if (s < k0 + kCycleSteps * stored) {
    s = static_cast<uint8_t>(s - k0);
    StoredCycle& c = scratch_.stored[s / kCycleSteps];
    uint8_t sub = static_cast<uint8_t>(s % kCycleSteps);
    if (sub < 2) {
      // The reading noise lifts what the relay measured, each from the 4-reading mean (σ_f = σ/2):
      // its extremes (the max of many noisy readings near a peak), and its switch levels (the
      // mean switches when its noise first carries it past target ± hysteresis, while the
      // temperature is still short of it). The switches' overstated span s_hi − s_lo, taken off
      // both num and den of 1 − θ = num/den, reads λ = L/T short; the lifted extremes lengthen
      // the period's logarithms: T short; L = T·λ short on both counts (σ 0.3 °C on the 6 FOPDT
      // plants × 10 noise realisations, against the noise-free filtered reading's figures:
      // switches alone L −10..−20 %, extremes alone T −1..−20 %, both L −1..−17 % and T −1..−20 %;
      // σ 0.5: L to −28 %, T to −34 %, and the probe's C then disagreed). The expected lift grows
      // with the readings near the level the trend takes to cross one σ, r = σ · (half period)
      // / (max − min) ticks, measured 0.2 σ at r ≈ 2, 0.6 σ at 5–9, 0.75–0.9 σ at 16–25, 0.9–1.1
      // σ at 33–51 (σ the measured noise_q8_, which reads ~9 % low); the switches' ≈ 0.85 × that.
      // Subtracted as σ · min(1, 0.2 · log2 r) (none at σ = 0: a quiet sensor's tune unchanged).
      if (sub == 0) {
        // r × 16 = σ · period · 8 / (max − min): σ ≤ 262 < 2^9 (the 2 °C cap), period < 2^16,
        // × 8: < 2^28.
        const int32_t pp = int32_t{c.max_q8} - c.min_q8;
        v.log = static_cast<int32_t>((uint32_t{noise_q8_} * (uint32_t{c.t_hi} + c.t_lo) * 8u) /
                                     static_cast<uint32_t>(pp > 0 ? pp : 1));
        return false;
      }
      // 0.2 · log2 r in Q8: (log2(16 r) − 4) · 51.2 / 2^16 (log2 < 28 · 2^16 < 2^21, × 51 < 2^27),
      // capped at 1; the lift σ · that (< 2^9 · 2^8), the switches' × 218/256 (< 2^25).
      const int32_t l2 = v.log > 16 ? fixed_math::log2_q16(static_cast<uint32_t>(v.log)) - (int32_t{4} << 16) : 0;
      const int32_t f_q8 = static_cast<int32_t>((static_cast<uint32_t>(l2) * 51u + 0x8000u) >> 16);
      const int32_t lift = (static_cast<int32_t>(noise_q8_) * (f_q8 > kQ8 ? kQ8 : f_q8)) >> 8;
      const int32_t sw = (lift * 218) >> 8;
      c.max_q8 = static_cast<int16_t>(c.max_q8 - lift);
      c.min_q8 = static_cast<int16_t>(c.min_q8 + lift);
      c.switch_hi_q8 = static_cast<int16_t>(c.switch_hi_q8 - sw);
      c.switch_lo_q8 = static_cast<int16_t>(c.switch_lo_q8 + sw);
      return false;
    }
    sub = static_cast<uint8_t>(sub - 2);
    // Rises above ambient, °C × 256.
    const int32_t y_max = rise_target + c.max_q8, y_min = rise_target + c.min_q8;
    const int32_t s_hi = rise_target + c.switch_hi_q8, s_lo = rise_target + c.switch_lo_q8;
    const int32_t a_hi = v.a_hi, a_lo = v.a_lo;
    switch (sub) {
      case 0:
        v.a_hi = fixed::mul_q16(v.k_q8, c.u_hi_q16);
        v.a_lo = fixed::mul_q16(v.k_q8, c.u_lo_q16);
        return false;
      case 1: {
        // FOPDT under a relay: y_max − y_min − (s_hi − s_lo) = (a_hi − a_lo − (s_hi − s_lo))·(1 − θ),
        // θ = e^(−L/T). num < den; num ≤ 2^15 (clamped), × 2^16 < 2^31.
        const int32_t num = y_max - y_min - (s_hi - s_lo);
        const int32_t den = a_hi - a_lo - (s_hi - s_lo);
        v.theta = 0;
        if (num <= 0 || den <= num || a_hi <= s_hi || a_hi <= y_min || s_lo <= a_lo || y_max <= a_lo || num > 32767) return false;
        v.theta = 65536u - ((static_cast<uint32_t>(num) << 16) + static_cast<uint32_t>(den) / 2) / static_cast<uint32_t>(den);
        return false;
      }
      default:
        break;
    }
    if (v.theta == 0) return false;  // this cycle does not fit the FOPDT formulas
    switch (sub) {
      case 2:
        v.lambda = fixed_math::log2_q16(v.theta);
        return false;
      case 3:  // λ = L/T = ln(1/θ) = (16 − log2 θ)·ln 2, Q16
        v.lambda = fixed_math::ln_from_log2_q16((int32_t{16} << 16) - v.lambda);
        return false;
      case 4:
        v.ln = fixed_math::log2_q16(static_cast<uint32_t>(a_hi - y_min));
        return false;
      case 5:
        v.ln -= fixed_math::log2_q16(static_cast<uint32_t>(a_hi - s_hi));
        return false;
      case 6:  // 2λ + ln((a_hi − y_min)/(a_hi − s_hi))
        v.ln = 2 * v.lambda + fixed_math::ln_from_log2_q16(v.ln);
        return false;
      case 7:
        v.log = fixed_math::log2_q16(static_cast<uint32_t>(y_max - a_lo));
        return false;
      case 8:
        v.log -= fixed_math::log2_q16(static_cast<uint32_t>(s_lo - a_lo));
        return false;
      case 9:  // + ln((y_max − a_lo)/(s_lo − a_lo)): period / T, Q16
        v.ln += fixed_math::ln_from_log2_q16(v.log);
        return false;
      case 10:
        v.log = seconds_q8(static_cast<uint16_t>(c.t_hi + c.t_lo));
        return false;
      case 11:  // T = period·2^16/(period/T)
        v.log = v.ln > 0 ? static_cast<int32_t>(div_q16(static_cast<uint32_t>(v.log), static_cast<uint32_t>(v.ln))) : 0;
        return false;
      default: {
        if (v.log <= 0) return false;
        // L = T·λ (λ = whole + Q16 fraction).
        const int32_t t_q8 = v.log;
        const int32_t l_q8 = fixed::mul_round(t_q8, fixed::Multiplier{static_cast<uint32_t>(v.lambda) >> 16,
                                                                       static_cast<uint16_t>(v.lambda)});
        // Not corrected for the relay filter's 1.5-period delay: the filter also rounds the peaks
        // off (a smaller amplitude reads as a shorter L), and the two nearly cancel (measured).
        v.t_sum_q8 += t_q8;
        v.l_sum_q8 += l_q8 > 0 ? l_q8 : 0;
        ++v.tl_count;
        return false;
      }
    }
  }
  s = static_cast<uint8_t>(s - k0 - kFanSteps - kCycleSteps * stored);  // the fan gain's steps
  HotendModel& m = near(result_.model);
  const int32_t count = v.tl_count > 0 ? v.tl_count : 1;
  switch (s) {
    case 0: {
      // F = K_nofan / K_fan − 1 (%, q8): (K << 12)/K_fan with K < 2^19; × 25,600 < 2^31.
      int32_t f_q8 = 0;
      if (measure_fan_ && sum_ticks_[1] > 0 && v.mean_q8 > 0) {
        const uint32_t r = (static_cast<uint32_t>(v.k_q8) << 12) / static_cast<uint32_t>(v.mean_q8);
        f_q8 = static_cast<int32_t>(((r > 65535 ? 65535 : r) * 25600u + 2048u) >> 12) - 25600;
      }
      m.fan_loss_pct_q8 = f_q8 < 0 ? 0 : f_q8;
      return false;
    }
    case 1:
      m.time_constant_q8 = v.t_sum_q8 / count;
      return false;
    case 2:
      // No relay (settled_hold): the sharp cut probe's cut-to-peak time or the flat one's
      // tangent, an FOPDT's D.
      m.dead_time_q8 = ku_count_ == 0 ? seconds_q8(static_cast<uint16_t>(horizon_ticks_)) : v.l_sum_q8 / count;
      return false;
    case 3:
      v.a_hi = m.time_constant_q8;  // the relay's T (case 6 compares)
      if (probe_.continuous && v.k_q8 > probe_.slope_rise_q8) {
        // A lag-type hotend (its response started within the first pulse and steepened
        // smoothly): the relay's FOPDT formulas misread a lag as a long time constant. T from
        // the heat-up instead: the lag fit's Σ (< 2^16 bins × 64, × s per bin (q8) < 2^13), or
        // the tangent's: the steepest slope S = (K − rise there)/T (< 2^19 · 2^9).
        const uint32_t per_bin = static_cast<uint32_t>(seconds_q8(kTicksPerBin));
        if (v.sigma_q6 > 0) {
          m.time_constant_q8 = static_cast<int32_t>((static_cast<uint32_t>(v.sigma_q6) * per_bin + 32u) >> 6);
        } else {
          const uint32_t num = static_cast<uint32_t>(v.k_q8 - probe_.slope_rise_q8) * per_bin;
          m.time_constant_q8 = static_cast<int32_t>((num + static_cast<uint32_t>(slope_q8_) / 2) / static_cast<uint32_t>(slope_q8_));
        }
      }
      return false;
    case 4:
      // A cut probe is a full-power pulse of p = probe_.on_ticks ticks from a steady baseline; an FOPDT's
      // response to it peaks (at D + p) at h = A·(1 − e^(−p/C)), so C = p / ln(A/(A − h)), with A
      // from the relay (≈ 0.1 %): accurate where the relay's asymmetric formulas scatter by
      // ±2.5 % at σ 0.1 °C. Here ln(A/(A − h)) as log2 (A < 2^19, A − h ≥ 1).
      v.ln = 0;
      if (!probe_.continuous && probe_max_q8_ > 0 && v.k_q8 > probe_max_q8_) {
        v.ln = fixed_math::log2_q16(static_cast<uint32_t>(v.k_q8)) -
                fixed_math::log2_q16(static_cast<uint32_t>(v.k_q8 - probe_max_q8_));
      }
      return false;
    case 5: {
      // C = p·2^16 / ln (p ≤ 6 s: < 2^11 in q8); a C over 2^23 (no FOPDT hotend) counts as none.
      v.lambda = 0;
      if (v.ln > 0) {
        const uint32_t c = div_q16(static_cast<uint32_t>(seconds_q8(probe_.on_ticks)),
                                   static_cast<uint32_t>(fixed_math::ln_from_log2_q16(v.ln)));
        v.lambda = c < (uint32_t{1} << 23) ? static_cast<int32_t>(c) : 0;
      }
      return false;
    }
    case 6: {
      // Lag-type (continuous probe): the heat-up's slope S = (K − block rise)/T and the block
      // leads the sensor by lag·S, so T = (K − rise)/S − lag; the tangent's dead time stands for
      // the lag (the FOPDT equivalent of the heat-up, as a two-point fit of it: the M307 model's
      // initial rate A/C and its delay are what its model-following heat-up relies on).
      const int32_t lag = seconds_q8(static_cast<uint16_t>(horizon_ticks_));
      // No relay T (no cycle fitted the FOPDT formulas): each fallback below stands in unchecked.
      const bool no_relay_t = m.time_constant_q8 <= 0;
      v.log = 0;  // x for the next step: 0 = no lag seen
      if (probe_.continuous && v.k_q8 > probe_.slope_rise_q8) {
        if (m.time_constant_q8 > 2 * lag) m.time_constant_q8 -= lag;
        m.dead_time_q8 = lag;
        // x = lag / T, Q16 (the next step turns it into the two-point dead time), when the
        // relay's FOPDT formulas saw a lag (their T > 1.5 × the heat-up's: 2.2–3.5 × on the
        // two-node plants and seed003); a true FOPDT's tangent is right (fopdt-30-1: 1.18 ×).
        if (2 * v.a_hi > 3 * m.time_constant_q8) {
          v.log = static_cast<int32_t>(div_q16(static_cast<uint32_t>(lag), static_cast<uint32_t>(m.time_constant_q8)));
        }
      } else if (v.lambda > 0 && (no_relay_t || 5 * abs32(v.lambda - m.time_constant_q8) < m.time_constant_q8)) {
        // The probe's C where it agrees with the relay's within 20 % (an FOPDT hotend, where the
        // probe's C is the more accurate: relay T scatters ±14 % at σ 0.1 °C; a lag's disagree by
        // ≥ 27 %), or where no relay cycle fitted the FOPDT formulas (T 0: a lag-heavy hotend on a
        // quantised sensor, found by autotune_fuzz, finished with C 0; there the probe's C and K/S
        // below agreed within 1 %, and K/S stands in where the probe has none):
        // |C − T| < 2^23, × 5 < 2^26.
        m.time_constant_q8 = v.lambda;
      } else if (hot_start_ && inv_t_nofan_q16_ > 0) {
        // A hot start has no heat-up from a steady baseline to read T from, but the approach
        // learnt the loss rate 1/T that holds the target. Taken where the relay's FOPDT formulas
        // read well above it (a sensor lag read as a long T: hotend40w after M109 S200, tuning
        // at 240 °C, 683 s against its 245.6; the loss 261 s; its tuned heat-up 1.61 → 1.18 ×
        // bound in simavr). On FOPDT hotends the two agree within 1.3 × and the relay's is kept.
        // seconds per bin (q8) < 2^9, × 2^16 < 2^25; ÷ 1/T (Q16, ≥ 1).
        const uint32_t t_loss = div_q16(static_cast<uint32_t>(seconds_q8(kTicksPerBin)), inv_t_nofan_q16_);
        // The first cool-down's T (decay_step) where the relay's T is within 4/3 of it: an FOPDT's
        // decay gives T (within 1–4 % on the bank after a hold; the relay's reads 7–30 % long on
        // a dead time, the loss 16–35 % short; relay/decay 0.99–1.33). A thermistor lag slows the
        // first decay and the relay reads it as a long T (relay/decay 1.4–3.6 on the two-node
        // hotends, heavy-slow, seed003): there the loss below, but never above the decay's T,
        // which bounds the block's (the sensor's decay only lags it; seed003 from S − 30 read the
        // loss at 113 s, the decay 83 s). (t_loss < 2^25: × 3 fits; T's < 2^25: × 4 fits.)
        const uint32_t t_decay = static_cast<uint32_t>(v.t_decay_q8);
        if (t_decay > 0 && !no_relay_t && 3 * static_cast<uint32_t>(m.time_constant_q8) <= 4 * t_decay) {
          m.time_constant_q8 = v.t_decay_q8;
        } else if (no_relay_t || 2 * static_cast<uint32_t>(m.time_constant_q8) > 3 * t_loss) {
          m.time_constant_q8 = static_cast<int32_t>(t_decay > 0 && t_decay < t_loss ? t_decay : t_loss);
        } else if (t_decay > 0) {
          m.time_constant_q8 = v.t_decay_q8;
        }
      } else if (slope_q8_ > 0 && !hot_start_) {
        // A cut probe (hot start, or a slower response): S = K/T at full power. The relay's FOPDT
        // formulas read a sensor lag as a long T (×3 on a lag-type hotend); K/S does not. Taken
        // when it is well below the relay's T (an FOPDT hotend: within noise, the relay's kept) or
        // the relay gave none; cold starts only (a hot start's pulse is read against a decaying
        // baseline: S unsure).
        // K < 2^19, × (s × 256 per bin) < 2^10: < 2^29.
        const uint32_t num = static_cast<uint32_t>(v.k_q8) * static_cast<uint32_t>(seconds_q8(kTicksPerBin));
        const int32_t t_s = static_cast<int32_t>((num + static_cast<uint32_t>(slope_q8_) / 2) / static_cast<uint32_t>(slope_q8_));
        if (t_s > 0 && (no_relay_t || 4 * t_s < 3 * m.time_constant_q8)) m.time_constant_q8 = t_s;
      }
      return false;
    }
    case 7:
      // A cold cut probe's tail (decay_step) over 1/16 faster than the C chosen above (relay, probe
      // or K/S): the block's own τ1, which a thermistor lag behind it hid from every other
      // estimate. The heat-up runs open loop within a dead time on the C it is given: 24/2/20 s
      // (τ1/τ2/D) with C 28.7 overshot 20.9 °C after U1, with τ1 0.24 °C (docs/autotune.md). Not
      // under C/2 (the lags seen read C at most ~1.5 τ1): no tail would explain more.
      if (!hot_start_ && v.t_decay_q8 > m.time_constant_q8 >> 1 && m.time_constant_q8 - v.t_decay_q8 > v.t_decay_q8 >> 4) {
        m.time_constant_q8 = v.t_decay_q8;
      }
      if (v.log > 0) {
        result_.sensor_lag_q8 = m.dead_time_q8;
        m.dead_time_q8 = two_point_dead_time(m.dead_time_q8, v.log);
      } else if (!probe_.continuous && !hot_start_) {
        // A cut probe whose cut-to-peak time is over 4 × the relay's dead time: no FOPDT peaks
        // that late (there it is the dead time), two lags τ1 ≫ τ2 peak at τ2·ln(τ1/τ2)/(1 − τ2/τ1),
        // 2–3 τ2 for τ2/τ1 = 0.2–0.05 (heavy-slow: 66 s, τ2 = 25 s). τ2 ≈ peak/2.5 is then the
        // lag, and the two-point fit's dead time ≈ τ2 at such ratios. peak < 2^17: × 13,107 < 2^31.
        const int32_t peak = seconds_q8(static_cast<uint16_t>(horizon_ticks_));
        if (peak > 4 * m.dead_time_q8) {
          const int32_t lag = static_cast<int32_t>((static_cast<uint32_t>(peak) * 13107u) >> 15);
          result_.sensor_lag_q8 = lag;
          if (m.dead_time_q8 < lag) m.dead_time_q8 = lag;
        } else {
          // 2.5–4 × D: a shorter lag. An FOPDT peaks at D, read 0.99–1.39 × on the bank at
          // σ 0.1 °C (fopdt-slow's flat peak the latest; up to 2.33 × at σ 0.3 over 10 noise
          // seeds), hotend40w-delay5 2.76–3.56 ×. The design then takes D from Tu. (A
          // tangent-timed probe's L̂ is D itself, not its peak: never late.)
          result_.late_peak = 2 * peak > 5 * m.dead_time_q8;
        }
      }
      return false;
    case 8:
      result_.ultimate.ku_q8 = ku_count_ > 0 ? static_cast<int32_t>(ku_sum_q8_ / ku_count_) : 0;
      return false;
    case 10:
    case 11:
    case 12:
    case 13:
      relay_lag_stage(s);
      return false;
    case 9:
      result_.ultimate.tu_q8 = ku_count_ > 0 ? static_cast<int32_t>(tu_sum_q8_ / ku_count_) : 0;
      // A hot start whose relay read a lag as a long T (case 6 took the loss's T): the relay's D
      // is the phase's leftover and reads short (hotend80w: 1.9 s for a 4.6 s lag). With K and T
      // known, the relay's amplitude gives the lag (relay_lag_stage, steps 10–13); not on a
      // response that outlasted the history (seed000-5 after it: 3.9 → 5.0 °C over). Every other
      // tune ends here, in as many steps as before.
      if (hot_start_ && !long_response() && 2 * v.a_hi > 3 * m.time_constant_q8) return false;
      // fall through
    default:
      m.rise_q8 = v.k_q8;
      result_.ambient_q8 = ambient_q8_;
      result_.hot_start = hot_start_;
      result_.held_gain = held_start();
      result_.unsure = untrusted_;
      result_.noise_q8 = noise_n_ >= 16 ? noise_q8_ : AutotuneResult::kNoiseUnmeasured;
      // The fit's two lags where its K agrees with the relay's within 1/8 (a record two lags do
      // not describe fits K off) and τ1/10 ≤ τ2 < τ1/2 (the range design_from_tune's two-point
      // FOPDT covers; at τ1 = 2·τ2 the design leaves the two-lag law), τ2 within M307's D.
      // seed000-4 (host rig, σ 0.02 °C): τ 520–527/194–196 s for the plant's 521/176; seed000-5
      // τ 1,164–1,181/121–123 s for 1,176/102 (design_from_tune keeps its state feedback off the
      // two-lag law: τ2 < τ1/5).
      // (x[0] = K may be anything: compared without a product that could overflow.)
      if (f.x[2] > 0 && 2 * f.x[2] < f.x[1] && f.x[1] <= 10 * f.x[2] && f.x[1] <= kModelMaxTimeConstantQ8 &&
          f.x[2] <= kModelMaxDeadTimeQ8 && f.x[0] > 0 && f.x[0] < 2 * v.k_q8 && abs32(f.x[0] - v.k_q8) <= v.k_q8 / 8) {
        result_.first_lag_q8 = f.x[1];
        result_.second_lag_q8 = f.x[2];
      }
      return true;
  }
}

}  // namespace control

// On-board identification for M303 (issue 7): a state machine stepped once per control period
// that heats the hotend, approaches the target without overshoot, runs a biased relay
// oscillation around it, holds it with the part fan on, and identifies the M307 model (static
// gain, time constant, dead time, fan loss) plus Marlin's Ku/Tu (from the relay cycles).
// Integer-only, portable (AVR and host), no heap; per-step cost estimates in autotune.cpp.
//
// Phases:
//   cool      heater off while too hot (or until a hot hotend visibly decays: its baseline)
//   baseline  heater off, 3 s: start temperature, its drift (decay rate when hot), ambient, and
//             the reading noise (measured on until the probe's response shows), which widens the
//             probe's detection and peak thresholds, the relay's hysteresis and the trend guard's
//             dead band
//   probe     full power, at most as long as a 20 °C/s hotend could take without reaching the
//             target, then either (lag-type hotend: response seen and steepening) heat on until
//             the slope is steady — S and the tangent's dead time — or heater off until the
//             response peaks and decays: S, the cut-to-peak time L̂ (the FOPDT's dead time) and
//             the loss rate 1/T; a cold peak that decays fast (a dead time, maybe behind a
//             thermistor lag) also waits for its tail, where the block's own τ1 is left, and
//             takes S, 1/T and L̂ from the FOPDT the tail and the pulse's area give (tail_stage;
//             compute: C)
//   approach  Smith predictor (FOPDT model S, L̂, 1/T, anchored to the reading) with a P law
//             around the model's steady duty; 1/T learnt on line (slope decline at full power,
//             model-vs-reading slope when the duty is steady); then the fan part starts here too.
//             After a cold cut probe with a sharp peak (L̂ to the tick, the predictor's delay
//             interpolated between bins) or a tail-timed one: deadbeat (full power until the
//             undelayed model is a bin's heat from the target), then twice the slow law's gain
//             (after a tail-timed one with the anchor and the predictor's offset held until the
//             deadbeat's ramp has passed through a lagged reading). A cut probe that
//             peaked late against its response D (a sensor lag, quiet sensor): D + (L̂ − D)/2.5.
//             A cold tangent probe too short to learn the loss at full power: 1/T learnt near the
//             target at ¼ per bin, ū's own steps not counted as duty changes, the heat in flight
//             behind the measured lag taken, and no hand-over while that learning still moves.
//             A hot start whose pulse read the full-power rate over 1.5 × low (a sensor lag it
//             missed): the reading's trend guard, as on an untrusted model
//             A hot start after a steady hold (start()'s hold_gain_q8: control/steady_hold.h): ū
//             from the hold's K, S at least K/T at the hand-over, S re-learnt at full power as
//             ẏ·K/(K − rise) (stage 10), and one more probe from a new baseline if it saw nothing
//   relay     biased relay (levels bias ± d, hysteresis ±0.2 °C on a 4-reading mean, wider on a
//             noisy sensor; with a trusted model no half shorter than L̂/2, or L̂ on a
//             dead-time hotend read through σ > 0.3 °C noise while within 2 °C) around the
//             target; bias = last cycle's mean duty, d for ±1.5 °C, a drifting relay re-biased
//             from its drift; one settling cycle, then max(2, C − 3) measured. No settling cycle
//             after an approach that settled (deadbeat or lag-type): a first low half ≥ L̂, and d
//             kept from then on. A bias under the smallest d (an approach held with the heater
//             off): levels 0 and 2d, then levels 0 and the first nudge's ū, in a settling cycle.
//             None at all (settled_hold) on a cold dead-time FOPDT hotend whose probe (a sharp
//             peak, or a flat one timed by its ramp's tangent) led a deadbeat approach that
//             settled (window L̂ + 2 bins ≥ C/5, C ≤ 5): the settled window's delay-aligned duty
//             gives K, the probe C and D = L̂; no Ku/Tu (0)
//   fan step  part fan at 100 %, the heater held open loop at the last relay cycle's mean duty
//             (after a settled hold: the approach's smoothed duty)
//             (the reading can only fall); from L̂ + 2 bins on (2 L̂ + 2 lag-type) a window of
//             ⌈C/2⌉ × (L̂/2 + 4) bins, ended once the reading fell 8 °C: its mean rise and its
//             fall give the duty that holds the rise with the fan, ū_F = u − ẏ/S
//   compute   K from mean temperature / mean duty; T and L from the relay's asymmetric-FOPDT
//             formulas, the reading noise's lift first taken off each cycle's extremes and
//             switch levels (lag-type hotends: T = τ1 + τ2 − the tangent's dead time, τ1 + τ2 from
//             a fit of K·t − ∫y = Σ·y + Π·ẏ at two heat-up points (else the heat-up slope), L from the relay amplitude;
//             a cold cut probe: T = p/ln(K/(K − peak)) from its pulse where it agrees within 20 %,
//             and its tail's T where over 1/16 shorter than the C chosen, the tail's K/T the fan
//             step's S where over 1/16 steeper than the probe's);
//             F = K·ū_F/rise − 1 from the fan step; K corrected for the relay's drift
//             (K·ū = rise + T·ẏ). A hot start: T from the first cool-down's decay where the
//             relay's T is within 4/3 of it (then also S = K/T for F), else the loss's T (never
//             above the decay's), and there the sensor lag τ from the relay's amplitude,
//             K/(ωT·√(1 + ω²τ²)) = 1/Ku, as D where longer; one small piece per step (≈ 122 steps)
// The slow logic runs in pieces of at most one 32-bit division each, one piece per step, so that
// every step() stays cheap on AVR (see the cost notes at the top of autotune.cpp).
#pragma once

#include <stdint.h>

#include "control/feedforward.h"
#include "control/fixed_math.h"
#include "control/lag_fit.h"

namespace control {

enum class AutotuneState : uint8_t { kIdle, kRunning, kFinished, kFailed };

enum class AutotuneFailure : uint8_t {
  kNone,
  kBadParameters,   // start() refused its arguments
  kTooHot,          // a reading above target + 25 °C: heater off at once
  kTimeout,         // longer than the time limit
  kNoHeating,       // full-power pulses raised the temperature by less than 0.5 °C
  kNoOscillation,   // the relay stopped switching (no crossing for far longer than expected)
  kAborted,         // abort()
};

// What a step produced besides the duty, for the G-code layer to print.
enum class AutotuneEvent : uint8_t {
  kNone,
  kCycle,     // a relay cycle completed: cycle() holds Marlin's " bias: d: min: max:" values
  kUltimate,  // after a cycle from the second on: ultimate() holds " Ku: Tu:"
  kResult,    // finished: result() holds the model
};

struct AutotuneOutput {
  uint16_t duty_q16;  // heater duty for the next period, 65535 = 100 %
  uint8_t fan_duty;   // part fan 0..255
  AutotuneState state;
  AutotuneFailure failure;
  AutotuneEvent event;
};

// One relay cycle as Marlin prints it: levels on the 0..255 scale, extremes in °C × 256.
struct AutotuneCycle {
  uint8_t bias;  // middle of the relay levels
  uint8_t d;     // half their difference
  int32_t min_q8;
  int32_t max_q8;
};

// Åström–Hägglund from the last cycle: Ku = 4d/(π·a) (0..255 output per °C), Tu = period.
struct AutotuneUltimate {
  int32_t ku_q8;
  int32_t tu_q8;  // s × 256
};

struct AutotuneResult {
  HotendModel model;        // M307 A C D F
  int32_t sensor_lag_q8;    // the heat-up tangent's dead time when the relay saw a lag (s × 256;
                            // model D is then the two-point fit's), 0 otherwise
  AutotuneUltimate ultimate;  // averaged over the measured no-fan cycles; 0 when the settled
                              // approach replaced the relay (Autotune::settled_hold)
  int32_t ambient_q8;       // the ambient A is counted from
  bool hot_start;           // true when the tune started above ambient + 15 °C
  bool unsure;              // the probe's response outlasted the model history (seed000): a
                            // model to control with, not one to bound the heater tightly by
  bool late_peak;           // a cold cut probe peaked 2.5–4 × the relay's D after the cut: a lag
                            // the relay's FOPDT folded into too short a D (hotend40w-delay5)
  uint16_t noise_q8;        // reading noise σ measured before the probe's response (°C × 256),
                            // kNoiseUnmeasured when that came within 16 readings
  // An unsure cold tune whose whole record fits two lags (Autotune::LagFit): τ1 and τ2 (s × 256;
  // model stays the relay's FOPDT), 0 otherwise.
  int32_t first_lag_q8, second_lag_q8;
  bool held_gain;           // a hot start that took its steady duty from the hold's K (start())
  static constexpr uint16_t kNoiseUnmeasured = 0xFFFF;
};

class Autotune {
 public:
  static constexpr int32_t kMeasureAmbient = INT32_MIN;  // start(): take the cold reading
  static constexpr int32_t kDefaultAmbientQ8 = 25L * 256;
  static constexpr int32_t kTooHotMarginQ8 = 25L * 256;
  static constexpr uint8_t kMinCycles = 3;
  static constexpr uint8_t kMaxCycles = 20;
  static constexpr uint8_t kMaxStoredCycles = 6;  // cycles kept for the T/L fit (the last ones)
  static constexpr uint8_t kRingBins = 72;        // duty history: ≥ the longest horizon, in bins
  static constexpr uint8_t kTicksPerBin = 8;      // 1.024 s at 128 ms
  // Reading noise σ above 0.3 °C (Q8; the estimate reads σ 0.3 as ≈ 0.27): a noisy sensor, on
  // which a dead-time hotend's relay halves last at least L̂ and M303 says so.
  static constexpr uint16_t kNoisyQ8 = 76;
  // Samples the two-lag fit needs (one per ~5 bins at most): seed000's tunes give ~400.
  static constexpr uint16_t kMinFitSamples = 100;
  // The fit's integrals stay within int32 for 8,000 bins (8,192 s at 128 ms; seed000's tunes
  // take ~2,700 s); past them it is dropped.
  static constexpr uint32_t kFitMaxTicks = 8000UL * kTicksPerBin;

  constexpr Autotune() = default;

  // Period of step() in ms (10..2000); timeout in s (default 30 min). Once the probe has measured
  // the response time L̂ the limit grows to (cycles in total + 4) × 6 L̂ if that is longer, up to
  // 4 × the configured one (slow hotends: seed000's heat-up alone takes 25 min).
  void configure(uint16_t period_ms, uint16_t timeout_s = 1800);

  // Starts a tune (false, and state kFailed/kBadParameters, if an argument is out of range):
  // target 50..275 °C, cycles 3..20, ambient_q8 = kMeasureAmbient to take the reading at start
  // when the hotend is cold (else 25 °C is assumed), or the ambient in °C × 256. hold_gain_q8:
  // the static gain K (°C × 256 per unit duty, from 25 °C) of a steady hold before the tune
  // (control/steady_hold.h), 0 if none: a hot start then takes its steady duty ū from it.
  bool start(int32_t target_q8, uint8_t cycles, bool measure_fan, int32_t ambient_q8 = kMeasureAmbient,
             int32_t hold_gain_q8 = 0);

  // Heater off, state kFailed/kAborted.
  void abort();

  // One control period with the thermistor reading (°C × 256).
  AutotuneOutput step(int32_t measured_q8);

  AutotuneState state() const { return state_; }
  AutotuneFailure failure() const { return failure_; }
  const AutotuneCycle& cycle() const { return cycle_; }
  const AutotuneUltimate& ultimate() const { return ultimate_; }
  const AutotuneResult& result() const { return result_; }

  // For tests and diagnostics.
  enum class Phase : uint8_t { kIdle, kCool, kBaseline, kProbe, kApproach, kRelay, kCompute, kDone, kFan };
  Phase phase() const { return phase_; }
  uint32_t elapsed_ticks() const { return tick_; }
  int32_t slope_q8() const { return slope_q8_; }          // S: °C×256 per bin at full duty
  int32_t horizon_ticks() const { return horizon_ticks_; }  // L̂
  uint16_t inv_t_q16() const { return inv_t_q16_; }         // 1/T per bin, Q16
  uint8_t overruns() const { return overruns_; }  // bin logic not finished within its bin (0)
  uint16_t noise_q8() const { return noise_q8_; }  // reading noise σ measured so far (°C × 256)
  bool hot_start() const { return hot_start_; }  // started above ambient + 15 °C (known after 3 bins)
  bool untrusted() const { return untrusted_; }     // the probe's model is not trusted (trend guard)
  uint8_t approach_law() const { return appr_.landed; }  // 0 deadbeat, 1 landed, 2 (3) the slow law (after a flat probe's deadbeat), 4 landed after a tangent- or tail-timed one
  bool lag_probe() const { return appr_.lag_probe; }

 private:
  struct StoredCycle {
    uint16_t u_hi_q16, u_lo_q16;
    int16_t max_q8, min_q8;        // relative to the target
    int16_t switch_hi_q8, switch_lo_q8;  // filtered reading at the two switches, rel. target
    uint16_t t_hi, t_lo;           // ticks
  };

  void fail(AutotuneFailure why);
  void enter(Phase p);
  void bin_end();            // the tick a bin completes: its means and histories only
  uint8_t bin_stage(uint8_t stage);  // one piece of the bin's slow logic; the next stage or 0
  uint8_t baseline_stage(uint8_t stage);
  uint8_t probe_stage(uint8_t stage);
  void heat_sample(uint16_t k, int32_t slope);
  void lag_fit_stage();
  void flight_stage();
  int32_t lag_sigma_q6(int32_t k_q8) const;
  uint8_t begin_stage(uint8_t stage);
  uint8_t approach_stage(uint8_t stage);
  uint8_t relearn_slope(int32_t s_full);
  uint8_t relay_stage(uint8_t stage);
  void fan_stage();
  void enter_compute();
  void settled_window();
  bool settled_hold();
  void end_nofan();
  uint16_t fan_wait_bins() const;
  uint16_t fan_span_bins() const;
  void model_bin();
  void model_anchor();
  void start_probe();
  int32_t steady_from_model() const;
  uint8_t approach_tau() const;  // the approach's closed-loop time constant in bins
  void set_approach_gain();
  uint32_t seed_history(uint8_t on, uint16_t a_q16);
  void extend_timeout();
  int32_t trend_q8(uint8_t sigma_q4) const;
  void measure_noise(int32_t y);
  int32_t noise_floor(int32_t fixed_q8, uint8_t sigma_q4) const;
  void set_levels();
  bool relay_tick(int32_t yf, int32_t y);  // true when a cycle ended
  void end_cycle(uint16_t t_lo);
  uint8_t cycle_stage(uint8_t stage);
  bool compute_chunk();      // one piece of the final arithmetic; true when done
  bool long_response() const;           // L̂ outlasts the model history (untrusted, fit used)
  void fit_bin();                        // bin_end: the fit's integrals and its next sample
  uint8_t fit_stage(uint8_t stage);      // one product of the latched sample into the sums
  uint8_t fit_solve(uint8_t stage);      // one piece of the fit's solution (compute, first)
  int32_t seconds_q8(uint16_t ticks) const;
  uint32_t ticks_from_s(uint16_t s) const;
  static uint32_t clamp_half_ticks(uint32_t ticks);
  int32_t model_ago(uint8_t bins) const;
  int32_t model_delayed() const;
  // A cold cut probe whose L̂ is a dead time, not the cut-to-peak time: a flat peak's ramp's tangent
  // (probe stage 5), or the tail's FOPDT (tail_stage, a sharp peak's too).
  bool tangent_timed() const { return !probe_.continuous && probe_.max_tick == 0 && probe_.peak_bin == 0; }
  // One whose S, 1/T and L̂ came from its tail (tail_stage; lag_q4 then holds the tail's 1/T).
  bool tail_timed() const { return tangent_timed() && probe_tail() && probe_.lag_q4 != 0; }
  // The tail fell by over 1/8 (its ln is then within ~1 % at σ 0.1 °C on a 40 °C pulse) and still
  // stood at over a quarter of the peak (not noise on a pulse that has gone): a/b in (8/7, 4].
  bool tail_fell() const { return probe_.fit_q_q8 - probe_.fit_r_q8 > probe_.fit_q_q8 >> 3 && probe_.fit_r_q8 > probe_.dev_peak_q8 >> 1; }
  uint8_t tail_stage(uint8_t stage);
  bool ramp_in_reading() const;
  uint32_t pulse_loss_factor_q16(uint16_t inv_t_q16) const;
  bool sharp_peak() const;
  int32_t slope4_q8() const;
  void push_bin(int16_t model_entry);
  int32_t heat_q8(uint16_t duty_q8) const;
  uint8_t duty_ago(uint8_t bins) const;
  uint8_t ring_index(uint8_t bins) const;

  // Hot scalars first: avr-gcc reaches members at offsets < 64 with one instruction (LDD/STD;
  // beyond, a pointer adjustment each time). Which ones sit here was measured: pending_q8_,
  // hot_start_, untrusted_ and the probe's maximum in place of model_q8_ and cyc_sum_duty_ saved
  // 138 B of flash.
  AutotuneState state_ = AutotuneState::kIdle;
  AutotuneFailure failure_ = AutotuneFailure::kNone;
  Phase phase_ = Phase::kIdle;
  AutotuneEvent event_ = AutotuneEvent::kNone;
  uint8_t stage_ = 0;          // next piece of the bin logic (0: none pending)
  uint8_t cycle_stage_ = 0;    // next piece of a relay cycle's end (0: none pending)
  uint8_t bin_ticks_ = 0;
  uint8_t fan_ = 0;
  uint16_t duty_q16_ = 0;
  uint16_t half_ticks_ = 0;
  int32_t slope_q8_ = 0;        // S: rise per bin at 100 % (°C × 256)
  uint16_t inv_t_q16_ = 0;      // loss rate 1/T per bin, Q16
  uint8_t horizon_bins_ = 0;
  int32_t pending_q8_ = 0;      // a value carried from one stage to the next (the fan step: its
                                // window's first bin mean, then its change over the window)
  int32_t horizon_ticks_ = 0;   // L̂
  int32_t target_q8_ = 0;
  int32_t ambient_q8_ = 0;  // (kDefaultAmbientQ8 from start() unless measured or given)
  uint16_t bin_duty_sum_ = 0;  // Σ duty q8 over the bin (≤ 8·256)
  int32_t y_bin_q8_ = 0;       // last completed bin mean
  bool relay_hi_ = false;
  bool heater_on_ = false;
  bool probe_pending_ = false;  // start the probe at the next bin boundary
  bool hot_start_ = false;
  // The probe's model cannot be trusted (cut-to-peak time beyond the history, or no clean peak):
  // the approach and the relay then also keep the reading's own
  // trend over guard_bins_ below the target (+ a margin in the relay): slower, never above S + 5.
  bool untrusted_ = false;
  uint8_t yf_head_ = 0;
  uint8_t ring_head_ = 0;
  uint16_t bias_q16_ = 0;
  uint16_t d_q16_ = 0;
  int32_t cyc_min_q8_ = 0, cyc_max_q8_ = 0;
  // Cool phase: the reading it started at. From the probe on (the cool phase is over): the
  // highest reading after the pulse's cut, then (cut probe) its height above the baseline.
  union {
    int32_t cool_ref_q8_ = 0;
    int32_t probe_max_q8_;
  };
  int32_t cyc_sum_dev_ = 0;     // Σ (y − target) over the cycle's ticks (q8)
  uint16_t last_bin_duty_q8_ = 0;  // mean duty of the last bin, 256 = 100 %
  uint32_t cyc_sum_duty_ = 0;   // Σ duty q16 over the cycle's ticks

  int32_t bin_sum_q8_ = 0;
  uint32_t tick_ = 0;
  uint16_t probe_ticks_ = 0;
  uint16_t bins_ = 0;          // completed bins in this phase

  // Configuration.
  uint16_t period_ms_ = 0;  // 0: not configured (128 ms). All defaults 0: the object is .bss, not .data
  uint32_t timeout_ticks_ = 0;
  bool ambient_given_ = false;
  uint8_t cycles_ = 0;
  bool measure_fan_ = false;
  uint16_t t6_ = 0, t40_ = 0, t60_ = 0, t90_ = 0, t600_ = 0;  // ticks in 6, 40, 60, 90, 600 s
                                                             // (t600_: ≥ 12 L̂ after the probe)
  uint32_t tick_s_whole_ = 0;  // s × 256 per tick: whole and Q16 fraction (seconds_q8)
  uint16_t tick_s_frac_ = 0;

  // Bin averaging and the duty history.
  int32_t y_prev_q8_ = 0;      // the bin before the last
  int32_t y_prev2_q8_ = 0;
  int32_t y_hist_q8_[4] = {};      // bin means 1..4 bins ago (4-bin slope)
  int32_t yf_ring_[4] = {};    // last 4 readings (relay filter)

  // Baseline / probe.
  int32_t y0_q8_ = 0;
  struct Probe {  // reached through near() where used most
    int32_t base_rise_q8;   // predicted baseline, relative to ambient
    uint16_t base_rate_q16;  // baseline decay per bin, Q16 (hot start)
    uint16_t on_ticks;
    uint16_t cap_ticks;     // energy cap of the probe's pulse
    uint16_t off_tick;      // tick (since probe start) the pulse ended
    bool extend;        // pulse extended past the cap (response seen, still steepening)
    bool detected;
    uint16_t det_bin;
    int32_t dev_q8;
    int32_t dev_prev_q8;
    int32_t dev_prev2_q8;
    int32_t slope_max_q8;
    uint16_t slope_max_bin;
    int32_t slope_max_dev_q8;  // deviation at the centre of the steepest window
    bool continuous;
    int32_t max_centre_tick;
    int32_t dev_peak_q8;
    uint16_t peak_bin;
    bool peaked;
    int32_t y_peak_q8;      // the peak bin's reading; tail_stage: T (bins × 256) once past stage 3
    int32_t y_after_q8;     // the bin after the peak's; tail_stage: ln(a/b), S, then the peak's lateness against L (ticks)
    uint8_t retries;
    uint16_t max_tick;       // probe tick of the highest reading after the cut (0: a flat peak)
    int32_t slope_rise_q8;   // rise at the centre of the steepest heat-up window (cut probe: its smoothed peak; tail_stage: S·on, then X)
    int32_t area_q8;         // Σ dev over bins 1..k−2 (°C × 256 × bins): the heat-up's integral, a cut pulse's area
    // The tangent path's lag fit (lag_fit_stage): Σ = τ1 + τ2 = (K·p − q)/r once K is known;
    // r = 0: none. A cut probe's tail instead (probe_stage): the window (bins, 0: no tail) and
    // two 2-bin sums of the rise (°C × 256), at 3 and 4 windows after the peak.
    int32_t fit_p_q6;        // bins × 64
    int32_t fit_q_q8;        // °C × 256 × bins
    int32_t fit_r_q8;        // °C × 256
    uint16_t lag_q4;         // the heat-up's lag τ (flight_stage), bins × 16; 0: not measured yet. A cut probe's
                             // tail: its 1/T per bin (Q16) where tail_stage took its model, else 0
  };
  // A point of the heat-up at full power (bin centre, in bins since the pulse began; the tangent
  // path's lag fit): its rise above the baseline, slope per bin and integral since the pulse began.
  struct HeatSample {
    int32_t dev_q8, slope_q8, area_q8;
    uint8_t centre;  // 0: none
  };
  const HeatSample& earlier_heat(uint16_t ca) const;  // lag_fit_stage's and flight_stage's sample b
  Probe probe_ = {};
  int32_t start_q8_ = 0;       // reading at start()
  bool cooled_ = false;        // a hot start has shown its decay
  // A hot start after a hold whose probe saw nothing after its retries cools on and probes once
  // more, from a new baseline (the decay it drifted on hid the few-tick pulses: heavy-slow, seed000).
  bool probe_again_ = false;
  uint16_t hold_gain_q4_ = 0;  // start()'s hold_gain_q8 in °C × 16 (0: none; 2 B of RAM)
  bool held_start() const { return hot_start_ && hold_gain_q4_ != 0; }  // a hot start after a hold
  // A cold cut probe read its tail (probe_stage; its rises in the lag fit's unused figures).
  bool probe_tail() const { return !hot_start_ && !probe_.continuous && probe_.fit_r_q8 > 0; }
  int32_t fan_slope_q8(int32_t k_q8, int32_t relay_t_q8) const;
  void relay_lag_stage(uint8_t s);
  void note_decay();
  void decay_step(uint8_t s);
  static constexpr uint8_t kCoolDecaySteps = 3;  // the compute's first steps on a hot start (decay_step)
  // Reading noise, measured while nothing but noise moves the reading (baseline, cooling, the
  // probe until its response shows): Σ|second difference| over noise_n_ readings, and the σ
  // it gives (°C × 256). The probe's thresholds, the relay's hysteresis and the trend guard's
  // dead band scale with it (noise_floor()).
  uint16_t noise_sum_ = 0;
  uint8_t noise_n_ = 0;
  uint16_t noise_q8_ = 0;

  // Model for the approach.
  int32_t offset_q8_ = 0;
  struct Approach {  // reached through near() where used most
    int32_t gain_q8;         // approach P gain: duty_q16 per temp_q8, × 256
    int32_t steady_q16;      // ū: steady duty estimate (integral part)
    uint8_t settled_bins;
    uint8_t near_bins;       // bins within 2 °C of the target (a stalled approach)
    uint8_t landed;          // 0 deadbeat (trusted cut probe's first approach), 1 landed, 2 the slow law,
                             // 3 the slow law after the deadbeat on a flat probe's model (stage 9 rebuilds it),
                             // 4 landed after the deadbeat on a tangent- or tail-timed probe's model (L̂ to the
                             // tick: the model read at L̂, the landed gain, a ±1 °C settled window later)
    int32_t ref_rise_q8;
    int32_t ref_slope_q8;     // loss learning: rise where the slope S was measured
    uint8_t loss_estimates;   // loss learning at full power: estimates so far (averaged)
    uint8_t full_bins;       // consecutive bins at 100 % in the approach
    int32_t duty_avg_q16;    // smoothed approach duty (relay bias)
    // The model's history before the approach, generated one entry per bin as it is first read
    // (instead of all L̂ entries at once): entry j bins before the approach began.
    int32_t fill_x_q8;
    uint8_t fill_j;          // entries j ≥ fill_j written
    uint8_t fill_on;         // the last fill_on bins were at full power
    uint16_t fill_a_q16;     // 1/T the history runs with
    uint8_t fill_head;       // ring_head_ when the approach began
    uint8_t crossings;
    uint8_t steady_bins;     // bins the duty has stayed near steady_ref
    int16_t steady_ref;
    int8_t side;
    bool lag_probe;          // a cold cut probe that peaked late against its response (a sensor lag)
    uint8_t bins;            // the approach's response time in bins: L̂, or a lag probe's (2L̂ + 3D)/5
    uint8_t det_bins;        // D: the probe's pulse-to-response time in bins (after a tail-timed landing:
                             // the approach bin the ramp has passed through the reading by; 0 until set)
    int32_t det_flight_q8;   // 3/5 of the model's rise over the last D bins (stage 1 for stage 6); after a
                             // tail-timed landing: the reading's offset from the model then (model_anchor)
    bool overshot;           // the reading went 1 °C past the target (no relay without a settling cycle)
    bool near_only;          // a trusted tangent probe's loss, not yet learnt at full power (stage 3 learns it)
    bool unlearnt;           // this bin's loss learning waited on a moving duty or moved 1/T by over 1/32 of itself
    bool blunted;            // a hot start's pulse read under ⅔ of the full-power rate (a missed lag): trend guard
    uint16_t lag_q4;         // a continuous probe's measured lag where it is over 1.5 × L̂ (bins × 16), else 0
  };
  Approach appr_ = {};
  // The settled window's first half in bins (L̂ + 2 bins in all): where settled_window snapshots
  // its drift sum and settled_hold splits the window's ticks; the two must agree.
  static uint8_t hold_half_bins(const Approach& ap);
  int32_t model_q8_ = 0;        // Smith predictor model state (undelayed rise)
  bool guard_off_ = false;      // relay: heater off while the trend would carry the reading too high
  bool bias_unknown_ = false;   // relay: the bias said nothing of the steady duty (set_levels) until the next nudge
  uint8_t guard_bins_ = 0;

  // Relay.
  uint16_t longest_half_ = 0;
  uint16_t last_nudge_ = 0;
  uint16_t t_hi_ = 0;
  int32_t sw_hi_q8_ = 0, sw_lo_q8_ = 0;
  int32_t stall_ref_q8_ = 0;      // reading at the half's switch or its last nudge (stall test)
  uint16_t period_ticks_ = 0;    // the completed cycle's period (its end's stages)
  int32_t cyc_a_q8_ = 0;         // ... its half amplitude
  uint32_t cyc_duty_done_ = 0;   // ... its Σ duty
  uint8_t cycle_index_ = 0;     // completed relay cycles (the settling one included)
  uint8_t settling_cycles_ = 0;  // relay cycles before the measured ones (0: the approach settled)
  uint8_t nofan_measure_ = 0;
  uint16_t inv_t_nofan_q16_ = 0;  // 1/T before the fan came on
  uint16_t fan_span_ = 0;         // the fan step's window: bins from its first to its last
  bool started_cycle_ = false;
  int32_t sum_dev_[2] = {};     // Σ (y − target) per tick over measured cycles, [0] no fan, [1] fan
  uint32_t sum_duty_[2] = {};   // Σ duty q16 >> 4 per tick
  uint32_t sum_ticks_[2] = {};
  uint8_t stored_count_ = 0;
  int32_t first_dev_ = 0, last_dev_ = 0;  // Σ (y − target) of the first / last measured cycle
  uint16_t first_ticks_ = 0, last_ticks_ = 0;
  uint32_t ku_sum_q8_ = 0, tu_sum_q8_ = 0;
  uint8_t ku_count_ = 0;

  // Compute.
  uint8_t compute_step_ = 0;
  uint8_t overruns_ = 0;        // bins whose stages were not done before the next (tests: 0)

  int16_t ring_[kRingBins] = {};  // Smith predictor: model's undelayed rise per bin − offset, °C × 16
  uint8_t duty_ring_[kRingBins] = {};  // mean duty per bin, 255 = 100 %
  // The relay's cycles; before the relay, the heat-up's two latest samples at power-of-two bins
  // (the probe's scratch: the relay stores its first cycle long after the hand-over read them).
  union Scratch {
    constexpr Scratch() : stored{} {}
    StoredCycle stored[kMaxStoredCycles];
    HeatSample heat[2];
  };
  Scratch scratch_;
  // compute_chunk's own figures, reached through one pointer (near() in autotune.cpp): their
  // place in the object then costs nothing.
  struct Compute {
    int32_t k_q8;  // K: °C × 256 per unit duty
    int32_t a_hi, a_lo, log, ln, lambda, mean_q8, duty;  // temporaries
    uint32_t theta;
    int32_t t_sum_q8, l_sum_q8;
    int32_t sigma_q6;  // τ1 + τ2 from the heat-up's lag fit, bins × 64 (0: none)
    uint8_t tl_count;
    // A hot start's first cool-down, or a cold cut probe's tail (decay_step): 1/T per bin, Q24,
    // and T, s × 256 (0: none).
    // (Within the fit's share of the union: no RAM of their own.)
    int32_t decay_q24, t_decay_q8;
  };
  // Two-lag fit (control/lag_fit.h) where the probe's response outlasts the model history
  // (long_response(): seed000's higher-order hotends), cold starts only: samples from the
  // approach's and the relay's bins more than 30 °C above ambient (the fan off). Its sums share
  // the compute's storage: they are solved first (fit_solve), then the compute's are cleared.
  struct LagFit {
    int32_t iu_q8;     // ∫u since the probe: Σ bin duty (256 = 100 %), duty × 256 × bins
    int32_t iy_q4;     // ∫(y − ambient) since the probe, °C × 16 × bins
    int32_t su, sy, siy;  // 16 × the filtered ∫u, y − ambient (Q8) and ∫y
    // The latched sample in lag_fit_accumulate's scales (16 × the filtered ∫u, y and ∫y, the
    // filtered y's change × 2^16); once solved, K, τ1, τ2 (Q8: °C, s, s).
    int32_t x[4];
    uint16_t samples;
    uint8_t stage;     // next piece of the latched sample (fit_stage), 0: none pending
    uint8_t solve;     // last piece of fit_solve done, 0: not started, 0xFF: done (or skipped)
  };
  // A hot start's first cool-down (the heater off: past a dead time, an FOPDT's clean decay). Its
  // first point is the bin after the first one 1 °C below where the cool-down began; its last is
  // the baseline's (stage 2).
  struct CoolDecay {
    int32_t rise_a_q8;   // the first point's rise above ambient
    uint32_t tick_a;     // ... and its tick (0: none yet)
    int32_t rise_b_q8;   // the baseline's rise
    uint16_t bins;       // bins from the first point to the baseline's (0: none)
  };
  union FitOrDecay {  // a cold start's fit, or a hot start's decay (a hot start never fits)
    constexpr FitOrDecay() : fit{} {}
    LagFit fit;
    CoolDecay decay;
  };
  FitOrDecay fd_;
  static_assert(sizeof(CoolDecay) <= sizeof(LagFit), "a hot start's decay takes no RAM of its own");
  union ComputeStore {
    constexpr ComputeStore() : c{} {}
    Compute c;
    fixed_math::Scaled fit[kLagFitSums];
  };
  ComputeStore store_;
  static_assert(sizeof(Compute) <= sizeof(fixed_math::Scaled) * kLagFitSums, "the decay's figures take no RAM of their own");

  AutotuneCycle cycle_{0, 0, 0, 0};
  AutotuneUltimate ultimate_{0, 0};
  AutotuneResult result_{{0, 0, 0, 0}, 0, {0, 0}, 0, false, false, false, 0, 0, 0, false};
};

}  // namespace control

// On-board state-feedback design for the FOPDT model (see state_feedback_autodesign.h).
//
// The host design (design/state_feedback_design_impl.h) is general: matrix exponentials,
// Ackermann, a search over the closed-loop speed. For one state with dead time all of it has a
// closed form. Notation: K static gain (°C per unit duty), T time constant, τ dead time,
// h = N·128 ms the law period, D = ⌈τ/h⌉, f = D·h − τ, and
//   a = h/T, Φ = e^(−a), A = 1 − Φ;   ε = e^(−f/T), B = 1 − ε   (ε = 1, B = 0 when f = 0)
//   Γa = K(ε − Φ) = K(A − B),  Γb = K·B                         (ZOH with fractional delay)
// Controller pole λc = e^(−c) (c = h/T_cl), observer poles λo = e^(−o) (state), λb = e^(−β)
// (bias). With the fractional delay the host's controller model is ξ = [x; u[k−D]] with the
// second pole at 0 (deadbeat); Ackermann on it gives L̃ = [l1, l1·Γa/Φ], l1 = Φ(Φ−λc)/(K·A·ε),
// and the predictor over D − 1 periods folds into
//   h_j = (Φ − λc)·Φ^(j−1), j < D;   h_D = (Φ − λc)·Φ^(D−1)·(A − B)/(ε·A)
//   L_D = (Φ − λc)·Φ^D/(ε·A·K),     g_d = 1 + Σh,   M = (1 + Σh + L_D·K)/K
// (f = 0: ε = 1 and the same formulas are the plain predictor's). Current observer on [x; d̂]
// with Φo = [[Φ, K·A], [0, 1]], error dynamics eig(Φo − k·[1 0]·Φo) = {λo, λb}:
//   k_x = 1 − λo·λb/Φ = 1 − e^(−(o + β − a)),   k_d = (1 − λo)(1 − λb)/(K·A).
// Φ − λc = (1 − λc) − A: both computed as 1 − e^(−x) with relative precision, so the small
// differences of slow poles keep their digits.
//
// The pole rule is the host's for n = 1: T_cl = t_rise/16 with t_rise = T·ln(K/(K − 185 K))
// the full-power rise time (T when K ≤ 185 K), at least 2h. The host lowers the speed until the
// saturated nominal step overshoots ≤ 0.2 K; with one state and an exact predictor the
// saturated response is monotone, so the search always stops at its first step (the host test
// checks this over the model grid) and none is needed here. Observer: c·4, capped at 1/τ
// (τ > 2h) or 1/(2h); bias 1/max(T_cl/2, τ). A plant no slower than T_cl keeps its open-loop
// pole (Φ − λc = 0, no feedback; observer pole at the plant's).
//
// Numbers: fixed_math::Scaled (30-bit mantissa, binary exponent; the values span 1e-5..1e3),
// then the host quantiser's rules on them (choose_shift, rounding halves away from zero, M and
// g_d from the quantised numbers). The values live in a register file (Calc) addressed by slot
// number: each step of the design is then a call with four byte arguments. Passing the 6-byte
// values themselves through a large stack frame cost avr-gcc ~100 bytes of flash per operation
// (12.9 KB for this file) against ~16 here.
#include "control/state_feedback_autodesign.h"

#include "control/fixed_math.h"

namespace control {
namespace {

using fixed_math::Scaled;

constexpr int32_t kStepQ8 = 185L * 256;    // design step 25 → 210 °C (DesignOptions::step_k)
constexpr int32_t kAmbientQ8 = 25L * 256;  // the M307 model's ambient
constexpr uint8_t kMaxDecimation = 250;    // as the host's period search
constexpr uint32_t kSqrt2Q16x10 = 926819;  // 1.41421356 · 65536 · 10 (the host's constant)

// Register slots. Rows the quantiser takes as a whole (kRow*, kLaw*) are consecutive.
enum Slot : uint8_t {
  kZero, kOne, kHalf, kHeadroom,  // 0, 1, 1/2, 1.01 (the host's room for the final M, g_d)
  kGain, kGainP, kT1000,          // K, K/2^p, 1000·T_q8
  kA, kRateTau, kRise, kC, kO, kBeta, kT0, kT1,
  kPhi, kOneMinusPhi, kEps, kOneMinusEps, kGap, kLast,
  kRow0, kRow1, kRow2, kRow3,  // [Φ − 1, 0, Γa/2^p, Γb/2^p]
  kGainQ, kKx, kKd,
  kBig, kSumH, kTap, kOnePlusH, kLg,
  kLaw0, kLaw1, kLaw2,  // [L_D·2^p, 1.01·g_d, 1.01·M·2^p]
  kFan, kInv,
  kFopdtSlots
};

// The two-lag design's slots (design_two_lags below), after the shared constants 0..3.
enum LagSlot : uint8_t {
  kLagK = 4, kLagT1000, kLagD1000, kLagA1, kLagA2, kLagQ, kLagR, kAlpha, kBeta2, kBetaMinusAlpha, kLagF,
  kLagRow0, kLagRow1, kLagRow2, kLagRow3,  // [−α or −β, 0 or f, Γ/2^p, 0]
  kLagC, kLc1, kLc2, kLo1, kLo2, kLob, kU0, kU1, kU2, kPa, kPb, kP0, kM1, kM2, kLagKP,
  kLagLaw0, kLagLaw1, kLagLaw2, kLagLaw3,  // [L1·2^p, L2·2^p, 1.01, 1.01·M·2^p]
  kLagG1, kLagGainQ, kLagShare0, kLagShare1, kLagKx1, kLagKx2, kLagKd, kLagFan, kLagInv,
  kLagSlots
};

constexpr uint8_t kSlots = static_cast<uint8_t>(kLagSlots) > static_cast<uint8_t>(kFopdtSlots) ? static_cast<uint8_t>(kLagSlots) : static_cast<uint8_t>(kFopdtSlots);

enum Op : uint8_t { kAdd, kSub, kMul, kDiv, kMin, kLdexp, kExpNeg, kOneMinusExpNeg, kLn };

// Input scale: 2^p ≈ K (the host: p < 10 while 2^p·1.41421356 < K); exact for Q8 K
// (rise_q8 ≤ 2000 × 256, × 2560 < 2^31). noinline: inlined into both designs (20 B as a call).
__attribute__((noinline)) int8_t input_shift(int32_t rise_q8) {
  int8_t p = 0;
  while (p < 10 && (kSqrt2Q16x10 << p) < static_cast<uint32_t>(rise_q8) * 2560u) ++p;
  return p;
}

class Calc {
 public:
  Calc() {
    set(kOne, 1);
    set(kHalf, 1, -1);
    set(kHeadroom, 542245110, -29);  // 1.01 · 2^29
  }
  // Not inlined: every call site stays a few register loads and a call.
  __attribute__((noinline)) void set(uint8_t d, int32_t v, int16_t e = 0) { r_[d] = fixed_math::scaled(v, e); }
  // r[d] = r[a] op r[b]; kLdexp: r[a]·2^b (b as int8); kExpNeg / kOneMinusExpNeg of r[a].
  // b is a register only for the binary operations: for kLdexp it is the exponent (an int8
  // that may be negative), so r_[b] must not be read there (out of bounds).
  // The binary operations share one call (their 12 bytes of arguments are loaded once).
  __attribute__((noinline)) void op(uint8_t code, uint8_t d, uint8_t a, uint8_t b) {
    const Scaled x = r_[a];
    Scaled z;
    if (code < kMin) {
      Scaled (*f)(Scaled, Scaled) = fixed_math::add;
      if (code == kSub) f = fixed_math::sub;
      if (code == kMul) f = fixed_math::mul;
      if (code == kDiv) f = fixed_math::div;
      z = f(x, r_[b]);
    } else if (code == kMin) {
      z = less(b, a) ? r_[b] : x;
    } else if (code == kLdexp) {
      z = fixed_math::ldexp(x, static_cast<int8_t>(b));
    } else if (code == kLn) {
      z = fixed_math::ln(x);
    } else {
      z = fixed_math::exp_neg(x, code == kOneMinusExpNeg);
    }
    r_[d] = z;
  }
  void add(uint8_t d, uint8_t a, uint8_t b) { op(kAdd, d, a, b); }
  void sub(uint8_t d, uint8_t a, uint8_t b) { op(kSub, d, a, b); }
  void mul(uint8_t d, uint8_t a, uint8_t b) { op(kMul, d, a, b); }
  void div(uint8_t d, uint8_t a, uint8_t b) { op(kDiv, d, a, b); }
  void min(uint8_t d, uint8_t a, uint8_t b) { op(kMin, d, a, b); }
  void ldexp(uint8_t d, uint8_t a, int8_t n) { op(kLdexp, d, a, static_cast<uint8_t>(n)); }
  void copy(uint8_t d, uint8_t a) { op(kAdd, d, a, kZero); }
  void exp_neg(uint8_t d, uint8_t a) { op(kExpNeg, d, a, 0); }
  void one_minus_exp_neg(uint8_t d, uint8_t a) { op(kOneMinusExpNeg, d, a, 0); }
  void ln(uint8_t d, uint8_t a) { op(kLn, d, a, 0); }
  __attribute__((noinline)) bool less(uint8_t a, uint8_t b) const { return fixed_math::less(r_[a], r_[b]); }

  // design::quantize_row on slots first..first+count−1: the largest shift s <= max_shift with
  // (s − 16) a multiple of step and |v|·2^s + 1/2 < 32767 for every v (16 when all are 0), then
  // the mantissas rounded halves away from zero. False when no shift fits.
  __attribute__((noinline)) bool quantize(uint8_t first, uint8_t count, int8_t max_shift, uint8_t step,
                                          int16_t* out, uint8_t* shift) {
    Scaled big{0, 0};
    for (uint8_t i = first; i < first + count; ++i) {
      const Scaled v = r_[i].m < 0 ? fixed_math::neg(r_[i]) : r_[i];
      if (fixed_math::less(big, v)) big = v;
    }
    int8_t s = 16;
    if (big.m != 0) {
      const Scaled limit = fixed_math::scaled(65533);  // 2·(32767 − 1/2)
      // big < 2^(e+30): every s above −15 − e fails, so the search starts there (a step or two).
      const int16_t start = static_cast<int16_t>(-15 - big.e);
      s = start > max_shift ? max_shift : (start < 0 ? -1 : static_cast<int8_t>(start));
      for (; s >= 0; --s)
        if ((s + 48) % step == 0 && fixed_math::less(fixed_math::ldexp(big, static_cast<int16_t>(s + 1)), limit)) break;
      if (s < 0) return false;
    }
    *shift = static_cast<uint8_t>(s);
    for (uint8_t i = 0; i < count; ++i) out[i] = mantissa(first + i, *shift);
    return true;
  }
  int16_t mantissa(uint8_t a, uint8_t shift) const {
    return static_cast<int16_t>(fixed_math::round_scaled(r_[a], shift));
  }

  // Both designs' fan gain: (F/100)/K per kelvin · 2^(16+p)/(255·256), per °C Q8 × fan:
  // F_q8·2^(16+p)/(K_q8·6,528,000). t0, t1: scratch slots.
  void fan_gain(uint8_t d, uint8_t t0, uint8_t t1, const HotendModel& model, int8_t p) {
    set(d, model.fan_loss_pct_q8, static_cast<int16_t>(16 + p));
    set(t0, model.rise_q8);
    set(t1, 6528000);
    mul(t0, t0, t1);
    div(d, d, t0);
  }

 private:
  Scaled r_[kSlots] = {};
};

// The register file is the caller's (design_state_feedback_fopdt's) local: here it is reached
// through a pointer, and this frame keeps only small locals (avr-gcc: within Y+63, no pointer
// arithmetic per access; with the 240-byte array in this frame ~900 bytes of flash went to that).
// noclone: avr-gcc 5.4 with LTO clones this function for the constant period (constprop) and the
// clone's result came back false although every check passed (measured in simavr: the M303 tune
// reported "outside what the board designs" for models the host designs; the HIL runs now
// compare the board's M311 lines with this code compiled on the host).
__attribute__((noinline, noclone)) bool design(const HotendModel& model, uint16_t period_ms, bool paced,
                                               StateFeedbackConstants& k, Calc& c) {
  if (!hotend_model_valid(model) || period_ms == 0 || period_ms > 1000) return false;

  // Law period: the smallest N >= 2 with D <= kSfMaxDelay and N >= state_feedback_min_decimation(D)
  // (the host's loop from 2, started where D first fits: D <= 32 ⇔ τ <= 32·N·period).
  // Times in 1/32 ms: τ = dead_time_q8·1000/256 ms = dead_time_q8·125/32 ms, exact.
  const uint32_t dead32 = static_cast<uint32_t>(model.dead_time_q8) * 125u;  // <= 1.92e7
  const uint32_t per_call32 = static_cast<uint32_t>(period_ms) * 32u;        // <= 32,000
  uint32_t dec = (dead32 + kSfMaxDelay * per_call32 - 1) / (kSfMaxDelay * per_call32);
  if (dec < 2) dec = 2;
  uint32_t h32 = 0;  // law period, 1/32 ms (<= 250 · 32,000 = 8e6)
  uint8_t delay = 0;
  for (;; ++dec) {
    if (dec > kMaxDecimation) return false;
    h32 = dec * per_call32;
    delay = static_cast<uint8_t>((dead32 + h32 - 1) / h32);  // <= 32 from the start value of dec
    if (dec >= state_feedback_min_decimation(delay)) break;
  }
  const uint32_t frac32 = delay * h32 - dead32;  // f, in [0, h)
  const bool frac = frac32 != 0;

  const int8_t p = input_shift(model.rise_q8);

  k.n = 1;
  k.output_mask = 1;
  k.delay = delay;
  k.decimation = static_cast<uint8_t>(dec);
  k.input_shift = static_cast<uint8_t>(p);
  k.ambient_q8 = kAmbientQ8;

  c.set(kGain, model.rise_q8, -8);
  c.ldexp(kGainP, kGain, static_cast<int8_t>(-p));
  // h/T = h32/32,000 s ÷ T_q8/256 s = h32·8/(1000·T_q8); T_q8·1000 <= 9.2e8, h32·8 <= 6.4e7.
  c.set(kT1000, model.time_constant_q8 * 1000);
  c.set(kA, static_cast<int32_t>(h32 * 8));
  c.div(kA, kA, kT1000);
  c.set(kRateTau, static_cast<int32_t>(h32));  // h/τ
  c.set(kT0, static_cast<int32_t>(dead32));
  c.div(kRateTau, kRateTau, kT0);

  // Pole rule: c = h/T_cl = min(16·(h/T)/(t_rise/T), 1/2), t_rise/T = ln(K/(K − 185)) (1 if K <= 185).
  c.copy(kRise, kOne);
  if (model.rise_q8 > kStepQ8) {
    c.set(kRise, model.rise_q8);
    c.set(kT0, model.rise_q8 - kStepQ8);
    c.div(kRise, kRise, kT0);
    c.ln(kRise, kRise);
  }
  c.ldexp(kC, kA, 4);
  c.div(kC, kC, kRise);
  c.min(kC, kC, kHalf);
  if (paced && dead32 != 0) c.min(kC, kC, kRateTau);  // T_cl ≥ τ
  const bool slow = c.less(kA, kC);  // T > T_cl: sped up; else the open-loop pole stays
  c.copy(kO, kA);                    // observer (state): 4c, capped at h/τ (τ > 2h) or 1/2
  if (slow) {
    c.ldexp(kO, kC, 2);
    c.min(kO, kO, dead32 > 2 * h32 ? kRateTau : kHalf);
  }
  c.ldexp(kBeta, kC, 1);  // bias: h/max(T_cl/2, τ)
  if (dead32 != 0 && !c.less(kBeta, kRateTau)) c.copy(kBeta, kRateTau);

  // Discrete model: Φ, 1 − Φ; ε, 1 − ε; Φ − λc = (1 − λc) − (1 − Φ).
  c.exp_neg(kPhi, kA);
  c.one_minus_exp_neg(kOneMinusPhi, kA);
  c.copy(kEps, kOne);
  if (frac) {
    c.set(kT0, static_cast<int32_t>(frac32 * 8));  // f/T
    c.div(kT0, kT0, kT1000);
    c.exp_neg(kEps, kT0);
    c.one_minus_exp_neg(kOneMinusEps, kT0);
  }
  if (slow) {
    c.one_minus_exp_neg(kGap, kC);
    c.sub(kGap, kGap, kOneMinusPhi);
  }

  // Observer model row [Φ − 1, 0, K(A − B)/2^p, K·B/2^p], nibble-aligned shift <= 40.
  c.sub(kRow0, kZero, kOneMinusPhi);
  c.sub(kRow2, kOneMinusPhi, kOneMinusEps);
  c.mul(kRow2, kRow2, kGainP);
  c.mul(kRow3, kOneMinusEps, kGainP);
  int16_t m[4];
  if (!c.quantize(kRow0, 4, 40, 4, m, &k.phi_shift[0]) || m[0] >= 0) return false;
  k.phi_diag[0] = m[0];
  k.gamma_a[0] = m[2];
  k.gamma_b[0] = m[3];
  // DC gain of the quantised model: (Γa + Γb)/(1 − Φ) = (m2 + m3)·2^p/(−m0).
  c.set(kGainQ, static_cast<int32_t>(m[2]) + m[3], p);
  c.set(kT0, -static_cast<int32_t>(m[0]));
  c.div(kGainQ, kGainQ, kT0);

  // Observer gains, byte-aligned shifts: k_x = 1 − e^(−(o + β − a)), k_d = (1 − λo)(1 − λb)/(K·A).
  c.add(kT0, kO, kBeta);
  c.sub(kT0, kT0, kA);
  if (c.less(kT0, kZero)) {  // λo·λb > Φ: k_x = −(e^x − 1) = −(1 − e^(−x))/e^(−x), x = −(o + β − a)
    c.sub(kT0, kZero, kT0);
    c.one_minus_exp_neg(kKx, kT0);
    c.exp_neg(kT1, kT0);
    c.div(kKx, kKx, kT1);
    c.sub(kKx, kZero, kKx);
  } else {
    c.one_minus_exp_neg(kKx, kT0);
  }
  c.one_minus_exp_neg(kT0, kO);
  c.one_minus_exp_neg(kKd, kBeta);
  c.mul(kKd, kKd, kT0);
  c.ldexp(kKd, kKd, p);
  c.mul(kT0, kGain, kOneMinusPhi);
  c.div(kKd, kKd, kT0);
  if (!c.quantize(kKx, 1, 40, 8, &k.obs_gain[0], &k.obs_shift[0]) ||
      !c.quantize(kKd, 1, 40, 8, &k.obs_gain[1], &k.obs_shift[1]))
    return false;

  // Predictor taps h_j·2^p: a first pass for the row's largest value and Σh, a second for the
  // mantissas. The last tap carries the fractional delay's (A − B)/(ε·A).
  c.copy(kLast, kOne);
  if (frac) {
    c.sub(kLast, kOneMinusPhi, kOneMinusEps);
    c.mul(kT0, kEps, kOneMinusPhi);
    c.div(kLast, kLast, kT0);
  }
  int32_t fir_sum = 0;  // Σ mantissas, <= 32 · 32767
  for (uint8_t pass = 0; pass < 2; ++pass) {
    c.ldexp(kTap, kGap, p);
    for (uint8_t j = 1; j <= delay; ++j) {
      if (j == delay)
        c.mul(kT0, kTap, kLast);
      else
        c.copy(kT0, kTap);
      if (pass == 0) {
        if (c.less(kBig, kT0)) c.copy(kBig, kT0);
        c.add(kSumH, kSumH, kT0);
      } else {
        k.fir[j - 1] = c.mantissa(kT0, k.fir_shift);
        fir_sum += k.fir[j - 1];
      }
      c.mul(kTap, kTap, kPhi);  // after the loop: (Φ − λc)·Φ^D·2^p
    }
    if (pass == 0 && !c.quantize(kBig, 1, 46, 1, k.fir, &k.fir_shift)) return false;
  }
  c.set(kOnePlusH, fir_sum, static_cast<int16_t>(-(k.fir_shift + p)));  // quantised g_d
  c.add(kOnePlusH, kOnePlusH, kOne);

  // Law row [L_D·2^p, 1.01·g_d, 1.01·M·2^p] with the design's L_D = (Φ − λc)·Φ^D/(ε·A·K) and
  // M = (1 + Σh + L_D·K)/K; then L is rounded, M and g_d follow from the quantised numbers.
  c.mul(kT0, kEps, kOneMinusPhi);
  c.mul(kT0, kT0, kGain);
  c.div(kLaw0, kTap, kT0);
  c.mul(kLaw1, kOnePlusH, kHeadroom);
  c.ldexp(kLaw2, kSumH, static_cast<int8_t>(-p));
  c.add(kLaw2, kLaw2, kOne);
  c.ldexp(kLaw2, kLaw2, p);
  c.div(kLaw2, kLaw2, kGain);
  c.add(kLaw2, kLaw2, kLaw0);
  c.mul(kLaw2, kLaw2, kHeadroom);
  int16_t law[3];
  if (!c.quantize(kLaw0, 3, 46, 1, law, &k.ctrl_shift)) return false;
  k.fb_gain[0] = law[0];
  const int16_t shift = static_cast<int16_t>(k.ctrl_shift);
  c.set(kLg, law[0], static_cast<int16_t>(-(shift + p)));  // L_D·g of the quantised law
  c.mul(kLg, kLg, kGainQ);
  k.bias_gain = c.mantissa(kOnePlusH, k.ctrl_shift);
  c.add(kT0, kOnePlusH, kLg);
  c.div(kT0, kT0, kGainQ);
  c.ldexp(kT0, kT0, p);
  k.ff_gain = c.mantissa(kT0, k.ctrl_shift);

  c.fan_gain(kFan, kT0, kT1, model, p);
  // Steady state per kelvin of rise (one state: exactly 1) and 2^p / DC gain.
  c.set(kInv, 1, p);
  c.div(kInv, kInv, kGainQ);
  return c.quantize(kFan, 1, 46, 1, &k.fan_gain, &k.fan_shift) &&
         c.quantize(kOne, 1, 46, 1, &k.ss_share[0], &k.ss_share_shift) &&
         c.quantize(kInv, 1, 46, 1, &k.inv_gain, &k.inv_gain_shift) && state_feedback_constants_valid(k);
}

// The two-lag design (see design_state_feedback_two_lags in the header). Notation: K static gain,
// τ1 = C, τ2 = D (no dead time), h = 2·period, q = τ2/τ1, r = τ1/(τ1 − τ2),
//   α = 1 − e^(−h/τ1), β = 1 − e^(−h/τ2)    (Φ's eigenvalues e1 = 1 − α, e2 = 1 − β)
//   Φ = [[e1, 0], [f, e2]], f = r(β − α);  Γ = K·[α, r(α − qβ)]   (exact ZOH of two lags)
// Poles as complements ℓ = 1 − z (relative precision for slow poles). Placement by residues in
// Φ's eigenbasis (V = [[β − α, 0], [f, 1]]; its columns' outputs and Γ's coordinates are closed
// forms, so no ill-conditioned controllability matrix is formed):
//   m1 = (ℓ1 − α)(ℓ2 − α)/(Kα),  m2 = (ℓ1 − β)(ℓ2 − β)/((β − α)·K·β·q·r)
//   L = [m1/(β − α) − r·m2, m2],  M = ℓ1ℓ2/(αβK)
// and for the current observer on [x1; x2; d] (error dynamics eig(Φo − k·c), c = Co·Φo =
// [f, e2, Γ2]; Φo's eigenvectors [β − α, f, 0], [0, 1, 0], [K, K, 1]) with P(z) = Π(z − λo_j):
//   k_d = P(1)/(αβK),  k1 = P(1)/(αβ) − P(e1)/(α·e1·f),
//   k2 = P(1)/(αβ) − P(e1)/(α(β − α)e1) + P(e2)/(β(β − α)e2),   P(e_i) = Π(ℓo_j − α_i).
__attribute__((noinline, noclone)) bool design_two_lags(const HotendModel& model, uint16_t period_ms, uint8_t pace_tenths,
                                                        StateFeedbackConstants& k, Calc& c) {
  if (!hotend_model_valid(model) || period_ms == 0 || period_ms > 1000 || pace_tenths == 0) return false;
  // Two distinct lags, the second at most half the first (well apart: Φ's eigenvalues distinct,
  // and no cancellation beyond a few bits in α − qβ). D > 0 (Q8: at least 1/256 s).
  if (model.dead_time_q8 <= 0 || 2 * model.dead_time_q8 > model.time_constant_q8) return false;
  const uint32_t h32 = uint32_t{2} * period_ms * 32u;  // the law period (D = 0: decimation 2), 1/32 ms
  const int8_t p = input_shift(model.rise_q8);
  k.n = 2;
  k.output_mask = 2;  // y = x2, the thermistor
  k.delay = 0;
  k.decimation = 2;
  k.input_shift = static_cast<uint8_t>(p);
  k.ambient_q8 = kAmbientQ8;

  c.set(kLagK, model.rise_q8, -8);
  // h/τ = h32/32,000 s ÷ τ_q8/256 s = h32·8/(1000·τ_q8): C_q8·1000 ≤ 9.2e8, D_q8·1000 ≤ 1.6e8, h32·8 ≤ 512,000.
  c.set(kLagT1000, model.time_constant_q8 * 1000);
  c.set(kLagD1000, model.dead_time_q8 * 1000);
  c.set(kU0, static_cast<int32_t>(h32 * 8));
  c.div(kLagA1, kU0, kLagT1000);
  c.div(kLagA2, kU0, kLagD1000);
  c.div(kLagQ, kLagD1000, kLagT1000);
  c.sub(kU0, kOne, kLagQ);
  c.div(kLagR, kOne, kU0);
  c.one_minus_exp_neg(kAlpha, kLagA1);
  c.one_minus_exp_neg(kBeta2, kLagA2);
  c.sub(kBetaMinusAlpha, kBeta2, kAlpha);
  c.mul(kLagF, kLagR, kBetaMinusAlpha);

  // Observer model rows, nibble-aligned shifts <= 40 (as the host's quantiser).
  c.set(kLagKP, 1, static_cast<int16_t>(-p));
  c.mul(kLagKP, kLagKP, kLagK);  // K/2^p
  c.sub(kLagRow0, kZero, kAlpha);
  c.copy(kLagRow1, kZero);
  c.mul(kLagRow2, kAlpha, kLagKP);
  c.copy(kLagRow3, kZero);
  int16_t m[4];
  if (!c.quantize(kLagRow0, 4, 40, 4, m, &k.phi_shift[0]) || m[0] >= 0) return false;
  k.phi_diag[0] = m[0];
  k.gamma_a[0] = m[2];
  c.set(kLagG1, static_cast<int32_t>(m[2]), p);  // quantised steady state of x1 per unit input
  c.set(kU0, -static_cast<int32_t>(m[0]));
  c.div(kLagG1, kLagG1, kU0);
  c.sub(kLagRow0, kZero, kBeta2);
  c.copy(kLagRow1, kLagF);
  c.mul(kU0, kLagQ, kBeta2);  // Γ2/2^p = (K/2^p)·r·(α − qβ)
  c.sub(kU0, kAlpha, kU0);
  c.mul(kU0, kU0, kLagR);
  c.mul(kLagRow2, kU0, kLagKP);
  if (!c.quantize(kLagRow0, 4, 40, 4, m, &k.phi_shift[1]) || m[0] >= 0 || m[1] <= 0) return false;
  k.phi_diag[1] = m[0];
  k.phi_off[1] = m[1];
  k.gamma_a[1] = m[2];
  // g2 = (φ10·g1 + Γ2·2^p)/(1 − φ11) in mantissas (one shift): (m1·g1 + m2·2^p)/(−m0).
  c.set(kU0, m[1]);
  c.mul(kU0, kU0, kLagG1);
  c.set(kU1, m[2], p);
  c.add(kU0, kU0, kU1);
  c.set(kU1, -static_cast<int32_t>(m[0]));
  c.div(kLagGainQ, kU0, kU1);

  // Pole rule: c = h/T_cl = min(16·h/t_rise, h/(κ·τ2), 1/2); t_rise = τ1·ln(K·r/(K − 185)), the
  // two lags' asymptote (τ1 when K ≤ 185). κ = pace_tenths/10 (the header's kLagPace*).
  c.ldexp(kLagC, kLagA1, 4);
  if (model.rise_q8 > kStepQ8) {
    c.set(kU0, model.rise_q8 - kStepQ8, -8);
    c.div(kU0, kLagK, kU0);
    c.mul(kU0, kU0, kLagR);
    c.ln(kU0, kU0);
    c.div(kLagC, kLagC, kU0);
  }
  c.set(kU0, 10);
  c.mul(kU0, kU0, kLagA2);
  c.set(kU1, pace_tenths);
  c.div(kU0, kU0, kU1);  // h/(κ·τ2)
  c.min(kLagC, kLagC, kU0);
  c.min(kLagC, kLagC, kHalf);
  // Each lag slower than T_cl is sped up by T_dom/T_cl = τ1/T_cl (controller: capped at 2h;
  // observer: 4 × the uncapped rate, capped at 2h); a faster one keeps its open-loop pole.
  c.copy(kLc1, kAlpha);
  c.copy(kLo1, kAlpha);
  if (c.less(kLagA1, kLagC)) {
    c.one_minus_exp_neg(kLc1, kLagC);
    c.ldexp(kU0, kLagC, 2);
    c.min(kU0, kU0, kHalf);
    c.one_minus_exp_neg(kLo1, kU0);
  }
  c.copy(kLc2, kBeta2);
  c.copy(kLo2, kBeta2);
  if (c.less(kLagA2, kLagC)) {
    c.div(kU1, kLagC, kLagQ);
    c.min(kU0, kU1, kHalf);
    c.one_minus_exp_neg(kLc2, kU0);
    c.ldexp(kU0, kU1, 2);
    c.min(kU0, kU0, kHalf);
    c.one_minus_exp_neg(kLo2, kU0);
  }
  c.ldexp(kU0, kLagC, 1);  // bias: T_cl/2 (no dead time)
  c.one_minus_exp_neg(kLob, kU0);

  // Law: m1, m2, L, M.
  c.sub(kU0, kLc1, kAlpha);
  c.sub(kU1, kLc2, kAlpha);
  c.mul(kM1, kU0, kU1);
  c.mul(kU2, kLagK, kAlpha);
  c.div(kM1, kM1, kU2);  // m1
  c.sub(kU0, kLc1, kBeta2);
  c.sub(kU1, kLc2, kBeta2);
  c.mul(kM2, kU0, kU1);
  c.mul(kU2, kBetaMinusAlpha, kLagK);
  c.mul(kU2, kU2, kBeta2);
  c.mul(kU2, kU2, kLagQ);
  c.mul(kU2, kU2, kLagR);
  c.div(kM2, kM2, kU2);  // m2 = L2
  c.div(kU0, kM1, kBetaMinusAlpha);
  c.mul(kU1, kLagR, kM2);
  c.sub(kLagLaw0, kU0, kU1);
  c.ldexp(kLagLaw0, kLagLaw0, p);
  c.ldexp(kLagLaw1, kM2, p);
  c.copy(kLagLaw2, kHeadroom);  // 1.01·g_d, g_d = 1
  c.mul(kU0, kLc1, kLc2);
  c.mul(kU1, kAlpha, kBeta2);
  c.mul(kU1, kU1, kLagK);
  c.div(kU0, kU0, kU1);
  c.ldexp(kU0, kU0, p);
  c.mul(kLagLaw3, kU0, kHeadroom);
  int16_t law[4];
  if (!c.quantize(kLagLaw0, 4, 46, 1, law, &k.ctrl_shift)) return false;
  k.fb_gain[0] = law[0];
  k.fb_gain[1] = law[1];
  // M from the quantised numbers: (1 + L·g)/gain_q·2^p, L·g = (l0·g1 + l1·g2)/2^(s + p).
  const int16_t ls = static_cast<int16_t>(-(k.ctrl_shift + p));
  c.set(kU0, law[0], ls);
  c.mul(kU0, kU0, kLagG1);
  c.set(kU1, law[1], ls);
  c.mul(kU1, kU1, kLagGainQ);
  c.add(kU0, kU0, kU1);
  c.add(kU0, kU0, kOne);
  c.div(kU0, kU0, kLagGainQ);
  c.ldexp(kU0, kU0, p);
  k.ff_gain = c.mantissa(kU0, k.ctrl_shift);
  k.bias_gain = c.mantissa(kOne, k.ctrl_shift);

  // Observer: P(1), P(e1), P(e2) over the poles ℓo1, ℓo2, ℓob.
  c.mul(kP0, kLo1, kLo2);
  c.mul(kP0, kP0, kLob);
  c.sub(kPa, kLo1, kAlpha);
  c.sub(kU0, kLo2, kAlpha);
  c.mul(kPa, kPa, kU0);
  c.sub(kU0, kLob, kAlpha);
  c.mul(kPa, kPa, kU0);
  c.sub(kPb, kLo1, kBeta2);
  c.sub(kU0, kLo2, kBeta2);
  c.mul(kPb, kPb, kU0);
  c.sub(kU0, kLob, kBeta2);
  c.mul(kPb, kPb, kU0);
  c.mul(kU0, kAlpha, kBeta2);
  c.div(kU2, kP0, kU0);  // P(1)/(αβ)
  c.div(kLagKd, kU2, kLagK);
  c.ldexp(kLagKd, kLagKd, p);
  c.sub(kU0, kOne, kAlpha);  // e1
  c.mul(kU0, kU0, kAlpha);   // α·e1
  c.div(kU1, kPa, kU0);      // P(e1)/(α·e1)
  c.div(kLagKx1, kU1, kLagF);
  c.sub(kLagKx1, kU2, kLagKx1);
  c.div(kU1, kU1, kBetaMinusAlpha);
  c.sub(kLagKx2, kU2, kU1);
  c.sub(kU0, kOne, kBeta2);  // e2
  c.mul(kU0, kU0, kBeta2);
  c.mul(kU0, kU0, kBetaMinusAlpha);
  c.div(kU1, kPb, kU0);
  c.add(kLagKx2, kLagKx2, kU1);
  if (!c.quantize(kLagKx1, 1, 40, 8, &k.obs_gain[0], &k.obs_shift[0]) ||
      !c.quantize(kLagKx2, 1, 40, 8, &k.obs_gain[1], &k.obs_shift[1]) ||
      !c.quantize(kLagKd, 1, 40, 8, &k.obs_gain[2], &k.obs_shift[2]))
    return false;

  // Fan (as the FOPDT's), steady state per kelvin [g1/g2, 1], 2^p / DC gain.
  c.fan_gain(kLagFan, kU0, kU1, model, p);
  c.div(kLagShare0, kLagG1, kLagGainQ);
  c.copy(kLagShare1, kOne);
  c.set(kLagInv, 1, p);
  c.div(kLagInv, kLagInv, kLagGainQ);
  return c.quantize(kLagFan, 1, 46, 1, &k.fan_gain, &k.fan_shift) &&
         c.quantize(kLagShare0, 2, 46, 1, k.ss_share, &k.ss_share_shift) &&
         c.quantize(kLagInv, 1, 46, 1, &k.inv_gain, &k.inv_gain_shift) && state_feedback_constants_valid(k);
}

}  // namespace

bool design_state_feedback_fopdt(const HotendModel& model, uint16_t period_ms, StateFeedbackConstants* out,
                                 bool dead_time_paced) {
  *out = StateFeedbackConstants();
  Calc calc;
  if (design(model, period_ms, dead_time_paced, *out, calc)) return true;
  *out = StateFeedbackConstants();  // n = 0: fails state_feedback_constants_valid
  return false;
}

bool design_state_feedback_two_lags(const HotendModel& model, uint16_t period_ms, StateFeedbackConstants* out,
                                    uint8_t pace_tenths) {
  *out = StateFeedbackConstants();
  Calc calc;
  if (design_two_lags(model, period_ms, pace_tenths, *out, calc)) return true;
  *out = StateFeedbackConstants();
  return false;
}

}  // namespace control

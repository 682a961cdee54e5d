// PID gains from a first-order-plus-dead-time (FOPDT) model, and the FOPDT model from a step
// response. Host-only design code in double (header-only: the firmware never includes it).
// Gains come out in Marlin's M301 units (output on a 0–255 scale, Ki per second, Kd in seconds)
// for the parallel form u = Kp·e + Ki·∫e dt − Kd·dy/dt that control/pid.h implements; each rule's
// controller gain Kc (duty fraction per °C) and times Ti, Td convert as Kp = 255·Kc, Ki = Kp/Ti,
// Kd = Kp·Td.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "control/pid.h"

namespace tuning {

// G(s) = K·e^(−τs) / (T·s + 1), input = heater duty 0–1, output = temperature in °C.
struct Fopdt {
  double k_c_per_duty;  // K: steady-state rise per unit duty, °C (all of 0 → 100 %)
  double t_s;           // T: time constant, s
  double tau_s;         // τ: dead time, s (> 0 for every rule below except SIMC)
};

// Gains as hosts type them with M301.
struct MarlinGains {
  double kp;  // output (0–255) per °C
  double ki;  // output per °C·s
  double kd;  // output per °C/s
};

namespace detail {
constexpr double kMarlinFullScale = 255.0;
inline MarlinGains from_standard_form(double kc_duty_per_c, double ti_s, double td_s) {
  const double kp = kMarlinFullScale * kc_duty_per_c;
  return MarlinGains{kp, kp / ti_s, kp * td_s};
}
}  // namespace detail

// Ziegler & Nichols (1942), "Optimum settings for automatic controllers", Trans. ASME 64:759,
// step-response (reaction-curve) rule: Kc = 1.2·T/(K·τ), Ti = 2τ, Td = τ/2. Aimed at quarter
// amplitude decay: fast, oscillatory, overshoots on a setpoint step.
inline MarlinGains ziegler_nichols_step(const Fopdt& m) {
  return detail::from_standard_form(1.2 * m.t_s / (m.k_c_per_duty * m.tau_s), 2.0 * m.tau_s, 0.5 * m.tau_s);
}

// Cohen & Coon (1953), "Theoretical consideration of retarded control", Trans. ASME 75:827
// (the rule seeds 002 and 004 use): with r = τ/T,
// Kc = (T/(K·τ))·(4/3 + r/4), Ti = τ·(32 + 6r)/(13 + 8r), Td = 4τ/(11 + 2r).
inline MarlinGains cohen_coon(const Fopdt& m) {
  const double r = m.tau_s / m.t_s;
  return detail::from_standard_form(m.t_s / (m.k_c_per_duty * m.tau_s) * (4.0 / 3.0 + r / 4.0),
                                    m.tau_s * (32.0 + 6.0 * r) / (13.0 + 8.0 * r),
                                    4.0 * m.tau_s / (11.0 + 2.0 * r));
}

// SIMC, Skogestad (2003), "Simple analytic rules for model reduction and PID controller tuning",
// J. Process Control 13:291, Table 1, first-order model: a PI controller (no derivative — SIMC
// adds D only for a second-order lag) with Kc = T/(K·(τc + τ)), Ti = min(T, 4·(τc + τ)).
// τc is the desired closed-loop time constant; τc = τ is Skogestad's "tight but robust" choice.
inline MarlinGains simc(const Fopdt& m, double tau_c_s) {
  const double ti_s = std::fmin(m.t_s, 4.0 * (tau_c_s + m.tau_s));
  const double kp = detail::kMarlinFullScale * m.t_s / (m.k_c_per_duty * (tau_c_s + m.tau_s));
  return MarlinGains{kp, kp / ti_s, 0.0};
}
inline MarlinGains simc(const Fopdt& m) { return simc(m, m.tau_s); }

// AMIGO, Åström & Hägglund (2004), "Revisiting the Ziegler–Nichols step response method for PID
// control", J. Process Control 14:635 (also "Advanced PID Control", ISA 2006, §7.6), PID form:
// Kc = (0.2 + 0.45·T/τ)/K, Ti = τ·(0.4τ + 0.8T)/(τ + 0.1T), Td = 0.5·τ·T/(0.3τ + T).
// Designed for robustness (maximum sensitivity ≈ 1.4): slower than ZN, little overshoot.
inline MarlinGains amigo(const Fopdt& m) {
  return detail::from_standard_form((0.2 + 0.45 * m.t_s / m.tau_s) / m.k_c_per_duty,
                                    m.tau_s * (0.4 * m.tau_s + 0.8 * m.t_s) / (m.tau_s + 0.1 * m.t_s),
                                    0.5 * m.tau_s * m.t_s / (0.3 * m.tau_s + m.t_s));
}

// The Q16 gains control::Pid takes, rounded to nearest.
inline control::PidGains to_q16(const MarlinGains& g) {
  auto q16 = [](double x) { return static_cast<int32_t>(std::lround(x * 65536.0)); };
  return control::PidGains{q16(g.kp), q16(g.ki), q16(g.kd)};
}

// --- Identification: the two-point method of C.L. Smith, "Digital Computer Process Control"
// (1972), as used by seeds 002 and 004. A FOPDT step response reaches 1 − e^(−1/3) ≈ 28.3 % of its
// final change at τ + T/3 and 1 − e^(−1) ≈ 63.2 % at τ + T, hence T = 1.5·(t63 − t28),
// τ = t63 − T. Times are measured from the step.
constexpr double kFraction28 = 0.28346868942621073;  // 1 − e^(−1/3)
constexpr double kFraction63 = 0.63212055882855767;  // 1 − e^(−1)

inline Fopdt fopdt_from_two_points(double t28_s, double t63_s, double k_c_per_duty) {
  const double t_s = 1.5 * (t63_s - t28_s);
  return Fopdt{k_c_per_duty, t_s, t63_s - t_s};
}

// Fits a FOPDT to a recorded step response: samples (time_s[i], temp_c[i]) in time order, the
// duty stepped by duty_step at step_time_s and held until the last sample, which must be
// settled (it is taken as the final value). The start value is the temperature interpolated
// at the step; crossings are interpolated linearly between samples. Returns t_s = 0 when the
// response never crosses both levels (too short a record, or no response).
inline Fopdt fit_fopdt_two_point(const std::vector<double>& time_s, const std::vector<double>& temp_c,
                                 double step_time_s, double duty_step) {
  const std::size_t n = time_s.size() < temp_c.size() ? time_s.size() : temp_c.size();
  if (n < 2) return Fopdt{0, 0, 0};
  auto at = [&](double t) {  // linear interpolation, clamped to the record
    if (t <= time_s[0]) return temp_c[0];
    for (std::size_t i = 1; i < n; ++i) {
      if (t <= time_s[i]) {
        const double w = (t - time_s[i - 1]) / (time_s[i] - time_s[i - 1]);
        return temp_c[i - 1] + (temp_c[i] - temp_c[i - 1]) * w;
      }
    }
    return temp_c[n - 1];
  };
  const double start_c = at(step_time_s);
  const double change_c = temp_c[n - 1] - start_c;
  auto first_crossing = [&](double fraction) {  // time after the step, or −1
    const double level = start_c + fraction * change_c;
    for (std::size_t i = 1; i < n; ++i) {
      if (time_s[i] <= step_time_s) continue;
      const double b = temp_c[i] - level;
      if (change_c > 0 ? b >= 0 : b <= 0) {
        const double t0 = std::fmax(time_s[i - 1], step_time_s);
        const double a = at(t0) - level;
        return t0 + (a == b ? 0.0 : (time_s[i] - t0) * a / (a - b)) - step_time_s;
      }
    }
    return -1.0;
  };
  const double t28_s = first_crossing(kFraction28);
  const double t63_s = first_crossing(kFraction63);
  if (t28_s < 0 || t63_s < 0 || change_c == 0) return Fopdt{0, 0, 0};
  return fopdt_from_two_points(t28_s, t63_s, change_c / duty_step);
}

}  // namespace tuning

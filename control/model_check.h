// Model-based heater protection (issue 8): the hotend's M307 model (A, C, D, F) bounds how fast
// the sensor may rise or fall for the duty the heater had and the part fan, and the evidence
// that the hotend leaves those bounds is accumulated (a leaky one-sided CUSUM per side):
//   low side:  the sensor heats less than the model's lower bound (heater dead, thermistor out
//              of its hole, cartridge loose, power dropped) -> kHeatsTooLittle
//   high side: the sensor heats more than the model's upper bound, above all with the heater off
//              for the whole dead-time window (heater stuck on) -> kHeatsTooMuch
// Per period, with h = period, u_lo/u_hi = min/max duty over the dead-time window, T the reading:
//   lower = h/C · (A·(1−g)·u_lo − (1+l)·(1 + F/100·fan)·(T − 18 °C))     tuned model
//           (fan: its highest duty over delays 0 .. the window's end: its loss reaches the
//           sensor through the same lags as the heater's power)
//   upper = h/C · (A·(1+g)·u_hi − (1−l)·(T − 35 °C))                      (fan ignored: it only cools)
//   E_lo = min(0, E_lo·(1 − h/τ) + ΔT − lower),  E_hi = max(0, E_hi·(1 − h/τ) + ΔT − upper)
//   trip: E_lo < −threshold, E_hi > 2·threshold (M570 T, or U for the default model), for 4
//   periods in a row (an opening or shorting thermistor is the range guard's: MINTEMP/MAXTEMP)
// g = 15 %, l = 10 % (a reasonable tune's error), ambient anywhere in 18..35 °C, τ = 512 periods,
// window = delays D/2 .. 2D + 1 s (the FOPDT's dead time stands for lags: a second-order plant
// keeps rising after the heater is off, and reaches full slope later than D; 3D/4 .. 5D/4 + 1 s
// left 27 °C of evidence on seed003, host test).
// A model that is only the firmware's default says little about this hotend: then the low side
// only requires that a heater driven ≥ 50 % over the whole window does not let the reading fall
// faster than 0.25 °C/s, and the high side that a heater off over the whole window (delays
// 0 .. 3D + 30 s) does not let it rise faster than 0.1 °C/s. Portable, float-free.
#pragma once
#include <stdint.h>

#include "control/feedforward.h"

namespace control {

class ModelCheck {
 public:
  enum class Verdict : uint8_t { kOk, kHeatsTooLittle, kHeatsTooMuch };
  static constexpr uint8_t kBins = 16;  // duty history: min/max per bin + fan max, 48 B of RAM

  constexpr ModelCheck() = default;

  // Precondition: hotend_model_valid(model), 10 ≤ period_ms ≤ 2000, threshold 1..255 °C
  // (Q8). `tuned`: the model came from M303/M307/EEPROM, not the default. Set-up code (two long
  // divisions); starts over (reset()).
  void configure(const HotendModel& model, bool tuned, int32_t threshold_q8, uint16_t period_ms);
  // Forget the evidence and the duty history (a new start, a fault cleared): the history then
  // counts as both 0 % and 100 %, so nothing is concluded until one window has passed.
  void reset();
  // One control period: the plausible reading at its end, the heater duty that ran in it
  // (65535 = 100 %, M303's too), the part fan (0..255).
  Verdict step(int32_t temp_q8, uint16_t duty_q16, uint8_t fan_duty);

  // Evidence so far, °C × 65536 (E_lo ≤ 0 ≤ E_hi): for tests and reports.
  int32_t low_evidence_q16() const { return low_q16_; }
  int32_t high_evidence_q16() const { return high_q16_; }
  bool tuned() const { return tuned_; }

 private:
  int32_t bound_q16(int32_t net_q8) const;  // h/C · net, °C × 65536 per period
  void close_bin();

  // Model terms (tuned).
  uint16_t heat_lo_q4_ = 0;    // A·(1−g), °C × 16
  uint16_t heat_hi_q4_ = 0;    // A·(1+g), °C × 16
  uint16_t fan_slope_q16_ = 0; // (1+l)·F/100 per fan unit, × 65536 / 16 (Q12 after >> 4)
  uint16_t rate_mantissa_ = 0; // h/C, normalised to 2^15..2^16−1
  int8_t rate_shift_ = 0;      // bound_q16 = mul_q16(net_q8, mantissa) << shift (>> −shift)
  uint32_t allow_fall_q16_ = 0;  // default model: per period, °C × 65536
  uint32_t allow_rise_q16_ = 0;
  bool tuned_ = false;
  int32_t threshold_q16_ = 0;
  // Duty history (duty_q16 >> 8).
  uint16_t bin_periods_ = 1;   // periods per bin
  uint8_t first_bin_ = 0;      // oldest delay of the window in bins (0: the running bin counts)
  uint8_t head_ = 0;           // the running bin
  uint16_t in_bin_ = 0;        // periods in the running bin
  uint8_t min_[kBins] = {};
  uint8_t max_[kBins] = {};
  uint8_t fan_max_[kBins] = {};  // the part fan's highest duty per bin
  uint8_t window_min_ = 0;     // over the closed bins of the window
  uint8_t window_max_ = 255;
  uint8_t window_fan_ = 255;   // the fan's highest over every closed bin (delays 0 .. window end)
  // Evidence.
  int32_t last_temp_q8_ = 0;
  bool have_last_ = false;
  int32_t low_q16_ = 0;
  int32_t high_q16_ = 0;
  uint8_t persist_ = 0;  // consecutive periods over a threshold
};

}  // namespace control

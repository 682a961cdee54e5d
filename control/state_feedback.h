// State feedback + static-gain feedforward with an observer and a dead-time predictor (seed 000,
// made practical), in fixed point. The constants come from the host design (`hotend-design`,
// design/state_feedback_quantize.h); their Q formats are documented in
// control/state_feedback_constants.h and docs/state_feedback.md. Portable, float-free.
//
// Each law period (decimation × 128 ms, spread over the period's step() calls):
//   call 0: innovation e = y − Σ x̂ (masked)  → x̂ += K e, d̂ += K_d e    (current observer)
//           v = M r − L_D x̂ − g_d d̂ − Σ h_j v[k−j]                         (predictive law)
//           u = clamp(v + fan, 0..100 %), history v[k] = u − fan         (fan feedforward)
//   call 1: x̂ ← x̂ + (Φ−I) x̂ + Γa (v[k−D] + d̂) + Γb (v[k−D+1] + d̂)      (time update)
//   2.. : Σ h_j v[k+1−j] for the next law update, kSfFirChunk taps per call
// fan = the known part-fan loss in duty (gain·fan·rise). The fan cools the block, so its effect
// reaches the sensor through the heater's dead time: adding it to the applied duty with weight 1
// cancels it as it arrives, and the model runs on the effective input v (heater minus fan loss).
// The observer and predictor use the applied (clamped) duty and nothing integrates the control
// error, so nothing winds up at 0 %/100 %; d̂ (input bias: model error, ambient, unmodelled
// loss) is clamped to ±100 % duty.
#pragma once

#include <stdint.h>

#include "control/controller.h"
#include "control/state_feedback_constants.h"

namespace control {

class StateFeedback final : public Controller {
 public:
  // Copies the constants; false (and nothing changes) if they fail the range checks.
  bool configure(const StateFeedbackConstants& k);
  const StateFeedbackConstants& constants() const { return k_; }
  bool configured() const { return configured_; }

  uint16_t step(const StepInput& in) override;
  void reset() override;
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;

  // Introspection for tests and M503-style reports.
  int32_t state_q16(uint8_t i) const { return x_q16_[i]; }  // °C above ambient × 2^16
  int32_t bias_q16p() const { return bias_; }               // duty × 2^(16+p)

 private:
  void prime(int32_t measured_q8, uint16_t duty_q16, bool zero_bias);
  void law_update(const StepInput& in);
  void time_update();
  void fir_chunk(uint8_t chunk);
  int32_t fan_share(int32_t rise_q8, uint8_t fan_duty) const;  // the fan's loss as duty Q16
  int32_t follow_fan(uint8_t fan_duty);  // duty_q16_ = the law's net duty + the fan's share (returned)
  int16_t history(uint8_t j) const;  // v[k−j] (duty Q15), k = the last law update

  // Scalars first: AVR's LDD/STD reach offsets 0..63 only (k_ is 174 bytes).
  uint8_t head_ = 0;                      // index of u[k] in hist_
  uint8_t phase_ = 0;                     // which call of the law period comes next
  uint16_t duty_q16_ = 0;
  bool configured_ = false;
  bool primed_ = false;
  int32_t bias_ = 0;                      // d̂, duty Q(16+p)
  int32_t fir_ = 0;                       // Σ h_j v[k+1−j] (pre-shifted by 8), next law update
  StateFeedbackConstants k_ = {};
  int32_t x_q16_[kSfMaxStates] = {};
  uint32_t residual_[kSfMaxStates] = {};  // time-update bits below Q16, carried (no dead band)
  int16_t hist_[kSfMaxDelay + 1] = {};    // ring of effective inputs v (duty minus fan), Q15
  // The fan's share between law updates (follow_fan), last: the law's members above keep their
  // offsets.
  int32_t net_q16_ = 0;                   // the last law update's duty net of the fan (Q16, ±)
  int32_t rise_q8_ = 0;                   // the sensor's rise above the model's ambient then, °C Q8
  uint16_t fan_full_q16_ = 0;             // the fan's share at 100 % airflow, from that rise
  uint8_t fan_seen_ = 0;                  // the airflow duty_q16_ holds the share for
  bool follows_fan_ = false;              // the law period has idle calls to follow the fan in
};

}  // namespace control

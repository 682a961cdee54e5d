// The part fan's airflow behind its PWM pin. A blower needs a fraction of a second to spin up or
// down, and the heat it carries off follows the airflow, not the pin: fan feedforward (M307 F)
// switched with the pin heats ahead of the fan. On seed002 (A 450 °C, C 24 s, 18 °C/s at full
// power) a 0 → 100 % step then came back 1.2 °C high one dead time later (pid+ff, simavr, whose
// plants lag the airflow 0.5 s behind the pin). The controllers get this estimate instead.
// First order, 1/4 of the gap per 128 ms period: τ = 0.128 s / ln(4/3) = 0.45 s. Portable.
#pragma once
#include <stdint.h>

namespace control {

class FanAirflow {
 public:
  // One control period on, with the pin's duty (0..255): the airflow the next period sees.
  void step(uint8_t pin_duty) {
    before_q6_ = q6_;
    advance(pin_duty);
  }
  // The pin changed after step() (M106 between two periods): the next period's airflow as if
  // step() had seen the new duty, as the controllers would see it inside the period.
  void retarget(uint8_t pin_duty) { advance(pin_duty); }
  uint8_t airflow() const { return airflow_; }  // same units as the pin's duty

 private:
  void advance(uint8_t pin_duty) {
    // Q6: 255·64 = 16,320, so the difference fits int16. The floor shift stalls at most 3/64
    // below a rising pin: the +32 rounding still lands on it.
    const int16_t gap = static_cast<int16_t>((static_cast<int16_t>(pin_duty) << 6) - static_cast<int16_t>(before_q6_));
    q6_ = static_cast<uint16_t>(before_q6_ + (gap >> 2));
    airflow_ = static_cast<uint8_t>((q6_ + 32) >> 6);
  }
  uint16_t q6_ = 0;         // airflow × 64 for the next period
  uint16_t before_q6_ = 0;  // the same one period earlier
  uint8_t airflow_ = 0;
};

}  // namespace control

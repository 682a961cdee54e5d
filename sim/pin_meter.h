// Measures the duty of a soft-PWM output pin from its edges, in CPU cycles: the firmware drives
// the heater and fan pins from the tick interrupt, so on-time between two sampling instants is
// exactly the sum of the high intervals, with no assumption about the PWM period.
#pragma once

#include <cstdint>

namespace sim {

class PinMeter {
 public:
  // The pin drives its MOSFET only when it is an output and high; an input pin (after reset)
  // leaves the gate to its pull-down, i.e. off.
  void set_level(bool high, uint64_t cycle) { update(high, output_, cycle); }
  void set_output(bool output, uint64_t cycle) { update(high_, output, cycle); }
  // After a CPU reset every pin is an input with PORT cleared.
  void reset(uint64_t cycle) { update(false, false, cycle); }

  bool is_on() const { return high_ && output_; }
  // Cycle of the last off→on or on→off change (0 if none yet).
  uint64_t last_change_cycle() const { return last_change_cycle_; }
  // Number of off→on changes so far.
  uint64_t turn_on_count() const { return turn_on_count_; }
  // Fraction of cycles the pin was on since the previous call (or since start), then restarts
  // the window at `cycle`. Returns the current state for an empty window.
  double take_duty(uint64_t cycle);

 private:
  void update(bool high, bool output, uint64_t cycle);

  bool high_ = false;
  bool output_ = false;
  uint64_t window_start_cycle_ = 0;
  uint64_t on_since_cycle_ = 0;  // valid while is_on()
  uint64_t on_cycles_in_window_ = 0;
  uint64_t last_change_cycle_ = 0;
  uint64_t turn_on_count_ = 0;
};

}  // namespace sim

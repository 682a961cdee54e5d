#include "sim/pin_meter.h"

namespace sim {

void PinMeter::update(bool high, bool output, uint64_t cycle) {
  const bool was_on = is_on();
  high_ = high;
  output_ = output;
  const bool now_on = is_on();
  if (was_on == now_on) return;
  if (was_on)
    on_cycles_in_window_ += cycle - on_since_cycle_;
  else {
    on_since_cycle_ = cycle;
    ++turn_on_count_;
  }
  last_change_cycle_ = cycle;
}

double PinMeter::take_duty(uint64_t cycle) {
  uint64_t on = on_cycles_in_window_;
  if (is_on()) {
    on += cycle - on_since_cycle_;
    on_since_cycle_ = cycle;
  }
  const uint64_t span = cycle - window_start_cycle_;
  window_start_cycle_ = cycle;
  on_cycles_in_window_ = 0;
  if (span == 0) return is_on() ? 1.0 : 0.0;
  return static_cast<double>(on) / static_cast<double>(span);
}

}  // namespace sim

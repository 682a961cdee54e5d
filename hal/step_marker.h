// Marks the control step for the simulator: GPIOR0 = 1 right before it, 0 right after
// (brief: firmware <-> simulator contract). GPIOR0 is I/O 0x1E (data 0x3E) on both MCUs and
// unused otherwise; a single OUT instruction each, so the marker costs 2 cycles.
#pragma once
#include <avr/io.h>

namespace hal {
namespace step_marker {

__attribute__((always_inline)) inline void begin() {
  __asm__ volatile("" ::: "memory");
  GPIOR0 = 1;
  __asm__ volatile("" ::: "memory");
}
__attribute__((always_inline)) inline void end() {
  __asm__ volatile("" ::: "memory");
  GPIOR0 = 0;
  __asm__ volatile("" ::: "memory");
}

}  // namespace step_marker
}  // namespace hal

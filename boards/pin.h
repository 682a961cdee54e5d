// A microcontroller pin named the way the datasheet names it: port letter and bit.
// Data only; hal/gpio.h turns it into register addresses.
#pragma once
#include <stdint.h>

namespace boards {

struct Pin {
  char port;    // 'A'..'L'
  uint8_t bit;  // 0..7
};

}  // namespace boards

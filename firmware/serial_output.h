// The G-code layer's Output on UART0: replies go into the TX ring (hal/uart).
#pragma once

#include "firmware/gcode_output.h"

namespace firmware {

class SerialOutput final : public gcode::Output {
 public:
  void write_char(char c) override;
  void write_flash(const gcode::FlashText* text) override;  // text in program memory
};

}  // namespace firmware

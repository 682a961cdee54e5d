// Constant tables the firmware reads at run time live in program memory on AVR (GCODE_PROGMEM,
// firmware/gcode_text.h): copied out with this, memcpy_P on the board (firmware/flash_copy.cpp),
// plain memcpy on the host (host_tests/fake_flash.cpp).
#pragma once
#include <stdint.h>

namespace firmware {

void flash_copy(void* ram, const void* flash, uint8_t bytes);

}  // namespace firmware

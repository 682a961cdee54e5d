// The board's flash_copy (firmware/flash_copy.h).
#include "firmware/flash_copy.h"

#include <avr/pgmspace.h>

namespace firmware {

void flash_copy(void* ram, const void* flash, uint8_t bytes) { memcpy_P(ram, flash, bytes); }

}  // namespace firmware

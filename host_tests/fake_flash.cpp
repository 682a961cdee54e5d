// The host's flash_copy (firmware/flash_copy.h): GCODE_PROGMEM tables are ordinary memory here.
#include <string.h>

#include "firmware/flash_copy.h"

namespace firmware {

void flash_copy(void* ram, const void* flash, uint8_t bytes) { memcpy(ram, flash, bytes); }

}  // namespace firmware

// control/fixed_math.h's log2 table in program memory (128 bytes of RAM otherwise) and its reader.
#include <avr/pgmspace.h>

#include "control/fixed_math.h"

namespace fixed_math {
namespace {

const Log2Table kLog2Flash PROGMEM = kLog2Table;

}  // namespace

uint16_t log2_table(uint8_t i) { return pgm_read_word(&kLog2Flash.q16[i]); }

}  // namespace fixed_math

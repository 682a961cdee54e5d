// The host builds' log2 table reader (control/fixed_math.h). The firmware images use
// firmware/log2_table_flash.cpp instead (firmware/CMakeLists.txt leaves this file out).
#include "control/fixed_math.h"

namespace fixed_math {

uint16_t log2_table(uint8_t i) { return kLog2Table.q16[i]; }

}  // namespace fixed_math

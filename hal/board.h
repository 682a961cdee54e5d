// The board this image is built for: the ONE place that includes the board header chosen by
// CMake (-DBOARD_HEADER="boards/<board>.h" -DBOARD_NS=<board>). Everything else uses `board::`.
// Lives in hal/ because hal needs the pins as compile-time constants (sbi/cbi in the tick ISR).
#pragma once
#include BOARD_HEADER

namespace board = boards::BOARD_NS;

// A host stand-in for hal/eeprom: 4 KB of cells, a write that stays busy for a few busy()
// polls as silicon's 3.4 ms write does, counters for misuse (a write or read started while
// busy), and a power cut after N completed writes (later writes are lost, as on a reset).
#pragma once
#include <stdint.h>

#include <vector>

namespace fake_eeprom {

struct State {
  std::vector<uint8_t> cells = std::vector<uint8_t>(4096, 0xFF);
  int busy_polls_per_write = 3;  // busy() answers true this many times after each write
  int busy_left = 0;
  long writes = 0;             // writes that reached the cells
  long write_limit = -1;       // >= 0: writes after this many are lost (power cut)
  long misuse = 0;             // start_write or read while a write was in progress
  long max_writes_between_polls = 0;
  long writes_since_poll = 0;
};

State& state();
void reset(int busy_polls_per_write = 3);  // blank (0xFF) cells, counters cleared

}  // namespace fake_eeprom

#include "host_tests/fake_eeprom.h"

#include "hal/eeprom.h"

namespace fake_eeprom {

State& state() {
  static State s;
  return s;
}

void reset(int busy_polls_per_write) {
  state() = State{};
  state().busy_polls_per_write = busy_polls_per_write;
}

}  // namespace fake_eeprom

namespace hal {
namespace eeprom {

using fake_eeprom::state;

bool busy() {
  fake_eeprom::State& s = state();
  s.writes_since_poll = 0;
  if (s.busy_left == 0) return false;
  --s.busy_left;
  return true;
}

uint8_t read_byte(uint16_t address) {
  if (state().busy_left != 0) ++state().misuse;  // silicon: EEPROM unreadable during a write
  return state().cells.at(address);
}

void read(uint16_t address, void* data, uint16_t size) {
  for (uint16_t i = 0; i < size; ++i) static_cast<uint8_t*>(data)[i] = read_byte(static_cast<uint16_t>(address + i));
}

void start_write(uint16_t address, uint8_t value) {
  fake_eeprom::State& s = state();
  if (s.busy_left != 0) ++s.misuse;  // silicon ignores it; the writer must never try
  if (++s.writes_since_poll > s.max_writes_between_polls) s.max_writes_between_polls = s.writes_since_poll;
  s.busy_left = s.busy_polls_per_write;
  if (s.write_limit >= 0 && s.writes >= s.write_limit) return;  // power is gone
  s.cells.at(address) = value;
  ++s.writes;
}

}  // namespace eeprom
}  // namespace hal

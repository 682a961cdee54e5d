// Digital pins from boards::Pin data. The register addresses are computed at compile time;
// with a constexpr Pin every access folds to a single sbi/cbi (ports A..G) or a short
// load/modify/store (ports H..L, ATmega2560 only).
#pragma once
#include <stdint.h>

#include "boards/pin.h"
#include "hal/critical_section.h"

namespace hal {
namespace gpio {

// Port index in register order; there is no port I on either MCU (datasheet register summary).
constexpr uint8_t port_index(char port) {
  return static_cast<uint8_t>(port < 'I' ? port - 'A' : port - 'A' - 1);
}

constexpr bool is_valid(boards::Pin pin) {
  return pin.port >= 'A' && pin.port <= 'L' && pin.port != 'I' && pin.bit < 8;
}

// Data-space address of PINx. ATmega1284P/2560: PINA..PING at 0x20 + 3i (I/O space),
// PINH..PINL at 0x100 + 3(i - 7) (extended I/O, 2560 only). DDRx = PINx + 1, PORTx = PINx + 2.
constexpr uint16_t pin_address(boards::Pin pin) {
  return port_index(pin.port) < 7 ? 0x20 + 3 * port_index(pin.port)
                                  : 0x100 + 3 * (port_index(pin.port) - 7);
}
constexpr uint16_t ddr_address(boards::Pin pin) { return pin_address(pin) + 1; }
constexpr uint16_t port_address(boards::Pin pin) { return pin_address(pin) + 2; }

// sbi/cbi reach I/O addresses 0..31 (data 0x20..0x3F): a single, atomic instruction there.
constexpr bool is_bit_addressable(uint16_t data_address) { return data_address < 0x40; }

static_assert(pin_address(boards::Pin{'H', 0}) == 0x100, "PINH");
static_assert(pin_address(boards::Pin{'L', 0}) == 0x109, "PINL (port I skipped)");
static_assert(port_address(boards::Pin{'G', 0}) == 0x34, "PORTG");

inline volatile uint8_t& reg(uint16_t data_address) {
  return *reinterpret_cast<volatile uint8_t*>(data_address);
}

// Sets or clears one bit of a port register. Above the sbi/cbi range the read-modify-write
// runs with interrupts off, or an ISR writing another pin of that port could be undone.
__attribute__((always_inline)) inline void write_bit(uint16_t address, uint8_t bit, bool high) {
  const uint8_t mask = static_cast<uint8_t>(1u << bit);
  if (is_bit_addressable(address)) {
    if (high) reg(address) |= mask; else reg(address) &= static_cast<uint8_t>(~mask);
  } else {
    CriticalSection lock;
    if (high) reg(address) |= mask; else reg(address) &= static_cast<uint8_t>(~mask);
  }
}

__attribute__((always_inline)) inline void write(boards::Pin pin, bool high) {
  write_bit(port_address(pin), pin.bit, high);
}

__attribute__((always_inline)) inline void set_output(boards::Pin pin) {
  write_bit(ddr_address(pin), pin.bit, true);
}

// Output, driven low: PORT first so the pin never drives high in between.
__attribute__((always_inline)) inline void drive_low(boards::Pin pin) {
  write(pin, false);
  set_output(pin);
}

}  // namespace gpio
}  // namespace hal

// Silicon EEPROM timing for AvrBoard (--eeprom-timing silicon). simavr 1.6 stores a written
// byte at once and clears EEPE in the same instruction, so firmware that busy-waits on EEPE
// never waits. On the ATmega1284P/2560 an erase-and-write takes 3.3-3.4 ms (datasheet
// tWD_EEPROM 3.3 ms; simavr's own EE_READY interrupt uses 3.4 ms): EEPE stays set meanwhile and
// a new write (EEMPE+EEPE) or read (EERE) is ignored, as is the EEPROM itself on silicon. This
// wraps simavr's EECR write handler: the data still goes through it, EEPE is held set for the
// write time. (Not modelled: silicon also ignores EEAR changes during a write.)
#include <stdexcept>

extern "C" {
#include <sim_avr.h>
#include <sim_io.h>
}

#include "sim/avr_board.h"
#include "sim/avr_board_parts.h"

namespace sim {
namespace {

constexpr uint16_t kEecrDataAddress = 0x3F;  // EECR (I/O 0x1F) on both MCUs
constexpr uint8_t kEere = 1u << 0;
constexpr uint8_t kEepe = 1u << 1;
constexpr uint8_t kEempe = 1u << 2;
constexpr uint32_t kWriteUs = 3400;

}  // namespace

void AvrBoard::EepromTiming::on_eecr_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param) {
  auto* self = static_cast<EepromTiming*>(param);
  EepromStats& stats = self->board->eeprom_stats_;
  if (self->busy_until != 0) {  // a write in progress: EEPE reads 1, EERE/EEPE are ignored
    if (v & (kEere | kEepe)) ++stats.ignored_while_busy;
    avr->data[addr] = static_cast<uint8_t>((avr->data[addr] & kEepe) | (v & ~(kEere | kEepe | kEempe)));
    return;
  }
  const bool starts_write = (avr->data[addr] & kEempe) && (v & kEepe);
  self->simavr_write(avr, addr, v, self->simavr_param);
  if (!starts_write) return;
  ++stats.writes;
  avr->data[addr] |= kEepe;
  const uint64_t write_cycles = uint64_t(avr->frequency) * kWriteUs / 1000000u;
  self->busy_until = avr->cycle + write_cycles;
  avr_cycle_timer_register(avr, write_cycles, &EepromTiming::on_write_done, self);
}

avr_cycle_count_t AvrBoard::EepromTiming::on_write_done(avr_t* avr, avr_cycle_count_t, void* param) {
  auto* self = static_cast<EepromTiming*>(param);
  self->busy_until = 0;
  avr->data[kEecrDataAddress] &= static_cast<uint8_t>(~kEepe);
  return 0;
}

void AvrBoard::use_silicon_eeprom_timing() {
  if (eeprom_timing_) return;
  const avr_io_addr_t io = AVR_DATA_TO_IO(kEecrDataAddress);
  if (!avr_->io[io].w.c) throw std::runtime_error("simavr core " + mcu_ + " has no EEPROM write handler");
  eeprom_timing_ = std::make_unique<EepromTiming>(EepromTiming{this, avr_->io[io].w.c, avr_->io[io].w.param, 0});
  // avr_register_io_write() refuses a second handler: replace simavr's and call it ourselves.
  avr_->io[io].w.c = &EepromTiming::on_eecr_write;
  avr_->io[io].w.param = eeprom_timing_.get();
}

// A reset deletes the cycle timers and zeroes EECR; the write in progress ends with it (on
// silicon it completes: simavr has already stored the byte).
void AvrBoard::reset_eeprom_timing() {
  if (eeprom_timing_) eeprom_timing_->busy_until = 0;
}

}  // namespace sim

// AvrBoard's private pieces shared by avr_board.cpp (life cycle) and avr_board_io.cpp (the
// UART, ADC, pin and marker couplings): the C callbacks' parameter blocks.
#pragma once

#include <functional>

extern "C" {
#include <avr_adc.h>
#include <avr_uart.h>
#include <sim_avr.h>
}

#include "sim/avr_board.h"

namespace sim {

struct AvrBoard::Periodic {
  AvrBoard* board;
  uint64_t period_cycles;
  std::function<void()> work;
  static avr_cycle_count_t fire(avr_t*, avr_cycle_count_t when, void* param) {
    auto* self = static_cast<Periodic*>(param);
    self->work();
    return when + self->period_cycles;
  }
};

struct AvrBoard::AdcFeed {
  AvrBoard* board;
  uint8_t feed_index;  // simavr ADC_IRQ_ADC0 + n that carries this channel
  std::function<uint16_t()> millivolts;
  void raise() { avr_raise_irq(board->adc_irqs_ + ADC_IRQ_ADC0 + feed_index, millivolts()); }
};

struct AvrBoard::PinWatch {
  AvrBoard* board;
  PinMeter* meter;
  uint8_t bit;
  static void on_level(avr_irq_t*, uint32_t value, void* param) {
    auto* w = static_cast<PinWatch*>(param);
    w->meter->set_level(value != 0, w->board->cycle());
  }
  static void on_direction(avr_irq_t*, uint32_t ddr, void* param) {
    auto* w = static_cast<PinWatch*>(param);
    w->meter->set_output((ddr >> w->bit) & 1u, w->board->cycle());
  }
};

struct AvrBoard::UartLine {
  AvrBoard* board;
  avr_uart_t* uart;  // simavr's UART0 (its registers and receive FIFO)
  std::function<int()> next_byte;
  uint64_t overruns = 0;
  static avr_cycle_count_t fire(avr_t* avr, avr_cycle_count_t when, void* param);
};

// --eeprom-timing silicon: simavr's EECR write handler, wrapped (avr_board_eeprom.cpp).
struct AvrBoard::EepromTiming {
  AvrBoard* board;
  avr_io_write_t simavr_write;
  void* simavr_param;
  uint64_t busy_until = 0;  // cycle at which the write in progress ends (0: none)
  static void on_eecr_write(avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param);
  static avr_cycle_count_t on_write_done(avr_t* avr, avr_cycle_count_t, void* param);
};

}  // namespace sim

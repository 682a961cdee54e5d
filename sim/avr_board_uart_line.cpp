// AvrBoard's host→board wire for `serve`: bytes at the line rate the firmware programmed, with
// the chip's receive buffer depth (simavr 1.6 queues up to 64 bytes and paces them by an
// 11-bit frame for 8N1: it always counts a parity bit).
#include <cstring>
#include <stdexcept>

extern "C" {
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_regbit.h>
}

#include "sim/avr_board.h"
#include "sim/avr_board_parts.h"

namespace sim {
namespace {

// UDR0's two-level receive FIFO plus the receive shift register (datasheet, "Receive Buffer").
constexpr uint16_t kChipReceiveBytes = 3;

avr_uart_t* find_uart0(avr_t* avr) {
  for (avr_io_t* io = avr->io_port; io; io = io->next)
    if (std::strcmp(io->kind, "uart") == 0 && reinterpret_cast<avr_uart_t*>(io)->name == '0')
      return reinterpret_cast<avr_uart_t*>(io);  // avr_io_t is its first member
  return nullptr;
}

uint64_t frame_cycles(avr_t* avr, const avr_uart_t* u) {
  const uint32_t ubrr = avr_regbit_get(avr, u->ubrrl) | (uint32_t(avr_regbit_get(avr, u->ubrrh)) << 8);
  const uint64_t cycles_per_bit = uint64_t(ubrr + 1) * (avr_regbit_get(avr, u->u2x) ? 8u : 16u);
  static const int kDataBits[8] = {5, 6, 7, 8, 8, 8, 8, 9};
  const int data = kDataBits[avr_regbit_get(avr, u->ucsz) | (avr_regbit_get(avr, u->ucsz2) << 2)];
  const bool parity = ((avr->data[u->r_ucsrc] >> 4) & 3u) != 0;  // UPMn1:0
  const int stop = 1 + avr_regbit_get(avr, u->usbs);
  return cycles_per_bit * uint64_t(1 + data + (parity ? 1 : 0) + stop);
}

}  // namespace

void AvrBoard::feed_uart_line(std::function<int()> next_byte) {
  avr_uart_t* uart = find_uart0(avr_.get());
  if (!uart) throw std::runtime_error("simavr core " + mcu_ + " has no UART0");
  uart_line_ = std::make_unique<UartLine>(UartLine{this, uart, std::move(next_byte)});
  avr_cycle_timer_register(avr_.get(), 1, &UartLine::fire, uart_line_.get());
}

uint64_t AvrBoard::uart_frame_cycles() const {
  const avr_uart_t* uart = uart_line_ ? uart_line_->uart : find_uart0(avr_.get());
  if (!uart || !avr_regbit_get(avr_.get(), uart->rxen)) return 0;
  return frame_cycles(avr_.get(), uart);
}

uint64_t AvrBoard::uart_overruns() const { return uart_line_ ? uart_line_->overruns : 0; }

avr_cycle_count_t AvrBoard::UartLine::fire(avr_t* avr, avr_cycle_count_t when, void* param) {
  auto* line = static_cast<UartLine*>(param);
  avr_uart_t* u = line->uart;
  const uint64_t frame = frame_cycles(avr, u);
  // Receiver off (boot, reset): the host's bytes stay in the pty until the firmware listens.
  if (!avr_regbit_get(avr, u->rxen)) return when + frame;
  u->cycles_per_byte = frame;  // simavr's RXC pacing (and TX) at the chip's frame, not 11 bits
  const int byte = line->next_byte();
  if (byte < 0) return when + frame;
  const uint16_t unread = (u->input.write + uart_fifo_fifo_size - u->input.read) & (uart_fifo_fifo_size - 1);
  if (unread >= kChipReceiveBytes)
    ++line->overruns;  // the chip sets DOR and drops the byte
  else
    avr_raise_irq(line->board->uart_irqs_ + UART_IRQ_INPUT, static_cast<uint8_t>(byte));
  return when + frame;
}

}  // namespace sim

#include "hal/uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#include "hal/critical_section.h"
#include "hal/sleep.h"

namespace {

constexpr uint8_t kRxMask = hal::uart::kRxBufferSize - 1;
constexpr uint8_t kTxMask = hal::uart::kTxBufferSize - 1;
static_assert((hal::uart::kRxBufferSize & kRxMask) == 0, "RX size must be a power of two");
static_assert((hal::uart::kTxBufferSize & kTxMask) == 0, "TX size must be a power of two");
// Actual rate F_CPU / (8 (UBRR + 1)) within 2.5 % of the nominal one (U2X receiver margin).
static_assert(F_CPU / (8UL * (hal::uart::kUbrr + 1)) * 1000UL / hal::uart::kBaud <= 1025UL &&
              F_CPU / (8UL * (hal::uart::kUbrr + 1)) * 1000UL / hal::uart::kBaud >= 975UL,
              "baud error");

// Single producer / single consumer rings: each index is written by one side only, and
// 8-bit indices are read atomically, so only UCSR0B read-modify-writes need a lock.
uint8_t g_rx_buffer[hal::uart::kRxBufferSize];
volatile uint8_t g_rx_head;  // ISR writes
volatile uint8_t g_rx_tail;  // main loop writes
volatile uint8_t g_rx_dropped;
uint8_t g_tx_buffer[hal::uart::kTxBufferSize];
volatile uint8_t g_tx_head;  // main loop writes
volatile uint8_t g_tx_tail;  // ISR writes

// Sends the oldest queued byte (UDR0 must be empty); false when the ring is empty.
inline bool send_next() {
  const uint8_t tail = g_tx_tail;
  if (tail == g_tx_head) return false;
  UDR0 = g_tx_buffer[tail];
  g_tx_tail = static_cast<uint8_t>(tail + 1) & kTxMask;
  return true;
}

}  // namespace

// Cycle budget: 74 measured in simavr (ATmega2560). Store one byte or count it lost.
ISR(USART0_RX_vect) {
  const bool overrun = (UCSR0A & (1 << DOR0)) != 0;  // must be read before UDR0
  const uint8_t byte = UDR0;
  const uint8_t head = g_rx_head;
  const uint8_t next = static_cast<uint8_t>(head + 1) & kRxMask;
  if (overrun || next == g_rx_tail) g_rx_dropped = static_cast<uint8_t>(g_rx_dropped + 1);
  if (next != g_rx_tail) {
    g_rx_buffer[head] = byte;
    g_rx_head = next;
  }
}

// Cycle budget: max 46 measured in simavr. One byte out, or stop the interrupt when empty.
ISR(USART0_UDRE_vect) {
  if (!send_next()) UCSR0B &= static_cast<uint8_t>(~(1 << UDRIE0));
}

namespace hal {
namespace uart {

void init() {
  UBRR0 = kUbrr;
  UCSR0A = (1 << U2X0);
  UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);  // 8 data bits, no parity, 1 stop bit
  UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
}

bool rx_available() { return g_rx_head != g_rx_tail; }

bool read(uint8_t& byte) {
  const uint8_t tail = g_rx_tail;
  if (tail == g_rx_head) return false;
  byte = g_rx_buffer[tail];
  g_rx_tail = static_cast<uint8_t>(tail + 1) & kRxMask;
  return true;
}

void write(uint8_t byte) {
  const uint8_t head = g_tx_head;
  const uint8_t next = static_cast<uint8_t>(head + 1) & kTxMask;
  while (next == g_tx_tail) {
    if (interrupts_enabled()) {
      sleep::idle_unless([] { return g_tx_tail != static_cast<uint8_t>((g_tx_head + 1) & kTxMask); });
    } else if (UCSR0A & (1 << UDRE0)) {
      send_next();  // interrupts off: the UDRE ISR cannot run, so drain by polling
    }
  }
  g_tx_buffer[head] = byte;
  g_tx_head = next;
  CriticalSection lock;  // UCSR0B is also changed by the UDRE ISR
  UCSR0B |= (1 << UDRIE0);
}

void flush() {
  while (g_tx_head != g_tx_tail) {
    if (interrupts_enabled()) {
      sleep::idle_unless([] { return g_tx_head == g_tx_tail; });
    } else if (UCSR0A & (1 << UDRE0)) {
      send_next();
    }
  }
}

uint8_t take_rx_dropped() {
  CriticalSection lock;
  const uint8_t dropped = g_rx_dropped;
  g_rx_dropped = 0;
  return dropped;
}

}  // namespace uart
}  // namespace hal

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
// Loss marks: bit i set = bytes were lost just before slot i (set by the ISR when it stores,
// cleared by the reader when it reports); g_rx_lost_pending = lost after the newest byte.
// 16 bytes of RAM instead of a second ring; touched only when something was lost.
volatile uint8_t g_rx_lost_bits[hal::uart::kRxBufferSize / 8];
volatile uint8_t g_rx_lost_pending;
hal::uart::RxObserver g_rx_observer;  // set before the receiver is enabled, then constant
hal::uart::TxWaitHook g_tx_wait_hook;
bool g_in_tx_wait_hook;  // main-loop context only: a write from inside the hook just sleeps
uint8_t g_tx_buffer[hal::uart::kTxBufferSize];
volatile uint8_t g_tx_head;  // main loop writes
volatile uint8_t g_tx_tail;  // ISR writes

// Sends the oldest queued byte (UDR0 must be empty); false when the ring is empty.
inline uint8_t lost_bit(uint8_t slot) { return static_cast<uint8_t>(1u << (slot & 7u)); }

inline bool send_next() {
  const uint8_t tail = g_tx_tail;
  if (tail == g_tx_head) return false;
  UDR0 = g_tx_buffer[tail];
  g_tx_tail = static_cast<uint8_t>(tail + 1) & kTxMask;
  return true;
}

}  // namespace

// Cycle budget: see hal/README.md (measured in simavr). Show the byte to the observer, then
// store it, or mark it lost when the ring is full.
ISR(USART0_RX_vect) {
  const bool overrun = (UCSR0A & (1 << DOR0)) != 0;  // must be read before UDR0
  const uint8_t byte = UDR0;
  if (g_rx_observer != nullptr) g_rx_observer(byte, overrun);
  const uint8_t head = g_rx_head;
  const uint8_t next = static_cast<uint8_t>(head + 1) & kRxMask;
  if (next == g_rx_tail) {
    g_rx_lost_pending = 1;
    return;
  }
  // A hardware overrun lost frames next to this byte, before or after it (the datasheet's
  // buffering leaves which one open): mark both sides; a false mark costs one resend.
  if (g_rx_lost_pending || overrun) g_rx_lost_bits[head >> 3] |= lost_bit(head);
  g_rx_buffer[head] = byte;
  g_rx_head = next;
  g_rx_lost_pending = overrun;
}

// Cycle budget: max 103 measured in simavr (send_next is shared with the polling writer, so it
// is called, not inlined). One byte out, or stop the interrupt when empty.
ISR(USART0_UDRE_vect) {
  if (!send_next()) UCSR0B &= static_cast<uint8_t>(~(1 << UDRIE0));
}

namespace hal {
namespace uart {

void init(RxObserver observer) {
  g_rx_observer = observer;
  UBRR0 = kUbrr;
  UCSR0A = (1 << U2X0);
  UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);  // 8 data bits, no parity, 1 stop bit
  UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
}

void set_tx_wait_hook(TxWaitHook hook) { g_tx_wait_hook = hook; }

bool rx_available() { return g_rx_head != g_rx_tail || g_rx_lost_pending; }

RxEvent read(uint8_t& byte) {
  CriticalSection lock;  // the loss marks share bytes with the slots the ISR marks
  const uint8_t tail = g_rx_tail;
  if (tail == g_rx_head) {  // empty: a loss after the newest byte is reported here
    if (!g_rx_lost_pending) return RxEvent::kNone;
    g_rx_lost_pending = 0;
    return RxEvent::kLost;
  }
  const uint8_t bit = lost_bit(tail);
  if (g_rx_lost_bits[tail >> 3] & bit) {  // the mark first, the byte on the next call
    g_rx_lost_bits[tail >> 3] &= static_cast<uint8_t>(~bit);
    return RxEvent::kLost;
  }
  byte = g_rx_buffer[tail];
  g_rx_tail = static_cast<uint8_t>(tail + 1) & kRxMask;
  return RxEvent::kByte;
}

void write(uint8_t byte) {
  const uint8_t head = g_tx_head;
  const uint8_t next = static_cast<uint8_t>(head + 1) & kTxMask;
  while (next == g_tx_tail) {
    if (interrupts_enabled()) {
      if (g_tx_wait_hook != nullptr && !g_in_tx_wait_hook) {
        g_in_tx_wait_hook = true;
        g_tx_wait_hook();
        g_in_tx_wait_hook = false;
      }
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

}  // namespace uart
}  // namespace hal

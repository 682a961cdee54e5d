// Interrupt-driven UART0, 8N1, 115200 baud, with RX and TX ring buffers.
// Baud: U2X0 = 1, UBRR0 = 16 -> 16 MHz / (8 x 17) = 117,647 baud, +2.1 % from 115,200.
// Inside the datasheet's recommended +-2.5 % receiver error for 8N1 in double-speed mode
// (without U2X, UBRR 8 would be -3.5 %); the Mega2560's USB bridge (16U2 at 16 MHz) uses the
// same divider, so both ends run at the same rate.
#pragma once
#include <stdint.h>

namespace hal {
namespace uart {

constexpr uint32_t kBaud = 115200;
constexpr uint8_t kUbrr = 16;       // with U2X0
// Powers of two: index wrap is a mask. RX holds a whole 96-char host line; TX is smaller since
// a full TX ring only makes the writer sleep until the ISR drains it (64 B = 5.6 ms at 115200),
// and static RAM is the scarcer resource (issue 2: <= 1.5 KB per image).
constexpr uint8_t kRxBufferSize = 128;
constexpr uint8_t kTxBufferSize = 64;

// Sees every received byte inside the RX interrupt, before the ring (so also the bytes a full
// ring drops); `overrun`: the hardware lost frames around this byte. Must be short and
// straight-line: it delays the next byte and the tick. hal/ knows nothing of what it looks for.
using RxObserver = void (*)(uint8_t byte, bool overrun);

// Enables the receiver last: the host may send from then on. `observer` may be nullptr.
void init(RxObserver observer);

// What the main loop takes from the RX ring, in arrival order. kLost stands where bytes were
// dropped (ring full, or hardware overrun) — between the bytes before and after it — so the
// line layer can discard the damaged line instead of gluing its pieces to the next one.
enum class RxEvent : uint8_t { kNone, kByte, kLost };
RxEvent read(uint8_t& byte);  // `byte` is set only for kByte
bool rx_available();          // read() would return something other than kNone

// Queues one byte. When the TX buffer is full it sleeps until the transmitter frees a slot
// (interrupts must be enabled then; with interrupts off it pushes bytes out by polling).
void write(uint8_t byte);

// Called (not nested) each time write() finds the TX ring full with interrupts enabled, before
// it sleeps for a free slot: the firmware runs a due control step there, so a long reply never
// delays it (M503 measured a 201 ms gap between 128 ms steps without it).
using TxWaitHook = void (*)();
void set_tx_wait_hook(TxWaitHook hook);

// Waits until the TX ring is empty; the hardware sends the last byte or two by itself even
// with interrupts off (used before a deliberate hang).
void flush();

}  // namespace uart
}  // namespace hal

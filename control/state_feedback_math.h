// The one product the state-feedback runtime is built from: int16 mantissa × int32 signal,
// rounded to the upper 32 bits of the 48-bit product, i.e. round(m·x / 2^16).
// On AVR with MUL it is hand-written (8 MULs, ~60 cycles): avr-gcc 5.4 builds the C version from
// libgcc widening-multiply calls at ~130 cycles, which would put a 5-state step over budget.
// Host builds (and the tests) use the C version; test_state_feedback_math.cpp checks it against
// 64-bit arithmetic and the AVR benchmark checks the assembly the same way on the simulator.
#pragma once

#include <stdint.h>

namespace control {
namespace sf {

// Portable reference: two 16×16→32 products. Requires |m| <= 32767 (the design never emits
// −32768), so m·x_lo + 2^15 cannot overflow.
inline int32_t mulhi16_c(int16_t m, int32_t x) {
  const int16_t x_hi = static_cast<int16_t>(static_cast<uint32_t>(x) >> 16);
  const uint16_t x_lo = static_cast<uint16_t>(x);
  const int32_t hi = static_cast<int32_t>(m) * x_hi;
  const int32_t lo = static_cast<int32_t>(m) * static_cast<int32_t>(x_lo) + 0x8000L;
  return hi + (lo >> 16);
}

#if defined(__AVR_HAVE_MUL__)
// Unsigned 16×32 product from byte MULs into bytes 1..5 (byte 0 never carries: it has one
// contributor), +2^15 for rounding, then the two's-complement corrections: −x·2^16 if m < 0,
// −m·2^32 if x < 0. r1 (avr-gcc's zero register) is restored at the end. Always inlined: as a
// call (-Os's choice) the argument moves and register saves cost ~20 cycles a product, ~260 on
// the 5-state law call (simavr), for ~1.1 kB of flash.
__attribute__((always_inline)) inline int32_t mulhi16(int16_t m, int32_t x) {
  int32_t r;
  uint8_t b1, z;
  asm("clr  %[z]\n\t"
      "mul  %A[m], %A[x]\n\t"
      "mov  %[b1], r1\n\t"
      "mul  %A[m], %C[x]\n\t"
      "movw %A[r], r0\n\t"
      "mul  %B[m], %D[x]\n\t"
      "movw %C[r], r0\n\t"
      "mul  %A[m], %B[x]\n\t"
      "add  %[b1], r0\n\t"
      "adc  %A[r], r1\n\t"
      "adc  %B[r], %[z]\n\t"
      "adc  %C[r], %[z]\n\t"
      "adc  %D[r], %[z]\n\t"
      "mul  %B[m], %A[x]\n\t"
      "add  %[b1], r0\n\t"
      "adc  %A[r], r1\n\t"
      "adc  %B[r], %[z]\n\t"
      "adc  %C[r], %[z]\n\t"
      "adc  %D[r], %[z]\n\t"
      "mul  %A[m], %D[x]\n\t"
      "add  %B[r], r0\n\t"
      "adc  %C[r], r1\n\t"
      "adc  %D[r], %[z]\n\t"
      "mul  %B[m], %B[x]\n\t"
      "add  %A[r], r0\n\t"
      "adc  %B[r], r1\n\t"
      "adc  %C[r], %[z]\n\t"
      "adc  %D[r], %[z]\n\t"
      "mul  %B[m], %C[x]\n\t"
      "add  %B[r], r0\n\t"
      "adc  %C[r], r1\n\t"
      "adc  %D[r], %[z]\n\t"
      "lsl  %[b1]\n\t"  // carry = bit 15 of the product: the +2^15 rounding
      "adc  %A[r], %[z]\n\t"
      "adc  %B[r], %[z]\n\t"
      "adc  %C[r], %[z]\n\t"
      "adc  %D[r], %[z]\n\t"
      "sbrs %B[m], 7\n\t"
      "rjmp 1f\n\t"
      "sub  %A[r], %A[x]\n\t"
      "sbc  %B[r], %B[x]\n\t"
      "sbc  %C[r], %C[x]\n\t"
      "sbc  %D[r], %D[x]\n"
      "1:\n\t"
      "sbrs %D[x], 7\n\t"
      "rjmp 2f\n\t"
      "sub  %C[r], %A[m]\n\t"
      "sbc  %D[r], %B[m]\n"
      "2:\n\t"
      "clr  __zero_reg__"
      : [r] "=&r"(r), [b1] "=&r"(b1), [z] "=&r"(z)
      : [m] "r"(m), [x] "r"(x)
      : "r0");
  return r;
}
#else
inline int32_t mulhi16(int16_t m, int32_t x) { return mulhi16_c(m, x); }
#endif

// The same product as a call (~20 cycles more, ~90 bytes of flash less per site): for every
// product but the time update's, whose call is the step's longest on 5-state models.
__attribute__((noinline)) inline int32_t mulhi16_call(int16_t m, int32_t x) { return mulhi16(m, x); }

}  // namespace sf
}  // namespace control

// The one way to keep an interrupt out of a multi-byte access or a read-modify-write.
// Saves SREG and disables interrupts; restores the saved SREG (not a blind sei) on scope
// exit, so it nests and is harmless inside an ISR.
#pragma once
#include <avr/io.h>
#include <stdint.h>

namespace hal {

class CriticalSection {
 public:
  // always_inline: an out-of-line call would cost a stack frame and, inside an ISR, the
  // saving of every call-clobbered register.
  __attribute__((always_inline)) CriticalSection() : sreg_(SREG) {
    __asm__ volatile("cli" ::: "memory");
  }
  __attribute__((always_inline)) ~CriticalSection() {
    __asm__ volatile("" ::: "memory");  // keep the guarded accesses inside the section
    SREG = sreg_;
  }
  CriticalSection(const CriticalSection&) = delete;
  CriticalSection& operator=(const CriticalSection&) = delete;

 private:
  uint8_t sreg_;
};

// Global interrupt enable, once start-up has configured every interrupt source.
inline void enable_interrupts() { __asm__ volatile("sei" ::: "memory"); }

// True when the global interrupt flag is set (used to refuse to block with interrupts off).
inline bool interrupts_enabled() { return (SREG & (1 << SREG_I)) != 0; }

}  // namespace hal

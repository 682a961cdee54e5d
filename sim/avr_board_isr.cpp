// Cycles each interrupt handler runs, from simavr's "interrupt running" signal: raised with the
// vector number when the core jumps to the vector, lowered (or set back to the interrupted
// vector) at RETI. simavr adds no cycles for the entry itself (silicon: 4–5), so add those when
// comparing with a budget; nesting is handled, though the firmware never re-enables interrupts.
extern "C" {
#include <avr_timer.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_interrupts.h>
}

#include <cstring>
#include <string>

#include "sim/avr_board.h"

namespace sim {
namespace {

// The vector `vector_of` picks from I/O module `name` ('0') of `kind` (avr_io_t is the first
// member of every module struct), or -1.
template <typename Module, typename VectorOf>
int module_vector(avr_t* avr, const char* kind, char name, VectorOf vector_of) {
  for (avr_io_t* io = avr->io_port; io; io = io->next) {
    if (std::strcmp(io->kind, kind) != 0) continue;
    auto* module = reinterpret_cast<Module*>(io);
    if (module->name == name) return vector_of(*module).vector;
  }
  return -1;
}

}  // namespace

void AvrBoard::attach_isr_meter() {
  avr_t* avr = avr_.get();
  const struct {
    const char* name;
    int vector;
  } named[] = {
      {"tick", module_vector<avr_timer_t>(avr, "timer", '0',
                                          [](avr_timer_t& t) { return t.comp[AVR_TIMER_COMPA].interrupt; })},
      {"uart rx", module_vector<avr_uart_t>(avr, "uart", '0', [](avr_uart_t& u) { return u.rxc; })},
      {"uart udre", module_vector<avr_uart_t>(avr, "uart", '0', [](avr_uart_t& u) { return u.udrc; })},
  };
  for (const auto& n : named)
    if (n.vector > 0) isr_cycles_.push_back(IsrCycleStats{n.name, uint8_t(n.vector)});
  avr_irq_register_notify(
      avr_get_interrupt_irq(avr, AVR_INT_ANY) + AVR_INT_IRQ_RUNNING,
      [](avr_irq_t*, uint32_t vector, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        const uint64_t now = self->avr_->cycle;
        auto& open = self->isr_open_;
        // RETI reports the vector it returns to (0: none); anything else is an entry.
        const bool leaves = !open.empty() && (vector == 0 || (open.size() >= 2 &&
                                                              open[open.size() - 2].vector == vector));
        if (leaves) {
          self->record_isr(open.back().vector, now - open.back().start_cycle);
          open.pop_back();
        } else if (vector != 0 && (open.empty() || open.back().vector != vector)) {
          open.push_back(OpenIsr{uint8_t(vector), now});
        }
      },
      this);
}

void AvrBoard::record_isr(uint8_t vector, uint64_t cycles) {
  IsrCycleStats* s = nullptr;
  for (IsrCycleStats& each : isr_cycles_)
    if (each.vector == vector) s = &each;
  if (!s) {
    isr_cycles_.push_back(IsrCycleStats{"vector " + std::to_string(vector), vector});
    s = &isr_cycles_.back();
  }
  ++s->count;
  s->total_cycles += cycles;
  if (cycles > s->max_cycles) s->max_cycles = cycles;
}

}  // namespace sim

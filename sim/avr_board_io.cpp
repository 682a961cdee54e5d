// AvrBoard's couplings to simavr's peripherals: UART bytes, thermistor ADC injection (with the
// ATmega2560 ADC8–15 remap), duty meters on output pins and the GPIOR0 control-step marker.
#include <cstring>
#include <stdexcept>

extern "C" {
#include <avr_adc.h>
#include <avr_ioport.h>
#include <avr_uart.h>
#include <sim_avr.h>
}

#include "sim/avr_board.h"
#include "sim/avr_board_parts.h"

namespace sim {
namespace {

constexpr uint16_t kGpior0DataAddress = 0x3E;  // GPIOR0 (I/O 0x1E) on both MCUs
constexpr uint8_t kAdcMuxHighChannels = 0x20;  // MUX5:0 = 1 0 0xxx selects ADC8..ADC15

}  // namespace

void AvrBoard::attach_uart() {
  // POLL_SLEEP usleeps on every UCSRA poll and STDIO echoes lines to our stdout: clear both.
  uint32_t flags = 0;
  avr_ioctl(avr_.get(), AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~uint32_t(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
  avr_ioctl(avr_.get(), AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  uart_irqs_ = avr_io_getirq(avr_.get(), AVR_IOCTL_UART_GETIRQ('0'), 0);
  avr_irq_register_notify(
      uart_irqs_ + UART_IRQ_OUTPUT,
      [](avr_irq_t*, uint32_t value, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        for (auto& handler : self->uart_handlers_) handler(static_cast<uint8_t>(value));
      },
      this);
  avr_irq_register_notify(
      uart_irqs_ + UART_IRQ_OUT_XON,
      [](avr_irq_t*, uint32_t, void* param) { static_cast<AvrBoard*>(param)->uart_xon_ = true; }, this);
  avr_irq_register_notify(
      uart_irqs_ + UART_IRQ_OUT_XOFF,
      [](avr_irq_t*, uint32_t value, void* param) {
        if (value) static_cast<AvrBoard*>(param)->uart_xon_ = false;
      },
      this);
}

bool AvrBoard::uart_send(uint8_t byte) {
  if (!uart_xon_) return false;
  avr_raise_irq(uart_irqs_ + UART_IRQ_INPUT, byte);  // may signal XOFF if the FIFO filled
  return true;
}

void AvrBoard::attach_adc() {
  adc_irqs_ = avr_io_getirq(avr_.get(), AVR_IOCTL_ADC_GETIRQ, 0);
  // simavr computes the result when ADCL is read, from the last value raised; a fresh value at
  // each conversion start is what silicon samples (and lets the sensor model add noise).
  avr_irq_register_notify(
      adc_irqs_ + ADC_IRQ_OUT_TRIGGER,
      [](avr_irq_t*, uint32_t value, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        union {
          avr_adc_mux_t mux;
          uint32_t raw;
        } trigger{};
        trigger.raw = value;
        if (trigger.mux.kind != ADC_MUX_SINGLE) return;
        for (auto& feed : self->adc_feeds_)
          if (feed->feed_index == trigger.mux.src) feed->raise();
      },
      this);
}

void AvrBoard::set_adc_source(uint8_t channel, std::function<uint16_t()> millivolts) {
  // simavr 1.6 keeps 8 input values (upstream issue 383): ADC8..15 are fed through slots 0..7,
  // see apply_adc_remap().
  const uint8_t feed_index = channel & 7u;
  for (auto& feed : adc_feeds_)
    if (feed->feed_index == feed_index) throw std::logic_error("ADC slot fed twice");
  adc_feeds_.push_back(std::make_unique<AdcFeed>(AdcFeed{this, feed_index, std::move(millivolts)}));
  adc_feeds_.back()->raise();
}

uint32_t AvrBoard::adc_ref_mv() const { return avr_->avcc; }

void AvrBoard::apply_adc_remap() {
  if (!remap_high_adc_) return;
  for (avr_io_t* io = avr_->io_port; io; io = io->next) {
    if (std::strcmp(io->kind, "adc") != 0) continue;
    auto* adc = reinterpret_cast<avr_adc_t*>(io);  // avr_io_t is its first member
    for (uint8_t n = 0; n < 8; ++n) {
      adc->muxmode[kAdcMuxHighChannels + n].kind = ADC_MUX_SINGLE;
      adc->muxmode[kAdcMuxHighChannels + n].src = n;
    }
    return;
  }
  throw std::runtime_error("simavr core " + mcu_ + " has no ADC");
}

void AvrBoard::watch_pin(boards::Pin pin, PinMeter* meter) {
  const uint32_t ioctl = AVR_IOCTL_IOPORT_GETIRQ(pin.port);
  avr_irq_t* port = avr_io_getirq(avr_.get(), ioctl, 0);
  if (!port) throw std::runtime_error(std::string("no port ") + pin.port + " on " + mcu_);
  pin_watches_.push_back(std::make_unique<PinWatch>(PinWatch{this, meter, pin.bit}));
  PinWatch* w = pin_watches_.back().get();
  avr_irq_register_notify(port + IOPORT_IRQ_PIN0 + pin.bit, &PinWatch::on_level, w);
  avr_irq_register_notify(port + IOPORT_IRQ_DIRECTION_ALL, &PinWatch::on_direction, w);
}

void AvrBoard::attach_step_marker() {
  // GPIOR0 has no simavr module: the callback must store the byte itself.
  avr_register_io_write(
      avr_.get(), kGpior0DataAddress,
      [](avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        avr->data[addr] = v;
        if (v != 0) {
          StepCycleStats& s = self->step_cycles_;
          if (s.count != 0 && avr->cycle - s.last_start_cycle > s.max_gap_cycles)
            s.max_gap_cycles = avr->cycle - s.last_start_cycle;
          s.last_start_cycle = avr->cycle;
          self->step_open_ = true;
          self->step_start_cycle_ = avr->cycle;
        } else if (self->step_open_) {
          self->step_open_ = false;
          const uint64_t cycles = avr->cycle - self->step_start_cycle_;
          StepCycleStats& s = self->step_cycles_;
          ++s.count;
          s.total_cycles += cycles;
          if (cycles > s.max_cycles) s.max_cycles = cycles;
        }
      },
      this);
}

}  // namespace sim

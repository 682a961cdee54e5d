#include "sim/avr_board.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>

extern "C" {
#include <avr_adc.h>
#include <avr_ioport.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_elf.h>
}

namespace sim {
namespace {

constexpr uint16_t kGpior0DataAddress = 0x3E;  // GPIOR0 (I/O 0x1E) on both MCUs
constexpr std::size_t kMaxMessages = 64;        // keep the first simavr messages, count the rest
constexpr uint8_t kAdcMuxHighChannels = 0x20;   // MUX5:0 = 1 0 0xxx selects ADC8..ADC15
// Lets avr_run_one() execute up to this many cycles per call while no timer is due and no
// interrupt is pending (simavr still stops at every timer and interrupt, so timing is exact);
// avr_init() and every reset set it to 1, which costs a timer scan per instruction.
constexpr avr_cycle_count_t kRunCycleLimit = 4096;

// elf_read_firmware() mallocs these; avr_load_firmware() copies what it needs.
struct ElfFirmware {
  elf_firmware_t fw{};
  ~ElfFirmware() {
    std::free(fw.flash);
    std::free(fw.eeprom);
    std::free(fw.fuse);
    std::free(fw.lockbits);
    for (uint32_t i = 0; i < fw.symbolcount; ++i) std::free(fw.symbol[i]);
    std::free(fw.symbol);
  }
};

void no_sleep(avr_t*, avr_cycle_count_t) {}  // fast-forward: never wait for the wall clock

}  // namespace

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

AvrBoard::AvrBoard(const BoardSpec& spec, const std::string& elf_path) {
  load(spec, elf_path);
  attach_uart();
  attach_adc();
  watch_pin(spec.hotend_heater, heater_.get());
  watch_pin(spec.part_fan, fan_.get());
  attach_step_marker();
  remap_high_adc_ = spec.hotend_adc_channel >= 8 || spec.bed_adc_channel >= 8;
  apply_adc_remap();
}

AvrBoard::~AvrBoard() {
  if (!avr_) return;
  avr_->custom.data = nullptr;
  avr_terminate(avr_);
  std::free(avr_);  // allocated by the core maker with malloc (avr_core_allocate)
}

AvrBoard* AvrBoard::from(avr_t* avr) {
  return avr ? static_cast<AvrBoard*>(avr->custom.data) : nullptr;
}

void AvrBoard::load(const BoardSpec& spec, const std::string& elf_path) {
  // Route simavr's messages to the board that raised them (and silence its loader chatter).
  static std::once_flag logger_once;
  std::call_once(logger_once, [] { avr_global_logger_set(&AvrBoard::log_trampoline); });
  auto elf = std::make_unique<ElfFirmware>();
  if (elf_read_firmware(elf_path.c_str(), &elf->fw) != 0)
    throw std::runtime_error("cannot read firmware ELF " + elf_path);
  mcu_ = elf->fw.mmcu[0] ? elf->fw.mmcu : spec.mcu;
  if (mcu_ != spec.mcu)
    throw std::runtime_error(elf_path + " is built for " + mcu_ + ", board " + spec.id +
                             " has an " + spec.mcu);
  avr_ = avr_make_mcu_by_name(mcu_.c_str());
  if (!avr_) throw std::runtime_error("simavr has no core for " + mcu_);
  avr_init(avr_);
  // Without an .mmcu section the ELF carries no clock or voltages: use the board's.
  if (!elf->fw.frequency) elf->fw.frequency = spec.cpu_hz;
  if (!elf->fw.avcc) elf->fw.avcc = spec.adc_ref_mv;
  if (!elf->fw.vcc) elf->fw.vcc = spec.adc_ref_mv;
  if (!elf->fw.aref) elf->fw.aref = spec.adc_ref_mv;
  avr_load_firmware(avr_, &elf->fw);
  image_size_.flash_bytes = elf->fw.flashsize;
  image_size_.ram_bytes = elf->fw.datasize + elf->fw.bsssize;

  // avr_t has no user pointer; custom.data is only handed to custom.init/deinit, which we
  // leave unset, so it can carry this board back to the C callbacks.
  avr_->custom.data = this;
  avr_->log = LOG_WARNING;  // avr_init() sets 1, which hides crash reasons
  avr_->sleep = no_sleep;
  avr_->run_cycle_limit = kRunCycleLimit;
  core_reset_ = avr_->reset;
  avr_->reset = &AvrBoard::reset_trampoline;
}

void AvrBoard::attach_uart() {
  // POLL_SLEEP usleeps on every UCSRA poll and STDIO echoes lines to our stdout: clear both.
  uint32_t flags = 0;
  avr_ioctl(avr_, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~uint32_t(AVR_UART_FLAG_POLL_SLEEP | AVR_UART_FLAG_STDIO);
  avr_ioctl(avr_, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  uart_irqs_ = avr_io_getirq(avr_, AVR_IOCTL_UART_GETIRQ('0'), 0);
  avr_irq_register_notify(
      uart_irqs_ + UART_IRQ_OUTPUT,
      [](avr_irq_t*, uint32_t value, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        if (self->uart_handler_) self->uart_handler_(static_cast<uint8_t>(value));
      },
      this);
  avr_irq_register_notify(
      uart_irqs_ + UART_IRQ_OUT_XON,
      [](avr_irq_t*, uint32_t, void* param) { static_cast<AvrBoard*>(param)->uart_xon_ = true; },
      this);
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
  adc_irqs_ = avr_io_getirq(avr_, AVR_IOCTL_ADC_GETIRQ, 0);
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
  avr_irq_t* port = avr_io_getirq(avr_, ioctl, 0);
  if (!port) throw std::runtime_error(std::string("no port ") + pin.port + " on " + mcu_);
  pin_watches_.push_back(std::make_unique<PinWatch>(PinWatch{this, meter, pin.bit}));
  PinWatch* w = pin_watches_.back().get();
  avr_irq_register_notify(port + IOPORT_IRQ_PIN0 + pin.bit, &PinWatch::on_level, w);
  avr_irq_register_notify(port + IOPORT_IRQ_DIRECTION_ALL, &PinWatch::on_direction, w);
}

void AvrBoard::attach_step_marker() {
  // GPIOR0 has no simavr module: the callback must store the byte itself.
  avr_register_io_write(
      avr_, kGpior0DataAddress,
      [](avr_t* avr, avr_io_addr_t addr, uint8_t v, void* param) {
        auto* self = static_cast<AvrBoard*>(param);
        avr->data[addr] = v;
        if (v != 0) {
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

void AvrBoard::every(uint32_t period_us, std::function<void()> work) {
  const uint64_t period_cycles = uint64_t(avr_->frequency) * period_us / 1000000u;
  periodics_.push_back(std::make_unique<Periodic>(Periodic{this, period_cycles, std::move(work)}));
  avr_cycle_timer_register(avr_, period_cycles, &Periodic::fire, periodics_.back().get());
}

void AvrBoard::reset_trampoline(avr_t* avr) {
  AvrBoard* self = from(avr);
  if (self && self->core_reset_) self->core_reset_(avr);
  if (self) self->after_reset();
}

void AvrBoard::after_reset() {
  // avr_reset() has just deleted every cycle timer and zeroed the I/O space.
  ++reset_count_;
  avr_->run_cycle_limit = kRunCycleLimit;
  const uint64_t now = cycle();
  heater_->reset(now);
  fan_->reset(now);
  step_open_ = false;
  uart_xon_ = false;  // RX is off until the firmware enables it again (which signals XON)
  apply_adc_remap();
  for (auto& p : periodics_) avr_cycle_timer_register(avr_, p->period_cycles, &Periodic::fire, p.get());
  for (auto& hook : reset_hooks_) hook();
}

CpuState AvrBoard::run_until(uint64_t end_cycle) {
  while (avr_->cycle < end_cycle) {
    const int state = avr_run(avr_);
    if (state == cpu_Done || state == cpu_Stopped) return CpuState::kStopped;
    if (state == cpu_Crashed) return CpuState::kCrashed;
  }
  return CpuState::kRunning;
}

uint64_t AvrBoard::cycle() const { return avr_->cycle; }
double AvrBoard::time_s() const { return double(avr_->cycle) / double(avr_->frequency); }
double AvrBoard::frequency_hz() const { return double(avr_->frequency); }
uint64_t AvrBoard::cycles_from_s(double seconds) const {
  return static_cast<uint64_t>(seconds * double(avr_->frequency) + 0.5);
}

void AvrBoard::record_message(const std::string& text) {
  if (messages_.size() < kMaxMessages) messages_.push_back(text);
  else ++messages_dropped_;
}

void AvrBoard::log_trampoline(avr_t* avr, int level, const char* format, va_list args) {
  if (level > LOG_WARNING) return;
  char text[256];
  std::vsnprintf(text, sizeof text, format, args);
  AvrBoard* self = from(avr);
  if (self) self->record_message(text);
  else if (level <= LOG_ERROR) std::fputs(text, stderr);
}

}  // namespace sim

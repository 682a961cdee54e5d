#include "sim/avr_board.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "sim/avr_board_parts.h"
#include "sim/firmware_image.h"

extern "C" {
#include <sim_avr.h>
#include <sim_elf.h>
}

namespace sim {
namespace {

constexpr std::size_t kMaxMessages = 64;  // keep the first simavr messages, count the rest
// Lets avr_run_one() execute up to this many cycles per call while no timer is due and no
// interrupt is pending (simavr still stops at every timer and interrupt, so timing is exact);
// avr_init() and every reset set it to 1, which costs a timer scan per instruction.
constexpr avr_cycle_count_t kRunCycleLimit = 4096;

void no_sleep(avr_t*, avr_cycle_count_t) {}  // fast-forward: never wait for the wall clock

}  // namespace

AvrBoard::AvrBoard(const BoardSpec& spec, const std::string& elf_path) {
  load(spec, elf_path);
  attach_uart();
  attach_adc();
  watch_pin(spec.hotend_heater, &heater_);
  watch_pin(spec.part_fan, &fan_);
  attach_step_marker();
  attach_isr_meter();
  remap_high_adc_ = spec.hotend_adc_channel >= 8 || spec.bed_adc_channel >= 8;
  apply_adc_remap();
}

AvrBoard::~AvrBoard() = default;

void AvrBoard::AvrDeleter::operator()(avr_t* avr) const {
  avr->custom.data = nullptr;
  avr_terminate(avr);
  std::free(avr);  // allocated by the core maker with malloc (avr_core_allocate)
}

AvrBoard* AvrBoard::from(avr_t* avr) { return avr ? static_cast<AvrBoard*>(avr->custom.data) : nullptr; }

void AvrBoard::load(const BoardSpec& spec, const std::string& elf_path) {
  // Route simavr's messages to the board that raised them (and silence its loader chatter).
  static std::once_flag logger_once;
  std::call_once(logger_once, [] { avr_global_logger_set(&AvrBoard::log_trampoline); });
  FirmwareImage image(elf_path);
  mcu_ = image.mcu().empty() ? spec.mcu : image.mcu();
  if (mcu_ != spec.mcu)
    throw std::runtime_error(elf_path + " is built for " + mcu_ + ", board " + spec.id + " has an " +
                             spec.mcu);
  avr_t* avr = avr_make_mcu_by_name(mcu_.c_str());
  if (!avr) throw std::runtime_error("simavr has no core for " + mcu_);
  avr_init(avr);
  avr_.reset(avr);
  image.default_clock_and_voltages(spec.cpu_hz, spec.adc_ref_mv);
  avr_load_firmware(avr, &image.elf());
  image_size_ = image.size();
  for (uint32_t a = stack_floor(); a <= avr->ramend; ++a) avr->data[a] = kStackPaint;

  // avr_t has no user pointer; custom.data is only handed to custom.init/deinit, which we
  // leave unset, so it can carry this board back to the C callbacks.
  avr_->custom.data = this;
  avr_->log = LOG_WARNING;  // avr_init() sets 1, which hides crash reasons
  avr_->sleep = no_sleep;
  avr_->run_cycle_limit = kRunCycleLimit;
  core_reset_ = avr_->reset;
  avr_->reset = &AvrBoard::reset_trampoline;
}

uint32_t AvrBoard::stack_floor() const {
  // SRAM starts after the I/O space; the static data (.data + .bss) comes first, then .noinit
  // (the reset cause, 1 byte; simavr's loader does not count it): 16 bytes are left for it.
  return uint32_t(avr_->ioend) + 1 + image_size_.ram_bytes + 16;
}

uint32_t AvrBoard::stack_room_bytes() const { return uint32_t(avr_->ramend) + 1 - stack_floor(); }

uint32_t AvrBoard::stack_max_bytes() const {
  uint32_t a = stack_floor();
  while (a <= avr_->ramend && avr_->data[a] == kStackPaint) ++a;
  return uint32_t(avr_->ramend) + 1 - a;
}

void AvrBoard::every(uint32_t period_us, std::function<void()> work) {
  const uint64_t period_cycles = uint64_t(avr_->frequency) * period_us / 1000000u;
  periodics_.push_back(std::make_unique<Periodic>(Periodic{this, period_cycles, std::move(work)}));
  avr_cycle_timer_register(avr_.get(), period_cycles, &Periodic::fire, periodics_.back().get());
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
  heater_.reset(now);
  fan_.reset(now);
  step_open_ = false;
  isr_open_.clear();
  reset_eeprom_timing();
  uart_xon_ = false;  // RX is off until the firmware enables it again (which signals XON)
  apply_adc_remap();
  for (auto& p : periodics_) avr_cycle_timer_register(avr_.get(), p->period_cycles, &Periodic::fire, p.get());
  if (uart_line_) avr_cycle_timer_register(avr_.get(), 1, &UartLine::fire, uart_line_.get());
  for (auto& hook : reset_hooks_) hook();
}

CpuState AvrBoard::run_until(uint64_t end_cycle) {
  while (avr_->cycle < end_cycle) {
    const int state = avr_run(avr_.get());
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
  if (messages_.size() < kMaxMessages)
    messages_.push_back(text);
  else
    ++messages_dropped_;
}

void AvrBoard::log_trampoline(avr_t* avr, int level, const char* format, va_list args) {
  if (level > LOG_WARNING) return;
  char text[256];
  std::vsnprintf(text, sizeof text, format, args);
  AvrBoard* self = from(avr);
  if (self)
    self->record_message(text);
  else if (level <= LOG_ERROR)
    std::fputs(text, stderr);
}

}  // namespace sim

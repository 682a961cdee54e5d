// One simulated board: RAII around a simavr avr_t running a firmware ELF, with the couplings the
// harness needs (UART bytes, thermistor ADC injection, heater/fan pin meters, the GPIOR0
// control-step marker, periodic harness work that survives watchdog resets). It hides every
// simavr 1.6 workaround listed in shared/notes/simavr-1.6.md. One instance per thread.
#pragma once

#include <cstdarg>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim/board_spec.h"
#include "sim/firmware_image.h"
#include "sim/pin_meter.h"

struct avr_t;
struct avr_irq_t;

namespace sim {

// CPU cycles between the firmware's GPIOR0 := 1 and GPIOR0 := 0 writes (one control step,
// including any tick interrupt that preempts it, as on silicon).
struct StepCycleStats {
  uint64_t count = 0;
  uint64_t max_cycles = 0;
  uint64_t total_cycles = 0;
  // Largest interval between two successive step starts (nominally one 128 ms period): what
  // anything that stalls the main loop (an EEPROM write waited for) shows up in.
  uint64_t max_gap_cycles = 0;
  uint64_t last_start_cycle = 0;
  double mean_cycles() const { return count ? double(total_cycles) / double(count) : 0.0; }
};

// Cycles per run of one interrupt handler (AvrBoard::isr_cycles; avr_board_isr.cpp).
struct IsrCycleStats {
  std::string name;  // "tick", "uart rx", "uart udre", or "vector N"
  uint8_t vector = 0;
  uint64_t count = 0;
  uint64_t max_cycles = 0;
  uint64_t total_cycles = 0;
  double mean_cycles() const { return count ? double(total_cycles) / double(count) : 0.0; }
};

enum class CpuState { kRunning, kStopped, kCrashed };

// EEPROM writes under --eeprom-timing silicon (AvrBoard::use_silicon_eeprom_timing).
struct EepromStats {
  uint64_t writes = 0;              // byte writes started
  uint64_t ignored_while_busy = 0;  // EEPE/EERE written while a write was in progress
};

class AvrBoard {
 public:
  // Loads the ELF (throws std::runtime_error with the reason if it cannot).
  AvrBoard(const BoardSpec& spec, const std::string& elf_path);
  ~AvrBoard();  // out of line: the parts below are incomplete here
  AvrBoard(const AvrBoard&) = delete;
  AvrBoard& operator=(const AvrBoard&) = delete;

  // Runs the firmware until `end_cycle` (or until it stops/crashes).
  CpuState run_until(uint64_t end_cycle);
  uint64_t cycle() const;
  double time_s() const;
  uint64_t cycles_from_s(double seconds) const;
  double frequency_hz() const;

  // UART0: every byte the firmware transmits (to each handler); bytes in are accepted only while
  // the UART signals XON (simavr drops bytes raised at other times).
  void on_uart_byte(std::function<void(uint8_t)> handler) { uart_handlers_.push_back(std::move(handler)); }
  bool uart_accepting() const { return uart_xon_; }
  bool uart_send(uint8_t byte);

  // The host→board wire as on the chip (serve): whenever the line is free — one frame after the
  // last byte began, the frame being start + data + parity + stop bits at the bit time UBRR0
  // and U2X0 give — and the receiver is on, `next_byte` is asked for the next byte (-1: idle).
  // A byte arriving while the receiver already holds two unread bytes and one being shifted in
  // is lost (a data overrun), as on silicon; simavr's own 64-byte FIFO would hide it.
  void feed_uart_line(std::function<int()> next_byte);
  uint64_t uart_frame_cycles() const;  // 0 until the firmware has set the UART up
  uint64_t uart_overruns() const;

  // The voltage (mV, integer as simavr takes it) of an analog input at the start of each of its
  // conversions. `channel` is the board's ADC number (ADC13 on RAMPS is 13).
  void set_adc_source(uint8_t channel, std::function<uint16_t()> millivolts);
  uint32_t adc_ref_mv() const;

  // Duty meters on output pins (the heater and fan are watched from construction).
  PinMeter& heater() { return heater_; }
  PinMeter& fan() { return fan_; }

  const StepCycleStats& step_cycles() const { return step_cycles_; }
  // Every interrupt handler that ran (or is known by name), vector entry to RETI as simavr
  // counts it: silicon adds 4–5 cycles of entry.
  const std::vector<IsrCycleStats>& isr_cycles() const { return isr_cycles_; }

  // Models silicon's 3.4 ms EEPROM write (EEPE stays set, accesses meanwhile are ignored);
  // without it simavr completes every write at once. avr_board_eeprom.cpp.
  void use_silicon_eeprom_timing();
  const EepromStats& eeprom_stats() const { return eeprom_stats_; }

  // Harness work every `period_us` of simulated time; re-armed after every reset.
  void every(uint32_t period_us, std::function<void()> work);
  // Called right after every CPU reset (watchdog), before the firmware runs again.
  void on_reset(std::function<void()> hook) { reset_hooks_.push_back(std::move(hook)); }
  int reset_count() const { return reset_count_; }

  ImageSize image_size() const { return image_size_; }
  // Deepest stack so far (bytes below RAMEND the firmware has written), and the room it has
  // (RAM above the static data): the RAM above .bss is painted at load, the first unpainted
  // byte from below is the deepest the stack reached. No heap in the firmware.
  uint32_t stack_max_bytes() const;
  uint32_t stack_room_bytes() const;
  const std::string& mcu() const { return mcu_; }
  // simavr's own warnings and errors for this board (e.g. crash reasons): the first ones, and
  // how many more were dropped.
  const std::vector<std::string>& simavr_messages() const { return messages_; }
  uint64_t simavr_messages_dropped() const { return messages_dropped_; }

 private:
  struct Periodic;
  struct AdcFeed;
  struct UartLine;
  struct EepromTiming;

  void load(const BoardSpec& spec, const std::string& elf_path);
  void attach_uart();
  void attach_adc();
  void watch_pin(boards::Pin pin, PinMeter* meter);
  void attach_step_marker();
  void attach_isr_meter();
  void record_isr(uint8_t vector, uint64_t cycles);
  void apply_adc_remap();
  void after_reset();
  void reset_eeprom_timing();

  void record_message(const std::string& text);
  static AvrBoard* from(avr_t* avr);
  static void reset_trampoline(avr_t* avr);
  static void log_trampoline(avr_t* avr, int level, const char* format, va_list args);

  struct AvrDeleter {
    void operator()(avr_t* avr) const;  // avr_terminate() and free the core
  };

  std::unique_ptr<avr_t, AvrDeleter> avr_;
  void (*core_reset_)(avr_t*) = nullptr;
  std::string mcu_;
  ImageSize image_size_;
  static constexpr uint8_t kStackPaint = 0xA5;
  uint32_t stack_floor() const;  // first SRAM address above the static data
  PinMeter heater_;
  PinMeter fan_;
  struct PinWatch;
  std::vector<std::unique_ptr<PinWatch>> pin_watches_;
  std::vector<std::unique_ptr<AdcFeed>> adc_feeds_;
  std::vector<std::unique_ptr<Periodic>> periodics_;
  std::vector<std::function<void()>> reset_hooks_;
  std::vector<std::function<void(uint8_t)>> uart_handlers_;
  std::unique_ptr<UartLine> uart_line_;
  avr_irq_t* uart_irqs_ = nullptr;
  avr_irq_t* adc_irqs_ = nullptr;
  bool uart_xon_ = false;
  bool remap_high_adc_ = false;
  int reset_count_ = 0;
  uint64_t step_start_cycle_ = 0;
  bool step_open_ = false;
  StepCycleStats step_cycles_;
  struct OpenIsr {
    uint8_t vector;
    uint64_t start_cycle;
  };
  std::vector<OpenIsr> isr_open_;  // handlers entered and not yet left, innermost last
  std::vector<IsrCycleStats> isr_cycles_;
  std::unique_ptr<EepromTiming> eeprom_timing_;
  EepromStats eeprom_stats_;
  std::vector<std::string> messages_;
  uint64_t messages_dropped_ = 0;
};

}  // namespace sim

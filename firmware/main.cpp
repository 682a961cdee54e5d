// Start-up and the main loop. The loop sleeps until an interrupt; then it runs the control
// step when the tick ISR has published an ADC window (every 128 ms), feeds received bytes to
// the G-code layer and lets it drive M109 waits and M155 reports.
#include <stdint.h>

#include "firmware/banner.h"
#include "firmware/control_loop.h"
#include "firmware/controller_bank.h"
#include "firmware/emergency_input.h"
#include "firmware/fuzzy_surface_flash.h"
#include "firmware/gcode_interpreter.h"
#include "firmware/heater_manager.h"
#include "firmware/hotend_machine.h"
#include "firmware/placement_new.h"
#include "firmware/serial_output.h"
#include "hal/adc.h"
#include "hal/board.h"
#include "hal/critical_section.h"
#include "hal/gpio.h"
#include "hal/heater_pwm.h"
#include "hal/sleep.h"
#include "hal/tick.h"
#include "hal/uart.h"
#include "hal/watchdog.h"

namespace {

// Static objects, wired once: no heap. Constructors only store references.
firmware::SerialOutput g_out;
// The bank is built at boot (main's first line) rather than constant-initialised: its ~1.1 KB
// are mostly zeros but not all (vtable pointers, the surface reader), so a constant image would
// be 1.1 KB of .data copied from flash; built, it is .bss, for ~260 B of constructor code (the
// rest of it is shared with ControllerBank::end_autotune, which rebuilds the controllers).
union BankStorage {
  constexpr BankStorage() : none() {}
  char none;
  firmware::ControllerBank bank;
} g_boot;  // (named directly below: a reference variable would make the others start-up code)
firmware::HeaterManager g_heater(g_boot.bank);
firmware::AutotuneJob g_tune(g_boot.bank);  // its engine borrows the bank's controller storage
firmware::ControlLoop g_loop(g_heater, g_tune);
firmware::HotendMachine g_machine(g_heater, g_loop, g_boot.bank, g_tune, g_out);
gcode::Interpreter g_gcode(g_machine, g_out);

bool has_work() {
  return hal::adc::window_ready() || firmware::emergency_input::pending() ||
         (g_gcode.accepting() && hal::uart::rx_available());
}

// M112/M108 seen in the byte stream (the RX interrupt already switched the heater off for
// M112): latch the fault or end the wait now, whatever lines are queued or held.
void take_urgent() {
  using firmware::emergency_input::take;
  if (take(gcode::Urgent::kStop)) g_gcode.urgent(gcode::Urgent::kStop);
  if (take(gcode::Urgent::kCancelWait)) g_gcode.urgent(gcode::Urgent::kCancelWait);
}

// Received input until a control step or an urgent command is due, or a line is held.
void feed_input() {
  uint8_t byte;
  while (!hal::adc::window_ready() && !firmware::emergency_input::pending() && g_gcode.accepting()) {
    const hal::uart::RxEvent event = hal::uart::read(byte);
    if (event == hal::uart::RxEvent::kNone) return;
    if (event == hal::uart::RxEvent::kLost) {
      g_gcode.input_lost();
    } else {
      g_gcode.feed(static_cast<char>(byte));
    }
  }
}

// While a reply waits for room in the TX ring: the control step, if its window is ready, so
// a long reply (M503, M303's report) never delays it. Not while an M112/M108 from the byte
// stream waits: the main loop latches that first, before any new duty.
void step_while_writing() {
  if (firmware::emergency_input::pending()) return;
  uint16_t adc_q6;
  if (!hal::adc::take_window(adc_q6)) return;
  g_loop.run(adc_q6);
  // An M112 that arrived during the step: its interrupt's force_off may have been overwritten by
  // the duty the step handed over. Off again; the main loop latches the stop after the reply.
  if (firmware::emergency_input::stop_pending()) hal::heater_pwm::force_off();
}

}  // namespace

// Building the bank at run time names control::Controller's vtable, whose pure slots point
// here; no such call can happen. If one did: heater off, and the watchdog resets the board.
extern "C" void __cxa_pure_virtual() {
  hal::heater_pwm::force_off();
  hal::watchdog::enable();
  hal::watchdog::hang_until_reset();
}

int main() {
  new (&g_boot.bank) firmware::ControllerBank(firmware::load_surface_cell);  // no output yet
  // The heater outputs are already low: .init3 (hal/startup.cpp) ran before this.
  hal::gpio::drive_low(board::kPartFan);
  hal::sleep::init();
  hal::uart::init(firmware::emergency_input::on_rx_byte);
  hal::adc::init(board::kHotendAdcChannel);
  hal::tick::init();
  hal::enable_interrupts();  // the banner below may be longer than the TX ring

  firmware::print_banner(g_out);
  g_machine.load_settings_at_boot();
  // From here on the control loop must run every 128 ms, or the board resets; a reply that
  // fills the TX ring runs it while it waits.
  hal::watchdog::enable();
  hal::uart::set_tx_wait_hook(step_while_writing);

  for (;;) {
    hal::sleep::idle_unless(has_work);
    take_urgent();  // before the step: a stop is latched before a new duty is computed
    uint16_t adc_q6;
    if (hal::adc::take_window(adc_q6)) {
      g_loop.run(adc_q6);
      take_urgent();  // a stop that came during the step overrides the duty it handed over
    }
    g_loop.report(g_out);  // a fault latched here or by a step inside a reply
    // Stops at a ready window, so a burst of commands cannot delay the control step.
    feed_input();
    g_gcode.poll(hal::tick::millis());
  }
}

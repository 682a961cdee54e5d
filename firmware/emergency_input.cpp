#include "firmware/emergency_input.h"

#include "hal/critical_section.h"
#include "hal/heater_pwm.h"

namespace firmware {
namespace emergency_input {
namespace {

gcode::EmergencyParser g_parser;  // interrupt only
volatile uint8_t g_flags;         // bit (1 << Urgent): set by the interrupt, cleared by take()

uint8_t flag_of(gcode::Urgent kind) { return static_cast<uint8_t>(1u << static_cast<uint8_t>(kind)); }

}  // namespace

void on_rx_byte(uint8_t byte, bool overrun) {
  if (overrun) g_parser.lost();
  const gcode::Urgent kind = g_parser.feed(byte);
  if (kind == gcode::Urgent::kNone) return;
  if (kind == gcode::Urgent::kStop) hal::heater_pwm::force_off();  // before anything else runs
  g_flags = static_cast<uint8_t>(g_flags | flag_of(kind));
}

bool pending() { return g_flags != 0; }

bool stop_pending() { return (g_flags & flag_of(gcode::Urgent::kStop)) != 0; }

bool take(gcode::Urgent kind) {
  hal::CriticalSection lock;  // read-modify-write of a byte the interrupt also sets
  const uint8_t flag = flag_of(kind);
  if ((g_flags & flag) == 0) return false;
  g_flags = static_cast<uint8_t>(g_flags & ~flag);
  return true;
}

}  // namespace emergency_input
}  // namespace firmware

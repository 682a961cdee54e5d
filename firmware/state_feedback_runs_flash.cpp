// control/state_feedback_gcode.h's field runs in program memory (78 bytes of RAM otherwise) and
// their reader.
#include <avr/pgmspace.h>

#include "control/state_feedback_gcode.h"

namespace control {
namespace {

const SfRuns kSfRunsFlash PROGMEM = kSfRuns;

}  // namespace

SfRun sf_run(uint8_t i) {
  const SfRun* r = &kSfRunsFlash.run[i];
  return SfRun{pgm_read_byte(&r->offset), pgm_read_byte(&r->count), static_cast<SfFieldType>(pgm_read_byte(&r->type))};
}

}  // namespace control

#include "firmware/fuzzy_surface_flash.h"

#include <avr/pgmspace.h>

#include "control/fuzzy_surface_gen.h"

namespace firmware {
namespace {

// A constant initialiser evaluated by avr-gcc (its double is 32-bit; the host test
// FuzzySurfaceGen checks that float builds the same grid), placed in flash: no RAM, no start-up code.
constexpr fuzzy::Surfaces<fuzzy::kSurfaceStepShift> kSurfacesValue = fuzzy::make_default_surfaces();
const fuzzy::Surfaces<fuzzy::kSurfaceStepShift> kSurfaces PROGMEM = kSurfacesValue;

}  // namespace

// Three bytes with post-increment `lpm` (non-volatile asm, like temperature_sensor.cpp's reader:
// the grid never changes). PROGMEM data lies in the first 64 KB, which `lpm` reaches.
fuzzy::Cell load_surface_cell(uint16_t index) {
  const void* address = &kSurfaces.cell[index];
  uint8_t kp, ki, kd;
  __asm__("lpm %0, Z+\n\tlpm %1, Z+\n\tlpm %2, Z" : "=r"(kp), "=r"(ki), "=r"(kd), "+z"(address));
  return fuzzy::Cell{kp, ki, kd};
}

}  // namespace firmware

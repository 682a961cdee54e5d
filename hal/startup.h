// What happened before main(): the heater outputs were forced low in .init3 and the reset
// cause was captured there (MCUSR must be cleared early or a watchdog reset loops).
#pragma once
#include <stdint.h>

namespace hal {
namespace startup {

enum class ResetCause : uint8_t { kUnknown, kPowerOn, kExternal, kBrownOut, kWatchdog, kJtag };

// The cause of the last reset, from MCUSR as read in .init3. kUnknown when no flag was set
// (a bootloader may clear MCUSR before jumping to the application).
ResetCause reset_cause();

}  // namespace startup
}  // namespace hal

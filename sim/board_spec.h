// The facts the harness needs about each board, gathered from the constexpr data in boards/*.h
// (the same headers the firmware is built from), so the simulator and the image cannot disagree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "boards/ramps14.h"
#include "boards/sanguinololu.h"

namespace sim {

struct BoardSpec {
  std::string id;    // command-line name, e.g. "ramps14" (also the ELF suffix)
  std::string name;  // human name, e.g. "RAMPS 1.4"
  std::string mcu;   // simavr core name, used when the ELF carries no .mmcu section
  uint32_t cpu_hz;
  boards::Pin hotend_heater;
  boards::Pin part_fan;
  uint8_t hotend_adc_channel;
  uint8_t bed_adc_channel;
  uint32_t thermistor_pullup_ohm;
  uint16_t adc_ref_mv;
};

// One BoardSpec from the boards::<ns> namespace: a macro because namespaces cannot be template
// arguments; it spells every field once for all boards.
// clang-format off
#define HOTEND_SIM_BOARD_SPEC(ns)                                                               \
  BoardSpec{#ns, boards::ns::kName, boards::ns::kMcu, boards::ns::kCpuHz,                       \
            boards::ns::kHotendHeater, boards::ns::kPartFan, boards::ns::kHotendAdcChannel,     \
            boards::ns::kBedAdcChannel, boards::ns::kThermistorPullupOhm,                       \
            boards::ns::kAdcRefMillivolts}
// clang-format on

// Every board one configure builds, in the order boards/boards.cmake lists them.
inline const std::vector<BoardSpec>& all_boards() {
  static const std::vector<BoardSpec> boards{HOTEND_SIM_BOARD_SPEC(sanguinololu),
                                             HOTEND_SIM_BOARD_SPEC(ramps14)};
  return boards;
}

// The board with this id, or nullptr.
inline const BoardSpec* find_board(const std::string& id) {
  for (const BoardSpec& b : all_boards())
    if (b.id == id) return &b;
  return nullptr;
}

}  // namespace sim

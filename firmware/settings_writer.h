// M500 without stalling the control loop: the settings slot (firmware/settings.h) is streamed
// to EEPROM one byte per EEPROM write (3.4 ms on silicon), started from the main loop only
// when the EEPROM is idle, so no pass ever waits for it. Unchanged bytes are skipped (no write,
// no wear). The objects being saved are read as the bytes go out: they must not change until
// the write ends, which the G-code layer guarantees by holding further input
// (gcode::Machine::command_pending) and the machine by refusing M500 during M303.
#pragma once
#include <stdint.h>

#include "control/state_feedback_constants.h"
#include "firmware/controller_settings.h"

namespace firmware {

class SettingsWriter {
 public:
  enum class Status : uint8_t { kWriting, kDone, kFailed };

  // Starts a save into the slot that does not hold the newest valid copy (reads both slots:
  // ~450 EEPROM bytes and their CRC, ~3 ms on the AVR). Precondition: !writing().
  void begin(const Settings& settings, bool sf_loaded, const control::StateFeedbackConstants& sf);
  bool writing() const { return phase_ != Phase::kIdle; }

  // One main-loop pass: at most one byte write started and kCompareBudget bytes compared;
  // never waits. kDone or kFailed (the slot read back invalid) once, when the write has ended.
  Status step();
  uint16_t bytes_written() const { return written_; }  // EEPROM writes of the last/current save

 private:
  enum class Phase : uint8_t { kIdle, kInvalidate, kBody, kCommit, kVerify };
  static constexpr uint8_t kCompareBudget = 32;  // ~4,000 AVR cycles of reads and CRC per pass

  uint8_t source_byte(uint16_t offset) const;  // the slot image's byte at `offset`
  void write_if_changed(uint16_t offset, uint8_t value, bool* wrote);

  const Settings* settings_ = nullptr;
  const control::StateFeedbackConstants* sf_ = nullptr;
  uint16_t base_ = 0;    // EEPROM address of the slot being written
  uint16_t offset_ = 0;  // next byte of the body phase
  uint16_t crc_ = 0;     // over the sequence and every body byte before offset_
  uint16_t written_ = 0;
  uint8_t flag_ = 0;
  uint8_t sequence_ = 0;
  uint8_t slot_ = 0;
  Phase phase_ = Phase::kIdle;
};

}  // namespace firmware

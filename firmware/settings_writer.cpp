#include "firmware/settings_writer.h"

#include "firmware/settings.h"
#include "hal/eeprom.h"

namespace firmware {

using namespace settings_layout;

void SettingsWriter::begin(const Settings& settings, bool sf_loaded, const control::StateFeedbackConstants& sf) {
  const Scan s = scan();
  slot_ = s.newest < 0 ? 0 : static_cast<uint8_t>(1 - s.newest);
  sequence_ = s.newest < 0 ? 0 : next_sequence(s.sequence[s.newest]);
  base_ = slot_address(slot_);
  settings_ = &settings;
  sf_ = &sf;
  flag_ = sf_loaded ? 1 : 0;
  crc_ = crc16_ccitt(0xFFFF, &sequence_, 1);  // the sequence byte is first in the CRC, last written
  offset_ = kHeaderOffset;
  written_ = 0;
  phase_ = Phase::kInvalidate;
}

uint8_t SettingsWriter::source_byte(uint16_t offset) const {
  if (offset < kSettingsOffset) return header_byte(static_cast<uint8_t>(offset - kHeaderOffset));
  if (offset < kFlagOffset) return reinterpret_cast<const uint8_t*>(settings_)[offset - kSettingsOffset];
  if (offset == kFlagOffset) return flag_;
  if (offset < kCrcOffset) return reinterpret_cast<const uint8_t*>(sf_)[offset - kSfOffset];
  return reinterpret_cast<const uint8_t*>(&crc_)[offset - kCrcOffset];  // final by now
}

void SettingsWriter::write_if_changed(uint16_t offset, uint8_t value, bool* wrote) {
  const uint16_t address = static_cast<uint16_t>(base_ + offset);
  *wrote = hal::eeprom::read_byte(address) != value;
  if (!*wrote) return;
  hal::eeprom::start_write(address, value);
  ++written_;
}

SettingsWriter::Status SettingsWriter::step() {
  if (phase_ == Phase::kIdle) return Status::kDone;
  if (hal::eeprom::busy()) return Status::kWriting;
  bool wrote = false;
  switch (phase_) {
    case Phase::kInvalidate:  // from here until the commit the slot does not count
      write_if_changed(kSequenceOffset, kNoSequence, &wrote);
      phase_ = Phase::kBody;
      break;
    case Phase::kBody:
      for (uint8_t budget = kCompareBudget; budget != 0 && !wrote; --budget) {
        if (offset_ == kSlotSize) {
          phase_ = Phase::kCommit;
          break;
        }
        const uint8_t b = source_byte(offset_);
        if (offset_ < kCrcOffset) crc_ = crc16_ccitt(crc_, &b, 1);
        write_if_changed(offset_++, b, &wrote);
      }
      break;
    case Phase::kCommit:
      write_if_changed(kSequenceOffset, sequence_, &wrote);
      phase_ = Phase::kVerify;
      break;
    default: {  // kVerify: the last write has ended; read the slot back
      phase_ = Phase::kIdle;
      uint8_t sequence;
      return read_slot(slot_, nullptr, &sequence) && sequence == sequence_ ? Status::kDone : Status::kFailed;
    }
  }
  return Status::kWriting;
}

}  // namespace firmware

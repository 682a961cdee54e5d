// The EEPROM settings slots and the asynchronous M500 writer on a fake EEPROM: a write never
// starts while one is in progress, only changed bytes are written, and a power cut (reset)
// after any number of bytes leaves either the old settings or the new ones, never a mix.
#include <gtest/gtest.h>

#include <cstring>

#include "firmware/settings.h"
#include "firmware/settings_writer.h"
#include "host_tests/fake_eeprom.h"

namespace {

using firmware::SettingsBlock;
using firmware::SettingsWriter;

SettingsBlock block_with(int32_t kp_units, bool sf_loaded) {
  SettingsBlock b;
  std::memset(&b, 0, sizeof b);  // padding bytes too: the tests compare whole blocks
  b.settings = firmware::default_settings();
  b.settings.pid.kp_q16 = kp_units << 16;
  b.sf_loaded = sf_loaded ? 1 : 0;
  b.sf.n = 3;
  b.sf.ambient_q8 = 25 * 256 + kp_units;
  for (uint8_t j = 0; j < control::kSfMaxDelay; ++j) b.sf.fir[j] = static_cast<int16_t>(kp_units * 100 + j);
  return b;
}

bool same(const SettingsBlock& a, const SettingsBlock& b) {
  return std::memcmp(&a.settings, &b.settings, sizeof a.settings) == 0 && a.sf_loaded == b.sf_loaded &&
         std::memcmp(&a.sf, &b.sf, sizeof a.sf) == 0;
}

// Runs a whole save, as the main loop would (one step per pass); returns the final status.
SettingsWriter::Status save(const SettingsBlock& b, long* steps = nullptr) {
  SettingsWriter writer;
  writer.begin(b.settings, b.sf_loaded == 1, b.sf);
  SettingsWriter::Status status = SettingsWriter::Status::kWriting;
  long n = 0;
  while (writer.writing()) {
    status = writer.step();
    ++n;
  }
  if (steps != nullptr) *steps = n;
  return status;
}

long writes_of(const SettingsBlock& b) {
  const long before = fake_eeprom::state().writes;
  EXPECT_EQ(save(b), SettingsWriter::Status::kDone);
  return fake_eeprom::state().writes - before;
}

TEST(SettingsEeprom, BlankEepromLoadsNothing) {
  fake_eeprom::reset();
  SettingsBlock out;
  EXPECT_FALSE(firmware::load_settings(out));
}

TEST(SettingsEeprom, SaveThenLoadRoundTrips) {
  fake_eeprom::reset();
  const SettingsBlock a = block_with(34, true);
  EXPECT_EQ(save(a), SettingsWriter::Status::kDone);
  SettingsBlock out;
  ASSERT_TRUE(firmware::load_settings(out));
  EXPECT_TRUE(same(out, a));
  EXPECT_EQ(fake_eeprom::state().misuse, 0);
}

// One byte write per main-loop pass at most, never while the EEPROM is busy: a pass costs
// microseconds, not 3.4 ms per byte.
TEST(SettingsEeprom, WriterNeverWaitsAndStartsOneWriteAtATime) {
  fake_eeprom::reset(5);
  long steps = 0;
  EXPECT_EQ(save(block_with(34, true), &steps), SettingsWriter::Status::kDone);
  EXPECT_EQ(fake_eeprom::state().misuse, 0);
  EXPECT_EQ(fake_eeprom::state().max_writes_between_polls, 1);
  EXPECT_GT(fake_eeprom::state().writes, 150);  // a blank slot: nearly every byte
  EXPECT_GE(steps, fake_eeprom::state().writes * 5);  // it waited out every write by polling
}

// The first save fills slot 0, the second slot 1 (blank: everything again); from then on a
// save of unchanged settings writes only the sequence byte twice and the CRC.
TEST(SettingsEeprom, WritesOnlyChangedBytes) {
  fake_eeprom::reset();
  const SettingsBlock a = block_with(34, true);
  const long first = writes_of(a);
  EXPECT_GT(first, 150);
  EXPECT_GT(writes_of(a), 150);
  const long third = writes_of(a);
  EXPECT_LE(third, 4);  // sequence := 0xFF, CRC (2), sequence
  EXPECT_GE(third, 2);
  SettingsBlock b = a;
  b.settings.pid.kd_q16 += 1;
  EXPECT_LE(writes_of(b), 4 + 1 + 2);  // (the other slot is two saves old)
  SettingsBlock out;
  ASSERT_TRUE(firmware::load_settings(out));
  EXPECT_TRUE(same(out, b));
}

// The torn-write property: for every number of completed byte writes N before the reset, the
// next boot loads the old settings (N < all) or the new ones (N = all). Run over four saves,
// so each slot is torn both as the first copy and while the other slot holds the old one.
TEST(SettingsEeprom, ResetAfterAnyByteLeavesOldOrNew) {
  const SettingsBlock versions[] = {block_with(10, false), block_with(20, true), block_with(30, true),
                                    block_with(40, false), block_with(50, true)};
  fake_eeprom::reset();
  std::vector<uint8_t> before = fake_eeprom::state().cells;
  const SettingsBlock* old_block = nullptr;
  long checked = 0;
  for (const SettingsBlock& next : versions) {
    fake_eeprom::state().cells = before;
    const long total = writes_of(next);
    const std::vector<uint8_t> after = fake_eeprom::state().cells;
    for (long n = 0; n <= total; ++n) {
      fake_eeprom::reset();
      fake_eeprom::state().cells = before;
      fake_eeprom::state().write_limit = n;
      save(next);  // the writes after the n-th are lost (the verify then fails: n < total)
      fake_eeprom::state().write_limit = -1;
      SettingsBlock out;
      const bool loaded = firmware::load_settings(out);  // the next boot
      if (n == total) {
        ASSERT_TRUE(loaded);
        EXPECT_TRUE(same(out, next)) << "all " << n << " writes done";
      } else if (old_block == nullptr) {
        EXPECT_FALSE(loaded) << "first save torn after " << n << " writes";
      } else {
        ASSERT_TRUE(loaded) << "torn after " << n << " of " << total;
        EXPECT_TRUE(same(out, *old_block)) << "torn after " << n << " of " << total;
      }
      ++checked;
    }
    fake_eeprom::state().cells = after;
    before = after;
    old_block = &next;
  }
  EXPECT_GT(checked, 400);
}

// A failed verify (a write lost) is reported, and the slot does not count.
TEST(SettingsEeprom, LostWriteFailsTheVerify) {
  fake_eeprom::reset();
  fake_eeprom::state().write_limit = 40;
  EXPECT_EQ(save(block_with(34, true)), SettingsWriter::Status::kFailed);
}

// Sequence numbers wrap 254 -> 0: the newest copy still wins after hundreds of saves.
TEST(SettingsEeprom, SequenceWrapKeepsTheNewest) {
  fake_eeprom::reset(0);
  for (int i = 0; i < 600; ++i) {
    const SettingsBlock b = block_with(i % 7, i % 2 == 0);
    ASSERT_EQ(save(b), SettingsWriter::Status::kDone);
    SettingsBlock out;
    ASSERT_TRUE(firmware::load_settings(out));
    ASSERT_TRUE(same(out, b)) << "save " << i;
  }
}

// A slot with a flipped bit (worn cell) is skipped: the other copy loads.
TEST(SettingsEeprom, CorruptNewestFallsBackToTheOtherCopy) {
  fake_eeprom::reset();
  const SettingsBlock a = block_with(11, true);
  const SettingsBlock b = block_with(12, true);
  save(a);
  save(b);  // slot 1
  fake_eeprom::state().cells[firmware::settings_layout::slot_address(1) + 40] ^= 0x10;
  SettingsBlock out;
  ASSERT_TRUE(firmware::load_settings(out));
  EXPECT_TRUE(same(out, a));
}

}  // namespace

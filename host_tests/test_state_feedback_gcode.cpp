// The M311 text form of the state-feedback constants (control/state_feedback_gcode.h): the
// field walk covers the struct exactly, in the order the design tool's own listing uses, and
// the canonical lines parse back to the same constants.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "design/state_feedback_format.h"
#include "control/state_feedback_gcode.h"
#include "host_tests/state_feedback_fixtures.h"

namespace {

using control::StateFeedbackConstants;

// Every field set to a distinct value that fits its type.
StateFeedbackConstants distinct_fields() {
  StateFeedbackConstants k;
  std::memset(&k, 0, sizeof k);
  for (uint8_t i = 0; i < control::kSfFieldCount; ++i) {
    const control::SfField f = control::sf_field(k, i);
    control::sf_set(f, f.type == control::SfFieldType::kU8 ? 100 + i : -300 * i - 7);
  }
  return k;
}

TEST(StateFeedbackGcode, FieldIndicesFollowTheDesignToolsListing) {
  const StateFeedbackConstants k = distinct_fields();
  int count = 0;
  design::for_each_field(k, [&](int index, const char* name, long value) {
    EXPECT_EQ(control::sf_get(k, static_cast<uint8_t>(index)), value) << index << " " << name;
    ++count;
  });
  EXPECT_EQ(count, control::kSfFieldCount);
  EXPECT_EQ(control::kSfFieldCount, 99);
  StateFeedbackConstants scratch = k;
  EXPECT_EQ(control::sf_field(scratch, control::kSfFieldCount).address, nullptr);
}

// The chain of per-member steps sf_field() used before its run table: the same address and
// type for every index 0..255 (beyond the last field: none).
control::SfField chained_field(StateFeedbackConstants& k, uint8_t index) {
  control::SfField field{nullptr, control::SfFieldType::kU8};
  auto run = [&](auto* first, uint8_t count, control::SfFieldType type) {
    if (field.address != nullptr) return;
    if (index < count) field = control::SfField{first + index, type};
    else index = static_cast<uint8_t>(index - count);
  };
  using T = control::SfFieldType;
  const uint8_t s = control::kSfMaxStates;
  run(&k.n, 1, T::kU8); run(&k.output_mask, 1, T::kU8); run(&k.delay, 1, T::kU8);
  run(&k.decimation, 1, T::kU8); run(&k.input_shift, 1, T::kU8); run(&k.ambient_q8, 1, T::kI32);
  run(k.phi_diag, s, T::kI16); run(k.phi_off, s, T::kI16); run(k.phi_col, s, T::kU8);
  run(k.gamma_a, s, T::kI16); run(k.gamma_b, s, T::kI16); run(k.phi_shift, s, T::kU8);
  run(k.obs_gain, s + 1, T::kI16); run(k.obs_shift, s + 1, T::kU8); run(k.fb_gain, s, T::kI16);
  run(&k.ff_gain, 1, T::kI16); run(&k.bias_gain, 1, T::kI16); run(&k.ctrl_shift, 1, T::kU8);
  run(k.fir, control::kSfMaxDelay, T::kI16); run(&k.fir_shift, 1, T::kU8); run(&k.fan_gain, 1, T::kI16);
  run(&k.fan_shift, 1, T::kU8); run(k.ss_share, s, T::kI16); run(&k.ss_share_shift, 1, T::kU8);
  run(&k.inv_gain, 1, T::kI16); run(&k.inv_gain_shift, 1, T::kU8);
  return field;
}

TEST(StateFeedbackGcode, RunTableFindsWhatThePerMemberChainFound) {
  StateFeedbackConstants k;
  for (int i = 0; i < 256; ++i) {
    const control::SfField table = control::sf_field(k, static_cast<uint8_t>(i));
    const control::SfField chain = chained_field(k, static_cast<uint8_t>(i));
    EXPECT_EQ(table.address, chain.address) << i;
    if (chain.address != nullptr) {
      EXPECT_EQ(table.type, chain.type) << i;
    }
  }
}

TEST(StateFeedbackGcode, EveryFieldIsReachedOnce) {
  // The fields' byte ranges are disjoint and add up to the members' total size (174 bytes:
  // the struct without padding), so together with the listing above no member is missed.
  StateFeedbackConstants k;
  std::vector<std::pair<const char*, const char*>> ranges;
  size_t bytes = 0;
  for (uint8_t i = 0; i < control::kSfFieldCount; ++i) {
    const control::SfField f = control::sf_field(k, i);
    const size_t size = f.type == control::SfFieldType::kU8 ? 1 : (f.type == control::SfFieldType::kI16 ? 2 : 4);
    const char* begin = static_cast<const char*>(f.address);
    ASSERT_GE(begin, reinterpret_cast<const char*>(&k));
    ASSERT_LE(begin + size, reinterpret_cast<const char*>(&k + 1));
    for (const auto& r : ranges) EXPECT_TRUE(begin + size <= r.first || begin >= r.second) << int(i);
    ranges.push_back({begin, begin + size});
    bytes += size;
  }
  EXPECT_EQ(bytes, 174u);
  const StateFeedbackConstants d = distinct_fields();
  EXPECT_EQ(d.n, 100);
  EXPECT_EQ(d.ambient_q8, -1507);
  EXPECT_EQ(d.obs_gain[5], -12307);
  EXPECT_EQ(d.inv_gain_shift, 198);
}

std::vector<std::string> lines_of(const StateFeedbackConstants& k) {
  std::vector<std::string> lines;
  control::write_state_feedback_mcode(k, [&](const char* line) { lines.push_back(line); });
  return lines;
}

// A minimal reader of the canonical lines (the firmware's real parser is tested through the
// G-code layer in test_controller_commands.cpp).
StateFeedbackConstants parse(const std::vector<std::string>& lines) {
  StateFeedbackConstants k;
  std::memset(&k, 0, sizeof k);
  for (const std::string& line : lines) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    EXPECT_EQ(word, "M311");
    long first = -1;
    while (words >> word) {
      const long v = std::strtol(word.c_str() + 1, nullptr, 10);
      if (word[0] == 'I') first = v;
      else if (word[0] >= 'A' && word[0] <= 'H')
        control::sf_set(control::sf_field(k, static_cast<uint8_t>(first + (word[0] - 'A'))), v);
    }
  }
  return k;
}

TEST(StateFeedbackGcode, CanonicalLinesRoundTrip) {
  for (const StateFeedbackConstants& k : {fixtures::hotend40w_constants(), fixtures::seed002_constants(), fixtures::seed000_5_constants()}) {
    const std::vector<std::string> lines = lines_of(k);
    ASSERT_EQ(lines.size(), 14u);  // 13 × 8 fields, then the commit
    EXPECT_EQ(lines.back(), "M311 W1");
    EXPECT_EQ(lines[0].rfind("M311 I0 A", 0), 0u);
    EXPECT_EQ(lines[12].rfind("M311 I96 A", 0), 0u);
    for (const std::string& line : lines) EXPECT_LT(line.size(), 80u) << line;  // fits the 96-byte line
    const StateFeedbackConstants back = parse(lines);
    for (uint8_t i = 0; i < control::kSfFieldCount; ++i) EXPECT_EQ(control::sf_get(back, i), control::sf_get(k, i)) << int(i);
  }
}

TEST(StateFeedbackGcode, Hotend40wFirstLineReadsAsExpected) {
  // n 2, output_mask 2, delay 0, decimation 2, input_shift 9, ambient 25 °C, phi_diag[0..1].
  const std::vector<std::string> lines = lines_of(fixtures::hotend40w_constants());
  std::ostringstream want;
  const StateFeedbackConstants& k = fixtures::hotend40w_constants();
  want << "M311 I0 A" << int(k.n) << " B" << int(k.output_mask) << " C" << int(k.delay) << " D" << int(k.decimation)
       << " E" << int(k.input_shift) << " F" << k.ambient_q8 << " G" << k.phi_diag[0] << " H" << k.phi_diag[1];
  EXPECT_EQ(lines[0], want.str());
}

}  // namespace

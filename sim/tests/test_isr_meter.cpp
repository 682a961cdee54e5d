// The interrupt meter (AvrBoard::isr_cycles) on the real images: it must pair every entry with
// its RETI, and the handlers it measures must leave the UART receiver its margin.
#include <string>

#include <gtest/gtest.h>

#include "sim/avr_board.h"
#include "sim/board_spec.h"

namespace sim {
namespace {

const IsrCycleStats* find(const std::vector<IsrCycleStats>& all, const std::string& name) {
  for (const IsrCycleStats& s : all)
    if (s.name == name) return &s;
  return nullptr;
}

class IsrMeter : public ::testing::TestWithParam<std::string> {};

TEST_P(IsrMeter, CountsEveryHandlerAndTheyFitBetweenTwoReceivedBytes) {
  const BoardSpec* spec = find_board(GetParam());
  ASSERT_NE(spec, nullptr);
  AvrBoard board(*spec, std::string(HOTEND_FIRMWARE_DIR) + "/firmware-" + spec->id + ".elf");
  // Back-to-back M105 lines at the wire's pace: the RX handler runs once per byte.
  const std::string line = "M105\n";
  int sent = 0;
  board.feed_uart_line([&]() -> int { return sent < 200 ? line[sent++ % line.size()] : -1; });
  ASSERT_EQ(board.run_until(board.cycles_from_s(2.0)), CpuState::kRunning);

  const IsrCycleStats* tick = find(board.isr_cycles(), "tick");
  const IsrCycleStats* rx = find(board.isr_cycles(), "uart rx");
  const IsrCycleStats* udre = find(board.isr_cycles(), "uart udre");
  ASSERT_TRUE(tick && rx && udre);
  // 1 kHz tick from shortly after reset; one RX entry per byte received, none lost.
  EXPECT_NEAR(double(tick->count), 2000.0, 20.0);
  EXPECT_EQ(rx->count, 200u);
  EXPECT_EQ(board.uart_overruns(), 0u);
  EXPECT_GT(udre->count, 0u);  // the "ok T:" replies go out through it
  // The receiver holds two bytes and shifts a third in: a byte is lost only if interrupts stay
  // off for longer than two frames. The longest handlers back to back (+5 entry each) must fit.
  const uint64_t frame = board.uart_frame_cycles();
  ASSERT_GT(frame, 0u);
  EXPECT_LT(tick->max_cycles + rx->max_cycles + udre->max_cycles + 15, 2 * frame);
  for (const IsrCycleStats* s : {tick, rx, udre}) {
    EXPECT_GT(s->max_cycles, 20u) << s->name;  // a prologue alone is longer: entry/exit paired
    EXPECT_LE(s->mean_cycles(), double(s->max_cycles)) << s->name;
  }
}

INSTANTIATE_TEST_SUITE_P(Boards, IsrMeter, ::testing::Values("ramps14", "sanguinololu"));

}  // namespace
}  // namespace sim

// Fault-run verdict inputs: what counts as "heater off", "error printed", "restarted".
#include <gtest/gtest.h>

#include "sim/fault_outcome.h"

namespace sim {
namespace {

TEST(FaultOutcome, OpenThermistor) {
  FaultRecord r;
  r.kind = FaultKind::kOpen;
  r.fault_s = 60.0;
  r.heater_last_change_s = 60.2;
  const std::vector<ReplyLine> lines{{59.0, "Error:MAXTEMP triggered"},  // before the fault: ignored
                                     {60.15, "Error:MINTEMP triggered"}};
  const FaultOutcome f = evaluate_fault(r, lines);
  ASSERT_TRUE(f.heater_last_on_s);
  EXPECT_NEAR(*f.heater_last_on_s, 0.2, 1e-9);
  EXPECT_EQ(f.expected_error, "MINTEMP");
  ASSERT_TRUE(f.error_line_s);
  EXPECT_NEAR(*f.error_line_s, 0.15, 1e-9);
  EXPECT_FALSE(f.reset_s);
}

// Issue 8: a plant fault wants Marlin's "…system stopped!" line (MAXTEMP does not count) and
// records the block's peak and the lowest reading until that line.
TEST(FaultOutcome, PlantFaultWantsTheModelCheckLineAndTheLowestReadingBeforeIt) {
  FaultRecord r;
  r.kind = FaultKind::kQuarterPower;
  r.fault_s = 100.0;
  r.heater_last_change_s = 107.0;
  r.block_peak_c = 212.5;
  r.true_c = {{100.1, 210.0}, {104.0, 203.0}, {107.0, 199.0}, {120.0, 150.0}};
  const std::vector<ReplyLine> lines{{105.0, "Error:MAXTEMP triggered"},
                                     {107.0, "Error:Thermal Runaway, system stopped! Heater_ID: 0"}};
  const FaultOutcome f = evaluate_fault(r, lines);
  ASSERT_TRUE(f.error_line_s);
  EXPECT_NEAR(*f.error_line_s, 7.0, 1e-9);
  ASSERT_TRUE(f.first_error_s);
  EXPECT_NEAR(*f.first_error_s, 5.0, 1e-9);
  EXPECT_EQ(f.first_error, "Error:MAXTEMP triggered");
  EXPECT_DOUBLE_EQ(f.block_peak_c, 212.5);
  EXPECT_DOUBLE_EQ(f.sensor_min_before_error_c, 199.0);  // 150 °C came after the Error
}

TEST(FaultOutcome, HeaterOffBeforeTheFaultCountsAsZero) {
  FaultRecord r;
  r.kind = FaultKind::kShort;
  r.fault_s = 60.0;
  r.heater_last_change_s = 59.9;
  const FaultOutcome f = evaluate_fault(r, {});
  EXPECT_DOUBLE_EQ(*f.heater_last_on_s, 0.0);
  EXPECT_FALSE(f.error_line_s);
}

TEST(FaultOutcome, HangNeedsStartAfterTheReset) {
  FaultRecord r;
  r.kind = FaultKind::kHang;
  r.fault_s = 60.0;
  r.reset_s = 60.5;
  r.heater_last_change_s = 60.5;
  FaultOutcome f = evaluate_fault(r, {{0.01, "start"}});
  EXPECT_NEAR(*f.reset_s, 0.5, 1e-9);
  EXPECT_FALSE(f.restarted);
  EXPECT_FALSE(f.heater_on_after_reset);
  f = evaluate_fault(r, {{0.01, "start"}, {60.52, "start"}});
  EXPECT_TRUE(f.restarted);
  r.heater_turned_on_after_reset = true;
  EXPECT_TRUE(evaluate_fault(r, {}).heater_on_after_reset);
}

TEST(FaultOutcome, HeaterStillOnAtTheEnd) {
  FaultRecord r;
  r.kind = FaultKind::kOpen;
  r.heater_on_at_end = true;
  EXPECT_FALSE(evaluate_fault(r, {}).heater_last_on_s);
}

}  // namespace
}  // namespace sim

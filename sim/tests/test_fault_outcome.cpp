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

// The serial-layer scenarios' own pieces: the host's line framing and the overrun verdict.
#include <gtest/gtest.h>

#include "sim/serial_scenario.h"

namespace sim {
namespace {

std::vector<ReplyLine> replies(std::initializer_list<const char*> texts) {
  std::vector<ReplyLine> lines;
  for (const char* t : texts) lines.push_back(ReplyLine{10.0, t});
  return lines;
}

TEST(SerialScenario, NumberedLineCarriesTheHostChecksum) {
  EXPECT_EQ(numbered_line(0, "M110 N0"), "N0 M110 N0*125");  // what OctoPrint sends on connect
}

TEST(SerialScenario, NumberedOverrunNeedsTheResendOfTheFirstLostLine) {
  const auto good = replies({"ok", "ok T:1 /2 @:3", "ok T:1 /2 @:3",
                             "Error:Format error: serial input lost, Last Line: 3", "Resend: 4", "ok"});
  EXPECT_TRUE(check_overrun_replies(FaultKind::kOverrunNumbered, good, 0.0).empty());
  const auto wrong = replies({"ok T:1 /2 @:3", "Error:Format error: serial input lost, Last Line: 1", "Resend: 2", "ok"});
  EXPECT_EQ(check_overrun_replies(FaultKind::kOverrunNumbered, wrong, 0.0).size(), 1u);
}

TEST(SerialScenario, GluedOrMissingReportsFail) {
  EXPECT_FALSE(check_overrun_replies(FaultKind::kOverrun, replies({"ok T:1 /2 @:3"}), 0.0).empty());
  const auto glued = replies({"echo:Unknown command: \"ler 7\"", "Error:Format error: serial input lost, line discarded", "ok"});
  EXPECT_EQ(check_overrun_replies(FaultKind::kOverrun, glued, 0.0).size(), 1u);
  const auto ran_after = replies({"Error:Format error: serial input lost, line discarded", "ok", "ok T:1 /2 @:3"});
  EXPECT_EQ(check_overrun_replies(FaultKind::kOverrun, ran_after, 0.0).size(), 1u);
}

}  // namespace
}  // namespace sim

// The host line protocol: line numbers, checksums, Resend requests, M110, and M112 passing
// every check. Replies are compared as exact text.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_tests/gcode_fakes.h"

namespace {

using gcode_test::numbered;
using gcode_test::Rig;

using Calls = std::vector<std::string>;

TEST(GcodeProtocol, PlainLinesNeedNoNumbers) {
  Rig rig;
  EXPECT_EQ(rig.send("M104 S200\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 51200"});
}

TEST(GcodeProtocol, NumberedLinesInSequenceAreAccepted) {
  Rig rig;
  EXPECT_EQ(rig.send(numbered(1, "M104 S200")), "ok\n");
  EXPECT_EQ(rig.send(numbered(2, "M106 S10")), "ok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"set_target 51200", "fan 10"}));
}

TEST(GcodeProtocol, KnownChecksum) {
  Rig rig;
  // XOR of "N1 M105" is 38: the value Pronterface/OctoPrint send.
  EXPECT_EQ(gcode_test::numbered(1, "M105"), "N1 M105*38\n");
  EXPECT_EQ(rig.send("N1 M105*38\n"), "ok T:25.00 /0.00 @:0\n");
}

TEST(GcodeProtocol, ChecksumMismatchAsksForResendAndChangesNothing) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send("N2 M104 S200*99\n"),
            "Error:checksum mismatch, Last Line: 1\nResend: 2\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
  EXPECT_EQ(rig.send(numbered(2, "M104 S200")), "ok\n");  // the resent line is taken
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 51200"});
}

TEST(GcodeProtocol, CorruptedByteIsCaughtByChecksum) {
  Rig rig;
  std::string line = numbered(1, "M104 S200");
  line[7] = '9';  // S200 -> S900 in transit
  EXPECT_EQ(rig.send(line), "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeProtocol, MalformedChecksumField) {
  Rig rig;
  EXPECT_EQ(rig.send("N1 M105*\n"), "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
  EXPECT_EQ(rig.send("N1 M105*38x\n"), "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
  EXPECT_EQ(rig.send("N1 M105*-38\n"), "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
}

TEST(GcodeProtocol, LineNumberWithoutChecksum) {
  Rig rig;
  EXPECT_EQ(rig.send("N1 M104 S200\n"),
            "Error:No checksum with line number, Last Line: 0\nResend: 1\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeProtocol, ChecksumWithoutLineNumber) {
  Rig rig;
  EXPECT_EQ(rig.send("M104 S200*42\n"),
            "Error:No line number with checksum, Last Line: 0\nResend: 1\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeProtocol, SkippedLineNumber) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send(numbered(3, "M104 S200")),
            "Error:Line number is not last line number+1, Last Line: 1\nResend: 2\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeProtocol, RepeatedLineNumber) {
  Rig rig;
  rig.send(numbered(1, "M106 S1"));
  EXPECT_EQ(rig.send(numbered(1, "M106 S1")),
            "Error:Line number is not last line number+1, Last Line: 1\nResend: 2\nok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"fan 1"});  // executed once
}

TEST(GcodeProtocol, BadLineNumber) {
  Rig rig;
  EXPECT_EQ(rig.send("Nx M105*10\n"), "Error:Bad line number, Last Line: 0\nResend: 1\nok\n");
  EXPECT_EQ(rig.send(numbered(99999999, "M105").replace(1, 8, "9999999999")),
            "Error:Bad line number, Last Line: 0\nResend: 1\nok\n");
}

TEST(GcodeProtocol, PlainLinesDoNotMoveTheLineNumber) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  rig.send("M105\n");
  EXPECT_EQ(rig.send(numbered(2, "M105")), "ok T:25.00 /0.00 @:0\n");
}

TEST(GcodeProtocol, M110ParameterSetsTheLastLine) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send("M110 N100\n"), "ok\n");
  EXPECT_EQ(rig.send(numbered(100, "M105")),
            "Error:Line number is not last line number+1, Last Line: 100\nResend: 101\nok\n");
  EXPECT_EQ(rig.send(numbered(101, "M106")), "ok\n");
}

TEST(GcodeProtocol, NumberedM110IsExemptFromTheSequence) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send(numbered(0, "M110 N0")), "ok\n");  // how OctoPrint resets on connect
  EXPECT_EQ(rig.send(numbered(1, "M105")), "ok T:25.00 /0.00 @:0\n");
  EXPECT_EQ(rig.send(numbered(41, "M110")), "ok\n");     // number from the line itself
  EXPECT_EQ(rig.send(numbered(42, "M105")), "ok T:25.00 /0.00 @:0\n");
}

TEST(GcodeProtocol, PrintrunsMinusOneM110MakesTheNextLineZero) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send(numbered(-1, "M110")), "ok\n");  // printcore's "N-1 M110*15"
  EXPECT_EQ(rig.send(numbered(0, "M105")), "ok T:25.00 /0.00 @:0\n");
  EXPECT_EQ(rig.send(numbered(-1, "M105")),
            "Error:Line number is not last line number+1, Last Line: 0\nResend: 1\nok\n");
  EXPECT_EQ(rig.send(numbered(-2, "M110")), "Error:Bad line number, Last Line: 0\nResend: 1\nok\n");
}

TEST(GcodeProtocol, M110NeedsAValidNumber) {
  Rig rig;
  EXPECT_EQ(rig.send("M110 N-1\n"), "Error:M110 N must be an integer in 0..2147483646\nok\n");
  EXPECT_EQ(rig.send("M110 N1.5\n"), "Error:M110 N must be an integer in 0..2147483646\nok\n");
  EXPECT_EQ(rig.send(numbered(1, "M105")), "ok T:25.00 /0.00 @:0\n");  // still at 0
}

TEST(GcodeProtocol, OverlongLineAsksForResend) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  const std::string too_long = "M117 " + std::string(120, 'x') + "\n";
  EXPECT_EQ(rig.send(too_long), "Error:Format error: line too long, Last Line: 1\nResend: 2\nok\n");
  EXPECT_EQ(rig.send(numbered(2, "M105")), "ok T:25.00 /0.00 @:0\n");
}

TEST(GcodeProtocol, CommentsAreNotChecksummed) {
  Rig rig;
  const std::string line = numbered(1, "M106 S5");
  EXPECT_EQ(rig.send(line.substr(0, line.size() - 1) + " ; fan on\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"fan 5"});
}

TEST(GcodeProtocol, NumberedEmptyLineIsAcknowledged) {
  Rig rig;
  EXPECT_EQ(rig.send(numbered(1, "")), "ok\n");
  EXPECT_EQ(rig.send(numbered(2, "M105")), "ok T:25.00 /0.00 @:0\n");
}

TEST(GcodeProtocol, EmptyAndCommentLinesGetNoReply) {
  Rig rig;
  EXPECT_EQ(rig.send("\n\r\n   \n; just a comment\n"), "");
}

TEST(GcodeProtocol, EmergencyStopPassesABadChecksum) {
  Rig rig;
  rig.send(numbered(1, "M105"));
  EXPECT_EQ(rig.send("N7 M112*0\n"),
            "Error:Emergency stop (M112): heater off until M999\n"
            "Error:checksum mismatch, Last Line: 1\nResend: 2\nok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"emergency_stop"});
}

TEST(GcodeProtocol, EmergencyStopInSequenceRunsOnce) {
  Rig rig;
  EXPECT_EQ(rig.send(numbered(1, "M112")),
            "Error:Emergency stop (M112): heater off until M999\nok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"emergency_stop"});
  EXPECT_EQ(rig.send("M112\n"), "Error:Emergency stop (M112): heater off until M999\nok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"emergency_stop", "emergency_stop"}));
}

TEST(GcodeProtocol, CompactAndLowerCaseCommands) {
  Rig rig;
  EXPECT_EQ(rig.send("m104 s200\n"), "ok\n");
  EXPECT_EQ(rig.send("M104S210\n"), "ok\n");
  EXPECT_EQ(rig.send(gcode_test::checksummed("N1M106S7")), "ok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"set_target 51200", "set_target 53760", "fan 7"}));
}

}  // namespace

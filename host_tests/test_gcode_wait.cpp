// M109's deferred "ok", the temperature lines while waiting, lines held behind the wait,
// M108/M112 during it, and M155 auto-reports. Time is a fake millisecond counter.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_tests/gcode_fakes.h"

namespace {

using gcode_test::numbered;
using gcode_test::Rig;
using Calls = std::vector<std::string>;

TEST(GcodeWait, M109DefersOkUntilTheTargetIsReached) {
  Rig rig;
  rig.poll(5000);
  EXPECT_EQ(rig.send("M109 S210\n"), "");  // no ok yet
  EXPECT_TRUE(rig.gcode.waiting());
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 53760"});
  EXPECT_EQ(rig.poll(5500), "");
  rig.machine.status.temp_q8 = 100 * 256;
  rig.machine.status.duty_q16 = 65535;
  EXPECT_EQ(rig.poll(6000), "T:100.00 /210.00 @:255\n");  // one line per second
  EXPECT_EQ(rig.poll(6999), "");
  EXPECT_EQ(rig.poll(7000), "T:100.00 /210.00 @:255\n");
  rig.machine.status.temp_q8 = 209 * 256 - 1;  // just outside the 1 °C window
  EXPECT_EQ(rig.poll(7100), "");
  rig.machine.status.temp_q8 = 209 * 256;
  EXPECT_EQ(rig.poll(7200), "ok\n");
  EXPECT_FALSE(rig.gcode.waiting());
  EXPECT_EQ(rig.poll(9000), "");  // no more reports (M155 is off)
}

TEST(GcodeWait, M109SDoesNotWaitForCooling) {
  Rig rig;
  rig.machine.status.temp_q8 = 250 * 256;
  EXPECT_EQ(rig.send("M109 S200\n"), "");
  EXPECT_EQ(rig.poll(10), "ok\n");
}

TEST(GcodeWait, M109RWaitsForCoolingToo) {
  Rig rig;
  rig.machine.status.temp_q8 = 250 * 256;
  EXPECT_EQ(rig.send("M109 R200\n"), "");
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 51200"});
  EXPECT_EQ(rig.poll(1000), "T:250.00 /200.00 @:0\n");
  rig.machine.status.temp_q8 = 201 * 256;
  EXPECT_EQ(rig.poll(1100), "ok\n");
}

TEST(GcodeWait, M109ZeroTargetEndsAtOnce) {
  Rig rig;
  EXPECT_EQ(rig.send("M109 S0\n"), "");
  EXPECT_EQ(rig.poll(1), "ok\n");
}

TEST(GcodeWait, M109R0EndsAtOnceWhileHot) {
  // Found by the fuzz target: M109 R0 waited for the hotend to cool to 0 °C, for ever.
  Rig rig;
  rig.machine.status.temp_q8 = 200 * 256;
  EXPECT_EQ(rig.send("M109 R0\n"), "");
  EXPECT_EQ(rig.poll(1), "ok\n");
  EXPECT_FALSE(rig.gcode.waiting());
}

TEST(GcodeWait, RefusedM109AnswersAtOnceAndDoesNotWait) {
  Rig rig;
  EXPECT_EQ(rig.send("M109 S300\n"), "Error:M109 S out of range 0..275\nok\n");
  EXPECT_EQ(rig.send("M109\n"), "Error:M109: missing R\nok\n");
  rig.machine.refusal = GCODE_TEXT("Heater fault latched, M999 to clear");
  EXPECT_EQ(rig.send("M109 S200\n"), "Error:Heater fault latched, M999 to clear\nok\n");
  EXPECT_FALSE(rig.gcode.waiting());
}

TEST(GcodeWait, FaultEndsTheWait) {
  Rig rig;
  rig.send("M109 S210\n");
  rig.machine.status.fault = true;
  EXPECT_EQ(rig.poll(100), "ok\n");
  EXPECT_FALSE(rig.gcode.waiting());
}

TEST(GcodeWait, OtherLinesAreHeldUntilTheWaitEnds) {
  Rig rig;
  rig.send(numbered(1, "M109 S210"));
  EXPECT_TRUE(rig.gcode.accepting());
  EXPECT_EQ(rig.send(numbered(2, "M106 S9")), "");
  EXPECT_FALSE(rig.gcode.accepting());  // the main loop leaves further bytes in the UART ring
  EXPECT_EQ(rig.send("M107\n"), "");     // contract violation: ignored, not mixed into the line
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 53760"});
  rig.machine.status.temp_q8 = 210 * 256;
  EXPECT_EQ(rig.poll(500), "ok\nok\n");  // M109's, then the held M106's
  EXPECT_EQ(rig.machine.calls, (Calls{"set_target 53760", "fan 9"}));
  EXPECT_TRUE(rig.gcode.accepting());
  EXPECT_EQ(rig.send(numbered(3, "M105")), "ok T:210.00 /210.00 @:0\n");
}

TEST(GcodeWait, HeldM109StartsTheNextWait) {
  Rig rig;
  rig.send("M109 S100\n");
  rig.send("M109 S210\n");
  rig.machine.status.temp_q8 = 100 * 256;
  EXPECT_EQ(rig.poll(100), "ok\n");  // first wait done; second started without an ok
  EXPECT_TRUE(rig.gcode.waiting());
  EXPECT_TRUE(rig.gcode.accepting());
  rig.machine.status.temp_q8 = 210 * 256;
  EXPECT_EQ(rig.poll(200), "ok\n");
}

TEST(GcodeWait, M108CancelsTheWait) {
  Rig rig;
  rig.send(numbered(1, "M109 S210"));
  EXPECT_EQ(rig.send(numbered(2, "M108")), "ok\nok\n");  // M109's ok, then M108's
  EXPECT_FALSE(rig.gcode.waiting());
  EXPECT_EQ(rig.machine.status.target_q8, 210 * 256);  // the target stays set
  EXPECT_EQ(rig.send("M108\n"), "ok\n");               // harmless when not waiting
}

TEST(GcodeWait, M112IsExecutedDuringTheWait) {
  Rig rig;
  rig.send("M109 S210\n");
  EXPECT_EQ(rig.send("M112\n"), "Error:Emergency stop (M112): heater off until M999\nok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"set_target 53760", "emergency_stop"}));
  EXPECT_EQ(rig.poll(100), "ok\n");  // the fault ends the wait
}

// The firmware's order: every byte passes the emergency parser when it arrives (RX interrupt),
// but reaches the line layer only when the main loop reads the ring, which it stops doing
// while a line is held behind a wait.
struct RingRig {
  Rig rig;
  std::string ring;

  std::string send(const std::string& text) {
    for (char c : text) {
      const gcode::Urgent urgent = rig.emergency.feed(static_cast<uint8_t>(c));
      if (urgent != gcode::Urgent::kNone) rig.gcode.urgent(urgent);
      ring += c;
    }
    pump();
    return rig.out.take();
  }
  std::string poll(uint32_t now_ms) {
    rig.gcode.poll(now_ms);
    pump();
    return rig.out.take();
  }
  void pump() {
    std::size_t used = 0;
    while (used < ring.size() && rig.gcode.accepting()) rig.gcode.feed(ring[used++]);
    ring.erase(0, used);
  }
};

// Issue 8: an M112 behind a waiting M109 and a held line ran only when the wait ended (85 s
// late in simavr). Now it acts as its bytes arrive.
TEST(GcodeWait, M112BehindAHeldLineActsAtOnce) {
  RingRig board;
  board.send(numbered(1, "M109 S210"));
  EXPECT_EQ(board.send(numbered(2, "M105")), "");  // held
  EXPECT_FALSE(board.rig.gcode.accepting());
  EXPECT_EQ(board.send(numbered(3, "M112")), "Error:Emergency stop (M112): heater off until M999\n");
  EXPECT_EQ(board.rig.machine.calls, (Calls{"set_target 53760", "emergency_stop"}));
  // The fault ends the wait; the held M105 and the M112 line follow, each with one ok.
  EXPECT_EQ(board.poll(100), "ok\nok T:25.00 /210.00 @:0\nok\n");
  EXPECT_EQ(board.rig.machine.calls, (Calls{"set_target 53760", "emergency_stop"}));  // stopped once
}

// An M108 ends the wait ahead of the held line; its own line, read later, must not cancel the
// wait that the held line started.
TEST(GcodeWait, M108LineDoesNotCancelALaterWait) {
  RingRig board;
  board.send("M109 S100\n");
  board.send("M109 S210\n");  // held
  // The first M109's ok (the second one now waits), then the M108 line's own ok.
  EXPECT_EQ(board.send("M108\n"), "ok\nok\n");
  EXPECT_TRUE(board.rig.gcode.waiting());
  EXPECT_EQ(board.rig.machine.calls, (Calls{"set_target 25600", "cancel_heating", "set_target 53760"}));
  board.rig.machine.status.temp_q8 = 210 * 256;
  EXPECT_EQ(board.poll(100), "ok\n");  // the second wait ends only at its target
}

// M108 during M303 (no M109 wait): the machine's heating job is cancelled once.
TEST(GcodeWait, M108CancelsTheHeatingJobOnce) {
  Rig rig;
  EXPECT_EQ(rig.send("M108\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"cancel_heating"});
}

TEST(GcodeWait, M155AutoReports) {
  Rig rig;
  rig.poll(1000);
  EXPECT_EQ(rig.send("M155 S2\n"), "ok\n");
  EXPECT_EQ(rig.poll(2999), "");
  EXPECT_EQ(rig.poll(3000), "T:25.00 /0.00 @:0\n");
  EXPECT_EQ(rig.poll(4000), "");
  EXPECT_EQ(rig.poll(5001), "T:25.00 /0.00 @:0\n");
  EXPECT_EQ(rig.send("M155 S0\n"), "ok\n");
  EXPECT_EQ(rig.poll(20000), "");
}

TEST(GcodeWait, M155SurvivesTimerWrap) {
  Rig rig;
  rig.poll(0xFFFFFE00u);  // 512 ms before the 32-bit millisecond counter wraps
  rig.send("M155 S1\n");
  EXPECT_EQ(rig.poll(0xFFFFFFFFu), "");
  EXPECT_EQ(rig.poll(0x000001E7u), "");
  EXPECT_EQ(rig.poll(0x000001E8u), "T:25.00 /0.00 @:0\n");  // 1000 ms later across the wrap
}

TEST(GcodeWait, M155RejectsBadIntervals) {
  Rig rig;
  EXPECT_EQ(rig.send("M155 S61\n"), "Error:M155 S must be an integer in 0..60\nok\n");
  EXPECT_EQ(rig.send("M155 S1.5\n"), "Error:M155 S must be an integer in 0..60\nok\n");
  EXPECT_EQ(rig.send("M155\n"), "Error:M155: missing S\nok\n");
  EXPECT_EQ(rig.poll(100000), "");  // still off
}

TEST(GcodeWait, AutoReportPausesWhileWaiting) {
  Rig rig;
  rig.send("M155 S1\n");
  rig.send("M109 S210\n");
  EXPECT_EQ(rig.poll(1000), "T:25.00 /210.00 @:0\n");  // the wait's own 1 s line, not two
}

}  // namespace

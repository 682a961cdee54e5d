// Each built-in command: happy path with its exact reply, and refused input that must leave
// the machine untouched.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host_tests/gcode_fakes.h"

namespace {

using gcode_test::Rig;
using Calls = std::vector<std::string>;

TEST(GcodeCommands, M104SetsTargetInQ8) {
  Rig rig;
  EXPECT_EQ(rig.send("M104 S210.5\n"), "ok\n");
  EXPECT_EQ(rig.send("M104 S0\n"), "ok\n");
  EXPECT_EQ(rig.send("M104 S275 T0\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"set_target 53888", "set_target 0", "set_target 70400"}));
}

TEST(GcodeCommands, M104RefusesBadTargets) {
  Rig rig;
  EXPECT_EQ(rig.send("M104 S275.01\n"), "Error:M104 S out of range 0..275\nok\n");
  EXPECT_EQ(rig.send("M104 S-1\n"), "Error:M104 S out of range 0..275\nok\n");
  EXPECT_EQ(rig.send("M104 S99999\n"), "Error:M104 S out of range 0..275\nok\n");
  EXPECT_EQ(rig.send("M104 S2x1\n"), "Error:M104: malformed parameter \"S2x1\"\nok\n");
  EXPECT_EQ(rig.send("M104 S\n"), "Error:M104: malformed parameter \"S\"\nok\n");
  EXPECT_EQ(rig.send("M104 S--1\n"), "Error:M104: malformed parameter \"S--1\"\nok\n");
  EXPECT_EQ(rig.send("M104 S200 5\n"), "Error:M104: malformed parameter \"5\"\nok\n");
  EXPECT_EQ(rig.send("M104\n"), "Error:M104: missing S\nok\n");
  EXPECT_EQ(rig.send("M104 S200 T1\n"), "Error:M104 T must be an integer in 0..0\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeCommands, MaximumComesFromTheMachine) {
  Rig rig;
  rig.machine.max_target = 250 * 256 + 128;
  EXPECT_EQ(rig.send("M104 S251\n"), "Error:M104 S out of range 0..250.50\nok\n");
  EXPECT_EQ(rig.send("M104 S250.5\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"set_target 64128"});
}

TEST(GcodeCommands, MachineRefusalIsReported) {
  Rig rig;
  rig.machine.refusal = GCODE_TEXT("Heater fault latched, M999 to clear");
  EXPECT_EQ(rig.send("M104 S200\n"), "Error:Heater fault latched, M999 to clear\nok\n");
  EXPECT_EQ(rig.machine.status.target_q8, 0);
}

TEST(GcodeCommands, M105ReportsTemperatureTargetAndPower) {
  Rig rig;
  rig.machine.status = {210 * 256, 210 * 256, 87 * 256 + 255, false};
  EXPECT_EQ(rig.send("M105\n"), "ok T:210.00 /210.00 @:87\n");
  rig.machine.status = {53759, 53888, 65535, false};
  EXPECT_EQ(rig.send("M105\n"), "ok T:210.00 /210.50 @:255\n");
  rig.machine.status = {-5 * 256 - 192, 0, 0, true};
  EXPECT_EQ(rig.send("M105 T0\n"), "ok T:-5.75 /0.00 @:0\n");
  EXPECT_EQ(rig.send("M105 T2\n"), "Error:M105 T must be an integer in 0..0\nok\n");
}

TEST(GcodeCommands, M301SetsAnySubsetAndReports) {
  Rig rig;
  EXPECT_EQ(rig.send("M301\n"), "echo: p:22.20 i:1.08 d:114.00\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
  EXPECT_EQ(rig.send("M301 P30 D50.5\n"), "echo: p:30.00 i:1.08 d:50.50\nok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"set_pid 1966080 70779 3309568"});
  // Printed with the decimals it needs to read back (not "0.01", 19 % off).
  EXPECT_EQ(rig.send("M301 I0.0123\n"), "echo: p:30.00 i:0.0123 d:50.50\nok\n");
  EXPECT_EQ(rig.machine.gains.ki_q16, 806);  // 0.0123 × 65536 = 806.1
}

TEST(GcodeCommands, M301ChangesNothingOnAnyBadGain) {
  Rig rig;
  EXPECT_EQ(rig.send("M301 P30 I-1 D50\n"), "Error:M301 I out of range 0..32767\nok\n");
  EXPECT_EQ(rig.send("M301 P30 I1 Dx\n"), "Error:M301: malformed parameter \"Dx\"\nok\n");
  EXPECT_EQ(rig.send("M301 P40000\n"), "Error:M301 P out of range 0..32767\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
  rig.machine.refusal = GCODE_TEXT("Gains beyond the controller's range");
  EXPECT_EQ(rig.send("M301 P3000\n"), "Error:Gains beyond the controller's range\nok\n");
  EXPECT_EQ(rig.machine.gains.kp_q16, 1454899);
}

TEST(GcodeCommands, FanCommands) {
  Rig rig;
  EXPECT_EQ(rig.send("M106 S128\n"), "ok\n");
  EXPECT_EQ(rig.send("M106\n"), "ok\n");
  EXPECT_EQ(rig.send("M106 S127.5\n"), "ok\n");  // Cura's fractional duty rounds
  EXPECT_EQ(rig.send("M106 S0\n"), "ok\n");
  EXPECT_EQ(rig.send("M107\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"fan 128", "fan 255", "fan 128", "fan 0", "fan 0"}));
  EXPECT_EQ(rig.send("M106 S256\n"), "Error:M106 S out of range 0..255\nok\n");
  EXPECT_EQ(rig.send("M106 S-1\n"), "Error:M106 S out of range 0..255\nok\n");
  EXPECT_EQ(rig.machine.calls.size(), 5u);
}

TEST(GcodeCommands, M115FirmwareInfoAndCapabilities) {
  Rig rig;
  EXPECT_EQ(rig.send("M115\n"),
            "FIRMWARE_NAME:hotend-controller FIRMWARE_VERSION:1.2.3 PROTOCOL_VERSION:1.0 "
            "MACHINE_TYPE:Test board EXTRUDER_COUNT:1\n"
            "Cap:AUTOREPORT_TEMP:1\nCap:EEPROM:1\nCap:EMERGENCY_PARSER:1\nCap:SERIAL_XON_XOFF:0\n"
            "ok\n");
}

// M500 on silicon takes up to ~0.8 s of EEPROM writes: its "ok" comes only once the machine
// says the write has ended, further lines wait (never two commands at once), M108 does not
// cut it short, and M112 still acts at once.
TEST(GcodeCommands, M500OkWaitsForThePendingWrite) {
  Rig rig;
  rig.machine.pending = true;
  EXPECT_EQ(rig.send("M500\n"), "");
  EXPECT_EQ(rig.send("M105\n"), "");  // held behind the write
  EXPECT_FALSE(rig.gcode.accepting());
  EXPECT_EQ(rig.poll(5000), "");  // no temperature lines: not a heating wait
  EXPECT_EQ(rig.machine.calls, (Calls{"save"}));
  rig.machine.pending = false;
  EXPECT_EQ(rig.poll(5100), "ok\nok T:25.00 /0.00 @:0\n");  // M500's ok, then the held M105
  EXPECT_TRUE(rig.gcode.accepting());
}

TEST(GcodeCommands, M108AndM112DuringAPendingWrite) {
  Rig rig;
  rig.machine.pending = true;
  EXPECT_EQ(rig.send("M500\n"), "");
  EXPECT_EQ(rig.send("M108\n"), "ok\n");  // answered, but the write's ok still waits
  EXPECT_EQ(rig.poll(10), "");
  EXPECT_EQ(rig.send("M112\n"), "Error:Emergency stop (M112): heater off until M999\nok\n");
  rig.machine.pending = false;
  EXPECT_EQ(rig.poll(20), "ok\n");
}

TEST(GcodeCommands, SettingsCommands) {
  Rig rig;
  EXPECT_EQ(rig.send("M500\n"), "ok\n");  // the machine prints what it stored
  EXPECT_EQ(rig.send("M501\n"), "echo:Settings loaded\nok\n");
  EXPECT_EQ(rig.send("M502\n"), "echo:Default settings loaded (M500 stores them)\nok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"save", "load", "reset"}));
  rig.machine.refusal = GCODE_TEXT("EEPROM contents invalid, settings unchanged");
  EXPECT_EQ(rig.send("M501\n"), "Error:EEPROM contents invalid, settings unchanged\nok\n");
}

// The machine's lines first: M301 is checked against the fuzzy spread M312 sets (replay order).
TEST(GcodeCommands, M503ReportsMachineSettingsThenPid) {
  Rig rig;
  EXPECT_EQ(rig.send("M503\n"),
            "echo:  M900 K3\n"
            "echo:; Hotend PID (Marlin units):\necho:  M301 P22.20 I1.08 D114.00\nok\n");
}

TEST(GcodeCommands, M112AndM999) {
  Rig rig;
  EXPECT_EQ(rig.send("M112\n"), "Error:Emergency stop (M112): heater off until M999\nok\n");
  rig.machine.refusal = GCODE_TEXT("MINTEMP: thermistor still open");
  EXPECT_EQ(rig.send("M999\n"), "Error:MINTEMP: thermistor still open\nok\n");
  rig.machine.refusal = nullptr;
  EXPECT_EQ(rig.send("M999\n"), "ok\n");
  EXPECT_EQ(rig.machine.calls, (Calls{"emergency_stop", "clear_fault", "clear_fault"}));
}

TEST(GcodeCommands, D0HangsForTheWatchdog) {
  Rig rig;
  EXPECT_EQ(rig.send("D0\n"), "ok\n");  // on the board it never returns
  EXPECT_EQ(rig.machine.calls, Calls{"hang"});
  EXPECT_EQ(rig.send("D1\n"), "echo:Unknown command: \"D1\"\nok\n");
}

TEST(GcodeCommands, ToolSelection) {
  Rig rig;
  EXPECT_EQ(rig.send("T0\n"), "ok\n");
  EXPECT_EQ(rig.send("T1\n"), "Error:T1: only T0 exists\nok\n");
}

TEST(GcodeCommands, UnknownCommandsEchoAsTyped) {
  Rig rig;
  EXPECT_EQ(rig.send("G28 X0 Y\n"), "echo:Unknown command: \"G28 X0 Y\"\nok\n");
  EXPECT_EQ(rig.send("m42 p1\n"), "echo:Unknown command: \"m42 p1\"\nok\n");
  EXPECT_EQ(rig.send("hello world\n"), "echo:Unknown command: \"hello world\"\nok\n");
  EXPECT_EQ(rig.send("M104.1 S3\n"), "echo:Unknown command: \"M104.1 S3\"\nok\n");
  EXPECT_EQ(rig.send(gcode_test::numbered(1, "G1 X5")), "echo:Unknown command: \"G1 X5\"\nok\n");
  EXPECT_EQ(rig.send(gcode_test::numbered(2, "G4  ")), "echo:Unknown command: \"G4\"\nok\n");
  EXPECT_TRUE(rig.machine.calls.empty());
}

TEST(GcodeCommands, MachineExtensionCommands) {
  Rig rig;
  EXPECT_EQ(rig.send("M900 K4\n"), "ok\n");
  EXPECT_EQ(rig.send("M900 K10\n"), "Error:M900 K must be an integer in 0..9\nok\n");
  EXPECT_EQ(rig.send("M900\n"), "Error:M900: missing K\nok\n");
  EXPECT_EQ(rig.send("M900 Kq\n"), "Error:M900: malformed parameter \"Kq\"\nok\n");
  EXPECT_EQ(rig.machine.calls, Calls{"M900 4"});
}

}  // namespace

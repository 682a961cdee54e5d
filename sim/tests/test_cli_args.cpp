// Command-line values: the G-code script and fault syntax users type.
#include <gtest/gtest.h>

#include <stdexcept>

#include "sim/cli_args.h"

namespace sim {
namespace {

TEST(CliArgs, GcodeScriptSplitsUntimedAndTimedCommands) {
  const auto cmds = parse_gcode(" M301 P1 I2 D3 ; M106 S255@120;;M107 @ 300.5 ");
  ASSERT_EQ(cmds.size(), 3u);
  EXPECT_EQ(cmds[0].line, "M301 P1 I2 D3");
  EXPECT_FALSE(cmds[0].at_s);
  EXPECT_EQ(cmds[1].line, "M106 S255");
  EXPECT_DOUBLE_EQ(*cmds[1].at_s, 120.0);
  EXPECT_EQ(cmds[2].line, "M107");
  EXPECT_DOUBLE_EQ(*cmds[2].at_s, 300.5);
  EXPECT_THROW(parse_gcode("M106 S255@soon"), std::invalid_argument);
}

TEST(CliArgs, Faults) {
  RunConfig c;
  parse_fault("short@42", c);
  EXPECT_EQ(c.fault, FaultKind::kShort);
  EXPECT_DOUBLE_EQ(c.fault_at_s, 42.0);
  parse_fault("hang@1", c);
  EXPECT_EQ(c.fault, FaultKind::kHang);
  parse_fault("detached@150", c);
  EXPECT_EQ(c.fault, FaultKind::kDetached);
  EXPECT_DOUBLE_EQ(c.fault_at_s, 150.0);
  parse_fault("heater-dead@1", c);
  EXPECT_EQ(c.fault, FaultKind::kHeaterDead);
  parse_fault("stuck-on@1", c);
  EXPECT_EQ(c.fault, FaultKind::kStuckOn);
  parse_fault("quarter-power@1", c);
  EXPECT_EQ(c.fault, FaultKind::kQuarterPower);
  parse_fault("fan-stuck@1", c);
  EXPECT_EQ(c.fault, FaultKind::kFanStuck);
  EXPECT_TRUE(is_plant_fault(FaultKind::kFanStuck));
  EXPECT_FALSE(is_plant_fault(FaultKind::kOpen));
  EXPECT_THROW(parse_fault("melt@1", c), std::invalid_argument);
  EXPECT_THROW(parse_fault("open", c), std::invalid_argument);
}

TEST(CliArgs, GainsAndOptions) {
  const MarlinGains g = parse_gains("22.2,1.08,114");
  EXPECT_DOUBLE_EQ(g.kp, 22.2);
  EXPECT_DOUBLE_EQ(g.kd, 114.0);
  EXPECT_THROW(parse_gains("1,2"), std::invalid_argument);

  const Options o =
      parse_options({"--board", "ramps14", "--check", "--variant=a=M1", "--variant", "b="}, {"check"});
  EXPECT_EQ(o.get("board"), "ramps14");
  EXPECT_TRUE(o.has("check"));
  EXPECT_EQ(o.all("variant"), (std::vector<std::string>{"a=M1", "b="}));
  EXPECT_THROW(reject_unknown(o, {"board"}), std::invalid_argument);
  EXPECT_THROW(parse_options({"--board"}, {}), std::invalid_argument);
  EXPECT_THROW(parse_options({"ramps14"}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace sim

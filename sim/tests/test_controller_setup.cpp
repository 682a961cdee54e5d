// Per-plant controller set-ups: the model the feedforward is given, the state-feedback design
// from the plant's own matrices, the conversion of the seeds' published gains, and the G-code
// each controller name sends.
#include <gtest/gtest.h>

#include <cstring>

#include "sim/controller_setup.h"
#include "sim/plant_model.h"

namespace sim {
namespace {

const PlantSpec& plant(const char* name) {
  const PlantSpec* p = find_plant(name);
  EXPECT_NE(p, nullptr) << name;
  return *p;
}

TEST(PlantModel, FopdtPlantsGiveTheirExactModel) {
  const HotendModelSetting m = hotend_model_for(plant("seed002"));
  EXPECT_NEAR(m.rise_k, 450.0, 1e-9);
  EXPECT_NEAR(m.time_constant_s, 24.0, 1e-9);
  EXPECT_NEAR(m.dead_time_s, 20.7, 1e-9);
  // The part fan raises every plant's loss as hotend40w's does: 0.097/0.068 − 1.
  EXPECT_NEAR(m.fan_loss_pct, (0.097 / 0.068 - 1.0) * 100.0, 1e-6);
  EXPECT_EQ(m307_command(m), "M307 A450 C24 D20.7 F42.647");
}

TEST(PlantModel, OtherPlantsGiveTheTwoPointFit) {
  const HotendModelSetting m = hotend_model_for(plant("hotend40w"));
  EXPECT_NEAR(m.rise_k, 40.0 / 0.068, 0.01);  // the fit's final value is the true DC gain
  EXPECT_GT(m.dead_time_s, 0.0);
  EXPECT_NEAR(m.fan_loss_pct, (0.097 / 0.068 - 1.0) * 100.0, 1e-6);
}

TEST(PlantModel, DesignModelCarriesTheFanLossAsHeaterDutyPerKelvin) {
  // Two-node hotend: (0.097 − 0.068) W/K of a 40 W heater.
  EXPECT_NEAR(design_model_for(plant("hotend40w")).fan_loss_per_k, 0.029 / 40.0, 1e-12);
  EXPECT_TRUE(design_model_for(plant("seed003")).physical_states);
  EXPECT_FALSE(design_model_for(plant("seed000-5")).physical_states);
}

TEST(PlantModel, M311UploadIsThirteenFieldLinesAndACommit) {
  const std::vector<std::string> lines = m311_commands(state_feedback_for(plant("seed004")).constants);
  ASSERT_EQ(lines.size(), 14u);
  EXPECT_EQ(lines.front().rfind("M311 I0 A1 ", 0), 0u);  // n = 1 state
  EXPECT_EQ(lines[12].rfind("M311 I96 ", 0), 0u);
  EXPECT_EQ(lines.back(), "M311 W1");
}

TEST(PublishedGains, LoopGainMatchedToThe450KPlants) {
  // Seed 004: Kp 4 on K = 0.233 → Kp·K = 0.932 = (Kp_M/255)·450.
  const auto s004 = published_gains(plant("seed004"));
  ASSERT_TRUE(s004);
  const MarlinGains g4 = marlin_gains_from_paper(*s004, 450.0);
  EXPECT_NEAR(g4.kp, 4.0 * 0.233 * 255.0 / 450.0, 1e-12);
  EXPECT_NEAR(g4.ki, 0.26 * 0.233 * 255.0 / 450.0, 1e-12);
  EXPECT_EQ(g4.kd, 0.0);  // published −19.6 cannot be sent
  // Seed 003, model (15): k = 2.847, kp 14.23, ki 0.671, kd 81.58.
  const MarlinGains g3 = marlin_gains_from_paper(*published_gains(plant("seed003")), 450.0);
  EXPECT_NEAR(g3.kp, 22.957, 1e-3);
  EXPECT_NEAR(g3.ki, 1.0825, 1e-4);
  EXPECT_NEAR(g3.kd, 131.61, 1e-2);
  EXPECT_FALSE(published_gains(plant("seed002")));  // the patent gives no PID gains
  EXPECT_FALSE(controller_applies("paper", plant("hotend40w")));
  EXPECT_TRUE(controller_applies("paper", plant("seed003")));
}

TEST(ControllerSetup, EachControllerSendsItsChoiceLast) {
  const PlantSpec& p = plant("seed004");
  const ControllerSetup pid = controller_setup("pid", p, 210.0);
  ASSERT_TRUE(pid.gains);
  // The model goes with F0 too (its part-fan term), as M303 U1 sets it for every controller.
  EXPECT_EQ(pid.gcode, (std::vector<std::string>{"M307 A450 C25.5 D19.5 F42.647", "M310 S0 F0"}));
  const ControllerSetup ff = controller_setup("pid+ff", p, 210.0);
  EXPECT_EQ(ff.gcode, (std::vector<std::string>{"M307 A450 C25.5 D19.5 F42.647", "M310 S0 F1"}));
  EXPECT_GT(ff.gains->kp, pid.gains->kp);  // SIMC τc = τ is tighter than the default τc = 2τ
  const ControllerSetup fuzzy = controller_setup("fuzzy+ff", p, 210.0);
  EXPECT_EQ(fuzzy.gcode.back(), "M310 S2 F1");
  EXPECT_EQ(fuzzy.gcode[1].rfind("M312 ", 0), 0u);
  EXPECT_EQ(controller_setup("marlin-zn", p, 210.0).gcode.size(), 1u);  // the baseline: no model
  const ControllerSetup sf = controller_setup("statefb", p, 210.0);
  EXPECT_FALSE(sf.gains);
  ASSERT_EQ(sf.gcode.size(), 15u);
  EXPECT_EQ(sf.gcode[13], "M311 W1");
  EXPECT_EQ(sf.gcode.back(), "M310 S1");
  EXPECT_EQ(controller_setup("marlin-zn", p, 210.0).gcode.back(), "M310 S3 F0");
  EXPECT_EQ(controller_setup("paper", plant("seed003"), 210.0).gcode.back(), "M310 S3 F0");
  EXPECT_THROW(controller_setup("bang-bang", p, 210.0), std::invalid_argument);
  EXPECT_THROW(controller_setup("paper", plant("seed002"), 210.0), std::invalid_argument);
}

}  // namespace
}  // namespace sim

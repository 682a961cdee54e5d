// firmware/controller_bank: M303's engine borrows the controllers' storage (issue 7's 2 KB of
// static RAM). What must hold: after the tune every controller steps exactly as one that was
// never lent out, settings loaded during the tune (M501, M502) are in force afterwards, and
// nothing the heater manager or the G-code layer calls meanwhile disturbs the engine.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "host_tests/controller_rig.h"
#include "host_tests/state_feedback_fixtures.h"

namespace {

using controller_test::load_cell;
using controller_test::Loop;
using firmware::ControllerBank;
using firmware::Settings;

constexpr firmware::HandOver kCold{25L * 256, 0, false};

Settings with(uint8_t controller, uint8_t feedforward) {
  Settings s = firmware::default_settings();
  s.controller = controller;
  s.feedforward = feedforward;
  return s;
}

void start(ControllerBank& bank, const Settings& s) {
  bank.init(firmware::default_settings());
  ASSERT_TRUE(bank.load_state_feedback(fixtures::hotend40w_constants(), kCold));
  ASSERT_EQ(bank.apply(s, kCold), nullptr);
}

// A tune's worth of engine activity in the shared storage: a heat-up on made-up readings.
void run_engine(control::Autotune& engine) {
  engine.configure(firmware::kControlPeriodMs);
  ASSERT_TRUE(engine.start(210L * 256, 5, true));
  for (int k = 0; k < 2000; ++k) engine.step(25L * 256 + k * 16);
}

// Both banks heat hotend40w from cold for 300 s; every duty must be the same.
void expect_same_duties(ControllerBank& a, ControllerBank& b, const char* what) {
  Loop la{a}, lb{b};
  for (int k = 0; k < 2344; ++k) {
    const uint16_t da = la.step(), db = lb.step();
    if (da != db) {
      ADD_FAILURE() << what << ": step " << k << " duty " << da << " vs " << db;
      return;
    }
  }
}

TEST(ControllerBankAutotune, AfterATuneEveryControllerStepsAsOneNeverLent) {
  for (uint8_t controller = 0; controller < firmware::kControllerCount; ++controller) {
    for (uint8_t ff = 0; ff <= 1; ++ff) {
      ControllerBank lent(load_cell), fresh(load_cell);
      start(lent, with(controller, ff));
      start(fresh, with(controller, ff));
      run_engine(lent.begin_autotune());
      EXPECT_TRUE(lent.autotuning());
      lent.end_autotune();
      EXPECT_FALSE(lent.autotuning());
      const std::string what = "S" + std::to_string(controller) + " F" + std::to_string(ff);
      expect_same_duties(lent, fresh, what.c_str());
    }
  }
}

TEST(ControllerBankAutotune, SettingsLoadedDuringATuneAreInForceAfterIt) {
  ControllerBank lent(load_cell), fresh(load_cell);
  start(lent, with(0, 0));
  Settings next = with(2, 1);  // what an M501 might bring: fuzzy-PID, other gains and spread
  next.pid.kp_q16 = 12L << 16;
  next.fuzzy_spread_pct = 30;
  start(fresh, next);
  control::Autotune& engine = lent.begin_autotune();
  run_engine(engine);
  EXPECT_EQ(lent.replace_all(next, &fixtures::hotend40w_constants(), kCold), nullptr);
  EXPECT_EQ(lent.settings().controller, 2);
  lent.end_autotune();
  expect_same_duties(lent, fresh, "M501 during the tune");
}

TEST(ControllerBankAutotune, WhatTheLoopCallsDuringATuneLeavesTheEngineAlone) {
  ControllerBank bank(load_cell);
  start(bank, with(1, 1));
  control::Autotune& engine = bank.begin_autotune();
  run_engine(engine);
  unsigned char before[sizeof(control::Autotune)];
  std::memcpy(before, &engine, sizeof before);
  // The heater manager (a fault's switch-off, a step), the machine (feedforward for M104 S0 or
  // M106) and the settings commands the machine does not refuse (M501, M502).
  bank.reset();
  bank.init_bumpless(200L * 256, 30000);
  EXPECT_EQ(bank.step({210L * 256, 200L * 256, 0}), 0);
  bank.prepare_feedforward(0);
  EXPECT_EQ(bank.replace_all(firmware::default_settings(), nullptr, {200L * 256, 30000, true}), nullptr);
  EXPECT_EQ(std::memcmp(before, &engine, sizeof before), 0);
  bank.end_autotune();
}

TEST(ControllerBankAutotune, M311StagingIsRefusedDuringATuneAndRefilledAfter) {
  controller_test::Rig rig;
  firmware::ControllerBank& bank = rig.machine.bank;
  ASSERT_TRUE(bank.load_state_feedback(fixtures::hotend40w_constants(), kCold));
  rig.machine.commands.sync_staging();
  rig.send("M311 I0 A1\n");  // a half-done upload: the tune discards it, as it always has
  run_engine(bank.begin_autotune());
  const std::string busy = std::string("Error:") + gcode_test::text_of(firmware::autotune_busy_text()) + "\nok\n";
  EXPECT_EQ(rig.send("M311 I0 A1\n"), busy);
  rig.machine.commands.sync_staging();  // (what the machine does after M501/M502) changes nothing now
  bank.end_autotune();
  // The staging copy is the loaded constants again: W1 alone commits them unchanged.
  EXPECT_EQ(rig.send("M311 W1\n"), "ok\n");
  EXPECT_EQ(std::memcmp(&bank.state_feedback_constants(), &fixtures::hotend40w_constants(),
                        sizeof(control::StateFeedbackConstants)),
            0);
}

}  // namespace

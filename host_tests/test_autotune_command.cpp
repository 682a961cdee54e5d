// M303 through the real G-code layer and the real AutotuneJob + ControllerBank, on a simulated
// FOPDT hotend (design/plant_sim.h): Marlin's wording, refusals while tuning, aborts, and what
// U1 / U0 do to the settings. The machine below does for M303 what firmware/hotend_machine.cpp
// does (target while tuning, refusals, report at the end) and nothing for the hardware.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "design/lti_model.h"
#include "design/plant_sim.h"
#include "design/seed_models.h"
#include "control/state_feedback_autodesign.h"
#include "control/state_feedback_gcode.h"
#include "firmware/controller_autotune.h"
#include "host_tests/controller_rig.h"

namespace {

const char kBusyText[] = "Autotune running (M303): refused; M108 or M104 S0 aborts it";
const gcode::FlashText* const kBusy = reinterpret_cast<const gcode::FlashText*>(kBusyText);

class TuneMachine final : public gcode::Machine {
 public:
  TuneMachine() {
    bank.init(firmware::default_settings());
    commands.sync_staging();
  }
  gcode::HeaterStatus heater_status() override { return {measured_q8, target_q8, duty_q16, fault}; }
  int32_t max_target_q8() override { return 275L * 256; }
  const gcode::FlashText* set_target_q8(int32_t t) override {
    if (job.busy()) {
      if (t != 0) return kBusy;
      job.stop(firmware::AutotuneJob::Stop::kUser);
    }
    target_q8 = t;
    return nullptr;
  }
  gcode::PidGainsQ16 pid_gains() override {
    const control::PidGains& g = bank.settings().pid;
    return {g.kp_q16, g.ki_q16, g.kd_q16};
  }
  const gcode::FlashText* set_pid_gains(const gcode::PidGainsQ16& g) override {
    if (job.busy()) return kBusy;
    firmware::Settings next = bank.settings();
    next.pid = control::PidGains{g.kp_q16, g.ki_q16, g.kd_q16};
    return bank.apply(next, {measured_q8, 0, false});
  }
  void set_fan_duty(uint8_t d) override { fan = d; }
  void emergency_stop() override {
    fault = true;
    target_q8 = 0;
    job.stop(firmware::AutotuneJob::Stop::kUser);
  }
  const gcode::FlashText* clear_fault() override { return nullptr; }
  const gcode::FlashText* save_settings() override { return nullptr; }
  const gcode::FlashText* load_settings() override { return nullptr; }
  void reset_settings() override {}
  const gcode::FlashText* firmware_version() override { return GCODE_TEXT("test"); }
  const gcode::FlashText* machine_type() override { return GCODE_TEXT("test"); }
  void hang_for_watchdog() override {}
  bool handle_command(const gcode::Command& cmd, gcode::Output& out) override {
    if (cmd.letter == 'M' && cmd.code == 303) {
      const gcode::FlashText* refusal =
          fault ? GCODE_TEXT("PID Autotune failed! Heater fault latched, send M999 to clear") : (job.busy() ? kBusy : nullptr);
      if (job.begin(cmd, out, refusal, fan, 0)) target_q8 = job.target_q8();
      return true;
    }
    if (job.busy() && cmd.letter == 'M' && cmd.code >= 307 && cmd.code <= 312 && *cmd.params != '\0') {
      out.error_line(kBusy);
      return true;
    }
    return commands.handle(cmd, out, {measured_q8, 0, false});
  }
  void report_settings(gcode::Output& out) override { commands.report(out); }
  void background(gcode::Output& out) override {
    if (job.busy() && job.report(out, {measured_q8, 0, false})) {
      target_q8 = 0;
      commands.sync_staging();
    }
  }
  void cancel_heating() override { job.stop(firmware::AutotuneJob::Stop::kUser); }

  firmware::ControllerBank bank{controller_test::load_cell};
  firmware::ControllerCommands commands{bank};
  firmware::AutotuneJob job{bank};
  int32_t measured_q8 = 25L * 256, target_q8 = 0;
  uint16_t duty_q16 = 0;
  uint8_t fan = 0;
  bool fault = false;
};

struct TuneRig {
  explicit TuneRig(const design::LtiModel& model) : plant(model) { plant.set_noise(0.05); }
  TuneMachine machine;
  gcode_test::StringOutput out;
  gcode::Interpreter gcode{machine, out};
  gcode::EmergencyParser emergency;
  design::PlantSim plant;
  double max_c = 0;

  std::string send(const std::string& text) {
    gcode_test::feed_like_firmware(emergency, gcode, text);
    return out.take();
  }
  // One 128 ms control period as firmware/control_loop.cpp runs it, then the main loop's poll.
  void period() {
    machine.measured_q8 = static_cast<int32_t>(std::lround(plant.measured_c() * 256.0));
    uint8_t fan = machine.fan;
    machine.duty_q16 = machine.job.busy() ? machine.job.step(machine.measured_q8, &fan) : 0;
    plant.set_fan(fan / 255.0);
    plant.run(machine.duty_q16 / 65535.0, 0.128);
    max_c = std::fmax(max_c, plant.true_c());
    gcode.poll(static_cast<uint32_t>(plant.time_s() * 1000.0));
  }
  // Until the job has ended (or `limit_s`); returns everything printed meanwhile.
  std::string run_tune(double limit_s = 3600) {
    std::string text;
    while (machine.job.busy() && plant.time_s() < limit_s) {
      period();
      text += out.take();
    }
    return text;
  }
};

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

design::LtiModel fast_fopdt() { return design::with_seed_fan(design::fopdt(450, 60, 3)); }

TEST(AutotuneCommand, BadParametersAreRefusedAndStartNothing) {
  TuneRig rig(fast_fopdt());
  EXPECT_TRUE(has(rig.send("M303 E-1 S210\n"), "Error:PID Autotune failed! E-1: this firmware has no bed heater"));
  EXPECT_TRUE(has(rig.send("M303 E1\n"), "Error:PID Autotune failed! Bad extruder number"));
  EXPECT_TRUE(has(rig.send("M303 S300\n"), "Error:M303 S out of range"));
  EXPECT_TRUE(has(rig.send("M303 S40\n"), "Error:M303 S out of range"));
  EXPECT_TRUE(has(rig.send("M303 C2\n"), "Error:M303 C must be an integer in 3..20"));
  EXPECT_TRUE(has(rig.send("M303 C21\n"), "Error:M303 C must be an integer in 3..20"));
  EXPECT_TRUE(has(rig.send("M303 U2\n"), "Error:M303 U must be an integer in 0..1"));
  EXPECT_TRUE(has(rig.send("M303 F1.5\n"), "Error:M303 F must be an integer in 0..1"));
  EXPECT_TRUE(has(rig.send("M303 SX\n"), "Error:"));
  EXPECT_FALSE(rig.machine.job.busy());
  EXPECT_EQ(rig.machine.target_q8, 0);
}

TEST(AutotuneCommand, RefusedWhileAFaultIsLatched) {
  TuneRig rig(fast_fopdt());
  rig.machine.fault = true;
  EXPECT_EQ(rig.send("M303 E0 S210 U1\n"), "Error:PID Autotune failed! Heater fault latched, send M999 to clear\nok\n");
  EXPECT_FALSE(rig.machine.job.busy());
}

TEST(AutotuneCommand, WhileTuningTargetAndControllerChangesAreRefusedReportsStillWork) {
  TuneRig rig(fast_fopdt());
  const firmware::Settings before = rig.machine.bank.settings();
  EXPECT_EQ(rig.send("M303 E0 S210 C3 U1\n"), "PID Autotune start\nok\n");
  EXPECT_EQ(rig.machine.target_q8, 210L * 256);
  for (int i = 0; i < 200; ++i) rig.period();
  rig.out.take();
  const std::string busy = std::string("Error:") + gcode_test::text_of(kBusy) + "\nok\n";
  EXPECT_EQ(rig.send("M104 S200\n"), busy);
  EXPECT_EQ(rig.send("M109 S200\n"), busy);
  EXPECT_EQ(rig.send("M303 E0 S200\n"), busy);
  EXPECT_EQ(rig.send("M301 P10\n"), busy);
  EXPECT_EQ(rig.send("M307 A400 C100 D5 F40\n"), busy);
  EXPECT_EQ(rig.send("M310 S2\n"), busy);
  EXPECT_TRUE(has(rig.send("M105\n"), "ok T:"));                     // reports go on
  EXPECT_TRUE(has(rig.send("M307\n"), "M307 A"));                    // a bare report is fine
  EXPECT_EQ(rig.machine.bank.settings().pid.kp_q16, before.pid.kp_q16);
  EXPECT_TRUE(rig.machine.job.running());
  EXPECT_GT(rig.machine.duty_q16, 0);
}

// The reading noise the tune measured is reported; above 0.3 °C, with a hint where to look (a
// noisy thermistor costs the model accuracy: docs/autotune.md, "Noisy sensors").
TEST(AutotuneCommand, ReportsTheReadingNoiseAndCallsANoisySensorOut) {
  TuneRig rig(fast_fopdt());
  rig.plant.set_noise(0.5);
  EXPECT_EQ(rig.send("M303 E0 S210 C3 U0\n"), "PID Autotune start\nok\n");
  const std::string text = rig.run_tune();
  SCOPED_TRACE(text);
  const size_t at = text.find("echo:Autotune reading noise ");
  ASSERT_NE(at, std::string::npos);
  const double sigma = std::atof(text.c_str() + at + 28);
  EXPECT_NEAR(sigma, 0.5, 0.1);  // the estimator reads σ 0.5 about 9 % low
  EXPECT_TRUE(has(text, " C (sigma): noisy, check the thermistor and its wiring\n"));
  EXPECT_TRUE(has(text, "PID Autotune finished!"));
}

TEST(AutotuneCommand, U1FinishesInMarlinsWordsAndAppliesModelGainsAndController) {
  TuneRig rig(fast_fopdt());
  rig.machine.fan = 77;  // the user's fan comes back afterwards
  EXPECT_EQ(rig.send("M303 E0 S210 C3 U1\n"), "PID Autotune start\nok\n");
  const std::string text = rig.run_tune();
  SCOPED_TRACE(text);
  EXPECT_TRUE(has(text, " bias: "));
  EXPECT_TRUE(has(text, " d: "));
  EXPECT_TRUE(has(text, " min: "));
  EXPECT_TRUE(has(text, " Ku: "));
  EXPECT_TRUE(has(text, " Tu: "));
  EXPECT_TRUE(has(text, " Kp: "));
  EXPECT_TRUE(has(text, "PID Autotune finished! Put the last Kp, Ki and Kd constants from below into Configuration.h\n"));
  EXPECT_TRUE(has(text, "#define DEFAULT_Kp "));
  EXPECT_TRUE(has(text, "#define DEFAULT_Ki "));
  EXPECT_TRUE(has(text, "#define DEFAULT_Kd "));
  EXPECT_TRUE(has(text, "echo:Autotune model (cold start"));
  EXPECT_TRUE(has(text, "echo:Autotune reading noise 0.0"));  // the rig's σ 0.05 °C
  EXPECT_TRUE(has(text, " C (sigma)\n"));
  EXPECT_FALSE(has(text, "noisy"));
  EXPECT_TRUE(has(text, "echo:Autotune applied (U1)"));
  EXPECT_FALSE(has(text, "Error:"));
  EXPECT_LE(rig.max_c, 215.0);
  EXPECT_EQ(rig.machine.target_q8, 0);  // heater off at the end, as Marlin does
  // A hotend whose dead time is short against its time constant: state feedback, designed on
  // the board, becomes the controller (and its constants what M311 would edit).
  const firmware::Settings& s = rig.machine.bank.settings();
  EXPECT_EQ(s.controller, static_cast<uint8_t>(firmware::ControllerId::kStateFeedback));
  EXPECT_TRUE(rig.machine.bank.state_feedback_loaded());
  EXPECT_TRUE(has(text, "echo:Autotune state feedback designed: law every "));
  EXPECT_TRUE(has(text, "echo:Autotune applied (U1): M310 S1 (state feedback), M307 A"));
  EXPECT_EQ(s.feedforward, 1);
  // The applied model is the plant's (the engine's accuracy is asserted in test_autotune.cpp;
  // here: a model of this plant, not the defaults), and it is the one the report printed.
  EXPECT_NEAR(s.model.rise_q8 / 256.0, 450.0, 45.0);
  EXPECT_NEAR(s.model.time_constant_q8 / 256.0, 60.0, 12.0);
  gcode_test::StringOutput printed;
  firmware::write_m307(printed, s.model);
  EXPECT_TRUE(has(text, printed.text)) << printed.text;
  // M503 shows the applied model and gains.
  const std::string m503 = rig.send("M503\n");
  EXPECT_TRUE(has(m503, "M310 S1"));
  EXPECT_TRUE(has(m503, "M311 I0 A1 "));  // the board's constants, one state
  // They are the on-board design of the applied model, field for field.
  control::StateFeedbackConstants expected;
  ASSERT_TRUE(control::design_state_feedback_fopdt(s.model, 128, &expected));
  std::string expected_lines;
  control::write_state_feedback_mcode(expected, [&](const char* line) {
    if (std::string(line) != "M311 W1") expected_lines += std::string("echo:  ") + line + "\n";
  });
  EXPECT_TRUE(has(m503, expected_lines)) << m503 << "\nwanted\n" << expected_lines;
  // Replaying the printed M301 line gives the same gains: the report is exact enough to type in.
  const std::size_t at = text.find("M301 P");
  ASSERT_NE(at, std::string::npos);
  const std::string m301 = text.substr(at, text.find('\n', at) - at);
  const control::PidGains applied = s.pid;
  rig.send(m301 + "\n");
  EXPECT_NEAR(rig.machine.bank.settings().pid.kp_q16, applied.kp_q16, 400);  // 2 decimals printed
}

// A hotend whose thermistor lags the block a little (80 W two-node: lag ≈ 4.5 s, C ≈ 250 s): the
// tune folds the lag into D, and U1 loads the two-lag state feedback on C and that D (the paced
// one-state law overshot it by 1.4–1.7 °C; host rig, test_autotune_after_u1.cpp).
TEST(AutotuneCommand, ASmallThermistorLagGetsTheTwoLagStateFeedback) {
  design::TwoNodeParams p80;
  p80.heater_w = 80;
  TuneRig rig(design::two_node(p80));
  rig.send("M303 E0 S210 C3 U1\n");
  const std::string text = rig.run_tune();
  const firmware::Settings& s = rig.machine.bank.settings();
  // The applied line names the lags exactly: here M307's C and D.
  const std::string applied = "echo:Autotune applied (U1): M310 S1 (state feedback, two lags ";
  const std::size_t at = text.find(applied);
  ASSERT_NE(at, std::string::npos) << text;
  double lag1 = 0, lag2 = 0;
  ASSERT_EQ(std::sscanf(text.c_str() + at + applied.size(), "%lf s and %lf s, pace 0.4), M307 A", &lag1, &lag2), 2) << text;
  EXPECT_NE(text.find(" s, pace 0.4), M307 A"), std::string::npos) << text;  // a lag the relay confirmed
  EXPECT_EQ(std::lround(lag1 * 256), s.model.time_constant_q8);
  EXPECT_EQ(std::lround(lag2 * 256), s.model.dead_time_q8);
  control::StateFeedbackConstants two_lags;
  ASSERT_TRUE(control::design_state_feedback_two_lags(s.model, 128, &two_lags, control::kLagPaceConfirmed));
  EXPECT_EQ(two_lags.n, 2);
  EXPECT_EQ(std::memcmp(&rig.machine.bank.state_feedback_constants(), &two_lags, sizeof two_lags), 0);
}

TEST(AutotuneCommand, DeadTimeDominatedHotendsGetThePidFollowingTheModel) {
  TuneRig rig(design::seed002());  // dead time 20.7 s, time constant 24 s
  rig.send("M303 E0 S210 C3 U1\n");
  const std::string text = rig.run_tune();
  EXPECT_TRUE(has(text, "echo:Autotune applied (U1): M310 S0 F1 (PID following the model's heat-up)")) << text;
  EXPECT_EQ(rig.machine.bank.settings().controller, static_cast<uint8_t>(firmware::ControllerId::kPid));
  EXPECT_LE(rig.max_c, 215.0);
}

TEST(AutotuneCommand, U0ReportsButChangesNothing) {
  TuneRig rig(fast_fopdt());
  const firmware::Settings before = rig.machine.bank.settings();
  rig.send("M303 E0 S210 C3 U0 F0\n");
  const std::string text = rig.run_tune();
  EXPECT_TRUE(has(text, "PID Autotune finished!")) << text;
  EXPECT_TRUE(has(text, "echo:Autotune not applied (U0)")) << text;
  const firmware::Settings& s = rig.machine.bank.settings();
  EXPECT_EQ(s.pid.kp_q16, before.pid.kp_q16);
  EXPECT_EQ(s.model.rise_q8, before.model.rise_q8);
  EXPECT_EQ(s.controller, before.controller);
  EXPECT_EQ(s.feedforward, before.feedforward);
}

TEST(AutotuneCommand, M108AbortsWithTheHeaterOff) {
  TuneRig rig(fast_fopdt());
  rig.send("M303 E0 S210 U1\n");
  for (int i = 0; i < 300; ++i) rig.period();
  rig.out.take();
  rig.send("M108\n");
  const std::string text = rig.run_tune();
  EXPECT_TRUE(has(text, "PID Autotune failed! Aborted by the host, heater off")) << text;
  EXPECT_EQ(rig.machine.duty_q16, 0);
  EXPECT_EQ(rig.machine.target_q8, 0);
  EXPECT_FALSE(rig.machine.job.busy());
  EXPECT_EQ(rig.send("M104 S200\n"), "ok\n");  // heating works again afterwards
}

TEST(AutotuneCommand, M104S0AndM112AbortToo) {
  for (const char* stop : {"M104 S0\n", "M112\n"}) {
    TuneRig rig(fast_fopdt());
    rig.send("M303 E0 S210 U1\n");
    for (int i = 0; i < 300; ++i) rig.period();
    rig.send(stop);
    const std::string text = rig.run_tune();
    EXPECT_TRUE(has(text, "PID Autotune failed!")) << stop << text;
    EXPECT_EQ(rig.machine.duty_q16, 0) << stop;
    EXPECT_FALSE(rig.machine.job.busy()) << stop;
  }
}

TEST(AutotuneCommand, AHeaterThatDoesNotHeatFailsClearly) {
  design::LtiModel dead = fast_fopdt();
  TuneRig rig(dead);
  rig.plant.set_gain_error(0.0);  // heater disconnected
  rig.send("M303 E0 S210 U1\n");
  const std::string text = rig.run_tune();
  EXPECT_TRUE(has(text, "PID Autotune failed! ")) << text;
  EXPECT_FALSE(has(text, "finished")) << text;
  EXPECT_EQ(rig.machine.bank.settings().controller, firmware::default_settings().controller);
}

}  // namespace

namespace {

// How far U1 trusts the model it applies (Settings::model_tuned): tight where nothing speaks
// against it; lag-dominated for a lag above C/20 (the model check's FOPDT bounds would trip, but a
// heat-up may follow it: fuzzy-PID F0 does); loose after a hot start or an unsure tune, whose C
// may be read long (neither the tight check nor the model heat-up of fuzzy-PID F0); fitted lags
// after an unsure tune whose record fit two lags (fuzzy-PID F0 and PID F0 follow its heat-up).
TEST(AutotuneCommand, U1MarksHowFarTheModelIsTrusted) {
  control::AutotuneResult r{};
  r.model = control::HotendModel{450 * 256, 200 * 256, 10 * 256, 43 * 256};
  r.sensor_lag_q8 = 10 * 256;  // = C/20
  EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelMeasured);
  r.sensor_lag_q8 = 10 * 256 + 1;
  EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelMeasuredLag);
  r.hot_start = true;
  EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelMeasuredLoose);
  r.hot_start = false;
  r.sensor_lag_q8 = 0;
  r.unsure = true;
  EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelMeasuredLoose);
  // ...unless its record fit two lags (seed000): M307 is their two-point FOPDT.
  r.first_lag_q8 = 526 * 256;
  r.second_lag_q8 = 194 * 256;
  EXPECT_EQ(firmware::tuned_model_source(r), firmware::kModelFittedLags);
}

}  // namespace

// The issue-3 M-codes (M307, M310, M311, M312) through the real G-code layer: reports, strict
// validation (Error line, nothing changes), the state-feedback upload, and M503's lines
// re-sent to a fresh firmware reproducing the same settings.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "control/state_feedback_gcode.h"
#include "host_tests/state_feedback_fixtures.h"
#include "host_tests/controller_rig.h"

namespace {

using controller_test::Rig;
using controller_test::settings_lines;
using firmware::ControllerId;

constexpr const char* kW1Refused =
    "Error:M311 W1: constants invalid (ranges, or a product beyond 32 bits), nothing applied\nok\n";

std::string upload_of(const control::StateFeedbackConstants& k) {
  std::string text;
  control::write_state_feedback_mcode(k, [&](const char* line) { text += std::string(line) + "\n"; });
  return text;
}

TEST(ControllerCommands, BareFormsReportTheDefaults) {
  Rig rig;
  EXPECT_EQ(rig.send("M307\n"), "echo:M307 A588.234 C245.59 D4.547 F42.65\nok\n");  // exact Q8
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S0 F0 ; PID\nok\n");
  EXPECT_EQ(rig.send("M312\n"), "echo:M312 S50 E0.40 C0.60\nok\n");
  EXPECT_EQ(rig.send("M311\n"), "echo:M311 ; no state-feedback constants loaded\nok\n");
}

TEST(ControllerCommands, M307SetsAnySubsetAndRefusesOutOfRange) {
  Rig rig;
  EXPECT_EQ(rig.send("M307 A450 D20.7\n"), "ok\n");
  EXPECT_EQ(rig.send("M307\n"), "echo:M307 A450.00 C245.59 D20.70 F42.65\nok\n");
  EXPECT_EQ(rig.send("M307 A9.99\n"), "Error:M307 A out of range 10..2000\nok\n");
  EXPECT_EQ(rig.send("M307 C400 F501\n"), "Error:M307 F out of range 0..500\nok\n");  // C not applied either
  EXPECT_EQ(rig.send("M307 D1x\n"), "Error:M307: malformed parameter \"D1x\"\nok\n");
  EXPECT_EQ(rig.send("M307\n"), "echo:M307 A450.00 C245.59 D20.70 F42.65\nok\n");
}

TEST(ControllerCommands, M310SelectsAndRefusesStateFeedbackWithoutConstants) {
  Rig rig;
  EXPECT_EQ(rig.send("M310 S2 F1\n"), "ok\n");
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S2 F1 ; fuzzy-PID\nok\n");
  EXPECT_EQ(rig.send("M310 S3\n"), "ok\n");
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S3 F1 ; Marlin PID\nok\n");
  EXPECT_EQ(rig.send("M310 S1\n"), "Error:M310 S1 needs state-feedback constants (M311 ... W1)\nok\n");
  EXPECT_EQ(rig.send("M310 S4\n"), "Error:M310 S must be an integer in 0..3\nok\n");
  EXPECT_EQ(rig.send("M310 F2\n"), "Error:M310 F must be an integer in 0..1\nok\n");
  EXPECT_EQ(rig.send("M310 S0.5\n"), "Error:M310 S must be an integer in 0..3\nok\n");
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S3 F1 ; Marlin PID\nok\n");
  EXPECT_EQ(rig.machine.bank.active_id(), ControllerId::kMarlinPid);
}

TEST(ControllerCommands, M311UploadsCommitsAndReportsTheConstants) {
  Rig rig;
  const std::string upload = upload_of(fixtures::seed004_constants());
  std::istringstream lines(upload);
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(rig.send(line + "\n"), "ok\n") << line;
    ++count;
  }
  EXPECT_EQ(count, 14);
  EXPECT_TRUE(rig.machine.bank.state_feedback_loaded());
  EXPECT_EQ(rig.send("M310 S1\n"), "ok\n");
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S1 F0 ; state feedback\nok\n");
  // Bare M311 prints the canonical upload of what is loaded.
  std::string echoed;
  std::istringstream again(upload);
  while (std::getline(again, line)) echoed += "echo:" + line + "\n";
  EXPECT_EQ(rig.send("M311\n"), echoed + "ok\n");
  // One field edited and committed: the staging copy started as the loaded constants.
  EXPECT_EQ(rig.send("M311 I53 A" + std::to_string(fixtures::seed004_constants().ff_gain + 1) + " W1\n"), "ok\n");
  EXPECT_EQ(rig.machine.bank.state_feedback_constants().ff_gain, fixtures::seed004_constants().ff_gain + 1);
  EXPECT_EQ(rig.machine.bank.state_feedback_constants().fir[3], fixtures::seed004_constants().fir[3]);
}

TEST(ControllerCommands, M311RejectsBadLinesWhole) {
  Rig rig;
  EXPECT_EQ(rig.send("M311 A1\n"), "Error:M311: missing I\nok\n");
  EXPECT_EQ(rig.send("M311 I0 A1 B256\n"), "Error:M311 B must be an integer in 0..255\nok\n");  // A not written
  EXPECT_EQ(rig.send("M311 I6 A-32769\n"), "Error:M311 A must be an integer in -32768..32767\nok\n");
  EXPECT_EQ(rig.send("M311 I96 D1\n"), "Error:M311 D: field index beyond 98\nok\n");
  EXPECT_EQ(rig.send("M311 I99 A1\n"), "Error:M311 I must be an integer in 0..98\nok\n");
  EXPECT_EQ(rig.send("M311 W2\n"), "Error:M311 W must be an integer in 1..1\nok\n");
  // Nothing was staged: committing the all-zero staging copy fails its checks (n = 0).
  EXPECT_EQ(rig.send("M311 W1\n"), std::string(kW1Refused));
  EXPECT_FALSE(rig.machine.bank.state_feedback_loaded());
}

// Issue 8, defect 4: a refused "M311 ... W1" left its fields staged, and a later W1 committed
// them. Here the refused line sets a valid ambient together with n = 0; the later W1 must
// commit the loaded constants as they were.
TEST(ControllerCommands, RefusedM311W1LeavesNothingStaged) {
  Rig rig;
  const control::StateFeedbackConstants k = fixtures::hotend40w_constants();
  rig.send(upload_of(k));
  ASSERT_TRUE(rig.machine.bank.state_feedback_loaded());
  EXPECT_EQ(rig.send("M311 I0 A0 F7680 W1\n"), std::string(kW1Refused));  // n = 0, ambient 30 °C
  EXPECT_EQ(rig.send("M311 W1\n"), "ok\n");
  EXPECT_EQ(rig.machine.bank.state_feedback_constants().ambient_q8, k.ambient_q8);
  EXPECT_EQ(rig.machine.bank.state_feedback_constants().n, k.n);
}

// Issue 8, defect 3: constants whose observer time update overflows int32 (row coefficients
// |Φ−I| + |Γ| above 8) were accepted and, on the AVR, heated to MAXTEMP. Now W1 refuses
// them and the loaded constants stay.
TEST(ControllerCommands, M311W1RefusesConstantsThatOverflowTheLaw) {
  Rig rig;
  const control::StateFeedbackConstants k = fixtures::hotend40w_constants();
  rig.send(upload_of(k));
  control::StateFeedbackConstants wild = k;
  wild.phi_diag[0] = 32767;
  wild.phi_shift[0] = 11;  // Φ−I = 16: x̂ + delta passes 2^31
  EXPECT_FALSE(control::state_feedback_constants_valid(wild));
  std::string upload = upload_of(wild);
  std::string replies = rig.send(upload);
  EXPECT_NE(replies.find("Error:M311 W1: constants invalid"), std::string::npos) << replies;
  EXPECT_EQ(rig.machine.bank.state_feedback_constants().phi_diag[0], k.phi_diag[0]);
  wild.phi_shift[0] = 16;  // Φ−I = 0.5 with the same mantissa: accepted (the law runs)
  EXPECT_TRUE(control::state_feedback_constants_valid(wild));
  EXPECT_EQ(rig.send(upload_of(wild)).find("Error"), std::string::npos);
}

// The ambient M311 accepts is what W1 and the EEPROM loader accept.
TEST(ControllerCommands, AmbientLimitsAreTheUploadLimits) {
  control::StateFeedbackConstants k = fixtures::hotend40w_constants();
  k.ambient_q8 = control::kSfMaxAmbientQ8;
  EXPECT_TRUE(control::state_feedback_constants_valid(k));
  k.ambient_q8 = control::kSfMaxAmbientQ8 + 1;
  EXPECT_FALSE(control::state_feedback_constants_valid(k));
  k.ambient_q8 = control::kSfMinAmbientQ8 - 1;
  EXPECT_FALSE(control::state_feedback_constants_valid(k));
}

TEST(ControllerCommands, M312SetsTheFuzzyScheduleAndReportsRoundTrippingFactors) {
  Rig rig;
  EXPECT_EQ(rig.send("M312 S30 E0.5 C0.25\n"), "ok\n");
  EXPECT_EQ(rig.send("M312\n"), "echo:M312 S30 E0.50 C0.25\nok\n");
  EXPECT_EQ(rig.send("M312 E0.1234\n"), "ok\n");  // Q12: 505/4096 prints with 4 decimals
  EXPECT_EQ(rig.send("M312\n"), "echo:M312 S30 E0.1233 C0.25\nok\n");
  EXPECT_EQ(rig.send("M312 E0.1233\n"), "ok\n");
  EXPECT_EQ(rig.send("M312\n"), "echo:M312 S30 E0.1233 C0.25\nok\n");
  EXPECT_EQ(rig.send("M312 S101\n"), "Error:M312 S must be an integer in 0..100\nok\n");
  EXPECT_EQ(rig.send("M312 E0.02\n"), "Error:M312 E out of range 0.03..15.99\nok\n");
  EXPECT_EQ(rig.send("M312 C2.1\n"), "Error:M312 C out of range 0.01..2.04\nok\n");
  EXPECT_EQ(rig.send("M312\n"), "echo:M312 S30 E0.1233 C0.25\nok\n");
}

TEST(ControllerCommands, M301RefusesGainsTheFuzzyScheduleCannotHold) {
  Rig rig;
  EXPECT_EQ(rig.send("M301 P900\n"),
            "Error:fuzzy-PID schedule (M301 x (1 + M312 S/100)) beyond what the fixed-point PID holds\nok\n");
  EXPECT_EQ(rig.send("M312 S10\n"), "ok\n");
  EXPECT_EQ(rig.send("M301 P900\n"), "echo: p:900.00 i:1.00 d:100.00\nok\n");
}

TEST(ControllerCommands, M503LinesRestoreEverySettingOnAFreshFirmware) {
  Rig rig;
  rig.send(upload_of(fixtures::hotend40w_constants()));
  rig.send("M301 P20 I0.5 D80\nM307 A500 C200 D6 F30\nM312 S40 E0.3 C0.7\nM310 S1 F1\n");
  rig.send("M570 T4 U20 P90\n");
  const std::vector<std::string> lines = settings_lines(rig);
  ASSERT_EQ(lines.size(), 1u + 1 + 14 + 1 + 1 + 1);  // M307, M312, M311 × 13 + W1, M310, M570, M301
  EXPECT_EQ(lines[lines.size() - 3], "M310 S1 F1 ; state feedback");
  EXPECT_EQ(lines[lines.size() - 2], "M570 T4 U20 P90 S1 ; model check: T (measured model)");
  EXPECT_EQ(lines.back().substr(0, 5), "M301 ");
  Rig fresh;
  for (const std::string& line : lines) EXPECT_EQ(fresh.send(line + "\n").substr(0, 5) == "Error", false) << line;
  EXPECT_EQ(settings_lines(fresh), lines);
  EXPECT_EQ(fresh.machine.bank.active_id(), ControllerId::kStateFeedback);
}

// Issue 8, defect 6: M503 printed M301 before M312, so gains stored with a small fuzzy spread
// were refused when replayed after M502 (the default 50 % spread). Each line must be accepted
// and M503 must read the same afterwards.
TEST(ControllerCommands, M503ReplaysAfterM502) {
  Rig rig;
  rig.send(upload_of(fixtures::hotend40w_constants()));
  EXPECT_EQ(rig.send("M312 S10 E0.3\n"), "ok\n");
  EXPECT_EQ(rig.send("M301 P900 I2 D150\n"), "echo: p:900.00 i:2.00 d:150.00\nok\n");
  EXPECT_EQ(rig.send("M307 A500 C200 D6 F30\nM310 S1 F1\n"), "ok\nok\n");
  const std::vector<std::string> before = settings_lines(rig);
  EXPECT_EQ(rig.send("M502\n").find("Error"), std::string::npos);
  EXPECT_FALSE(rig.machine.bank.state_feedback_loaded());
  for (const std::string& line : before) {
    const std::string reply = rig.send(line + "\n");
    EXPECT_EQ(reply.find("Error"), std::string::npos) << line << " -> " << reply;
  }
  EXPECT_EQ(settings_lines(rig), before);
}

// The M312-first order replays after M502 for any stored spread: the default gains hold every
// spread M312 accepts.
TEST(ControllerCommands, DefaultGainsHoldEveryFuzzySpread) {
  for (int spread = 0; spread <= firmware::kMaxFuzzySpreadPct; ++spread) {
    firmware::Settings s = firmware::default_settings();
    s.fuzzy_spread_pct = static_cast<uint8_t>(spread);
    for (int32_t e : {firmware::kMinEFactorQ12, firmware::kMaxEFactorQ12})
      for (int32_t c : {firmware::kMinEcFactorQ12, firmware::kMaxEcFactorQ12}) {
        s.fuzzy_e_factor_q12 = static_cast<uint16_t>(e);
        s.fuzzy_ec_factor_q12 = static_cast<uint16_t>(c);
        EXPECT_TRUE(control::FuzzyPid::valid(firmware::fuzzy_config(s), firmware::kControlPeriodMs)) << spread;
      }
  }
}

TEST(ControllerCommands, M502ForgetsTheUploadAndFallsBackToTheDefaultController) {
  Rig rig;
  rig.send(upload_of(fixtures::hotend40w_constants()));
  EXPECT_EQ(rig.send("M310 S1\n"), "ok\n");
  rig.send("M502\n");
  EXPECT_FALSE(rig.machine.bank.state_feedback_loaded());
  EXPECT_EQ(rig.send("M310\n"), "echo:M310 S0 F0 ; PID\nok\n");
  EXPECT_EQ(rig.send("M311\n"), "echo:M311 ; no state-feedback constants loaded\nok\n");
}

// Issue 8: M570 sets the protection's thresholds, all or nothing; bare, it reports them and
// whether the model check runs on a tuned model (M303/M307) or the default.
TEST(ControllerCommands, M570SetsTheProtectionAndRefusesOutOfRange) {
  Rig rig;
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T2 U15 P120 S0 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.send("M570 T5 P60\n"), "ok\n");
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S0 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.send("M570 T1\n"), "Error:M570 T must be an integer in 2..60\nok\n");
  EXPECT_EQ(rig.send("M570 T6 P700\n"), "Error:M570 P must be an integer in 20..600\nok\n");  // T not applied
  EXPECT_EQ(rig.send("M570 U2.5\n"), "Error:M570 U must be an integer in 2..60\nok\n");
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S0 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.send("M307 A500\n"), "ok\n");  // a model the host vouches for: the check tightens
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S1 ; model check: T (measured model)\nok\n");
  EXPECT_EQ(rig.send("M570 S5\n"), "Error:M570 S must be an integer in 0..4\nok\n");
  EXPECT_EQ(rig.send("M570 S2\n"), "ok\n");  // back to the wide check, the model kept as measured
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S2 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.machine.bank.settings().model.rise_q8, 500 * 256);
  // ...and still measured: the PID family's fan share with F0 keeps coming from it.
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelMeasuredLoose);
  EXPECT_EQ(rig.send("M570 S1\n"), "ok\n");
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelMeasured);
  EXPECT_EQ(rig.send("M570 S3\n"), "ok\n");
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelMeasuredLag);
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S3 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.send("M570 S4\n"), "ok\n");
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelFittedLags);
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T5 U15 P60 S4 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.send("M570 S0\n"), "ok\n");  // as is: the model counts as the default's
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelDefault);
  EXPECT_EQ(rig.send("M570 S5\n"), "Error:M570 S must be an integer in 0..4\nok\n");
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelDefault);
  rig.send("M502\n");
  EXPECT_EQ(rig.send("M570\n"), "echo:M570 T2 U15 P120 S0 ; model check: U (default, loose or lag-dominated model)\nok\n");
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelDefault);
}

// M503 prints M570 after M307: replaying it restores the model's source as it was (default,
// loose: hot start or unsure tune, lag-dominated), instead of M307 marking it measured. The
// default model most of all: marked measured or lag-dominated, fuzzy-PID F0 would follow the
// heat-up of a model nobody measured.
TEST(ControllerCommands, ReplayedM503KeepsTheModelsSource) {
  {
    Rig rig;  // the default model, untouched
    ASSERT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelDefault);
    Rig fresh;
    for (const std::string& line : settings_lines(rig)) fresh.send(line + "\n");
    EXPECT_EQ(fresh.machine.bank.settings().model_tuned, firmware::kModelDefault);
  }
  for (const char* s : {"S0", "S2", "S3", "S4"}) {
    Rig rig;
    rig.send(std::string("M307 A500 C200 D6 F30\nM570 ") + s + "\n");
    const uint8_t source = rig.machine.bank.settings().model_tuned;
    ASSERT_NE(source, firmware::kModelMeasured) << s;
    Rig fresh;
    for (const std::string& line : settings_lines(rig)) fresh.send(line + "\n");
    EXPECT_EQ(fresh.machine.bank.settings().model.rise_q8, 500 * 256);
    EXPECT_EQ(fresh.machine.bank.settings().model_tuned, source) << s;
  }
}

TEST(ControllerCommands, StoredProtectionOutOfRangeIsRefusedWhole) {
  Rig rig;
  firmware::Settings bad = rig.machine.bank.settings();
  bad.protect_tuned_c = 0;
  EXPECT_NE(rig.machine.bank.replace_all(bad, nullptr, firmware::HandOver{0, 0, false}), nullptr);
  bad = rig.machine.bank.settings();
  bad.watch_period_s = 5;
  EXPECT_NE(rig.machine.bank.replace_all(bad, nullptr, firmware::HandOver{0, 0, false}), nullptr);
  EXPECT_EQ(rig.machine.bank.settings().protect_tuned_c, 2);
  // The model's source: 0..4 (default, measured, loose, lag-dominated, fitted lags) load; a byte
  // beyond is corrupt.
  firmware::Settings lag = rig.machine.bank.settings();
  lag.model_tuned = firmware::kModelFittedLags;
  EXPECT_EQ(rig.machine.bank.replace_all(lag, nullptr, firmware::HandOver{0, 0, false}), nullptr);
  bad = rig.machine.bank.settings();
  bad.model_tuned = firmware::kModelFittedLags + 1;
  EXPECT_NE(rig.machine.bank.replace_all(bad, nullptr, firmware::HandOver{0, 0, false}), nullptr);
  EXPECT_EQ(rig.machine.bank.settings().model_tuned, firmware::kModelFittedLags);
}

}  // namespace

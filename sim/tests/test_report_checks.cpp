// The --check verdicts the HIL tests rely on: each limit must be able to fail.
#include <gtest/gtest.h>

#include <algorithm>

#include "sim/report.h"

namespace sim {
namespace {

// A run that meets every default limit: reached, settled, reports fine, a recovered disturbance.
RunResult good_run() {
  RunResult r;
  r.booted = true;
  r.heating_start_s = 0.1;
  r.metrics.time_to_reach_s = 40.0;
  r.metrics.overshoot_c = 0.5;
  r.metrics.steady_mean_error_c = 0.02;
  r.metrics.steady_peak_to_peak_c = 0.1;
  r.metrics.disturbance = DisturbanceMetrics{300.0, 1.5, 50.0};
  r.report_count = 10;
  r.report_error_max_c = 0.1;
  TraceSample s;
  s.heater_duty = 0.4;
  r.trace.assign(3, s);
  return r;
}

bool mentions(const std::vector<std::string>& failed, const std::string& what) {
  return std::any_of(failed.begin(), failed.end(),
                     [&](const std::string& f) { return f.find(what) != std::string::npos; });
}

TEST(ReportChecks, AGoodRunPassesEveryLimit) {
  CheckLimits limits;
  limits.max_overshoot_c = 3.0;
  limits.max_steady_peak_to_peak_c = 1.0;
  limits.max_recovery_s = 60.0;
  EXPECT_TRUE(failed_checks(good_run(), limits).empty());
}

TEST(ReportChecks, RecoveryBoundAndOscillationLimitFail) {
  CheckLimits limits;
  limits.max_recovery_s = 49.0;
  limits.max_steady_peak_to_peak_c = 0.05;
  const auto failed = failed_checks(good_run(), limits);
  EXPECT_TRUE(mentions(failed, "recovery 50.0 s"));
  EXPECT_TRUE(mentions(failed, "peak-to-peak"));
}

TEST(ReportChecks, RecoveryBoundInMultiplesOfThePhysicalBound) {
  RunResult r = good_run();
  r.bound.reachable = true;
  r.bound.settling_s = 24.0;
  CheckLimits limits;
  limits.max_recovery_bound_ratio = 2.0;  // 48 s < 50 s
  EXPECT_TRUE(mentions(failed_checks(r, limits), "> 48.0 s"));
  limits.max_recovery_bound_ratio = 2.1;
  EXPECT_TRUE(failed_checks(r, limits).empty());
}

// --settings: the run must have read the replayed lines back with M503, and the same.
TEST(ReportChecks, ReplayedSettingsMustReadBackTheSame) {
  RunResult r = good_run();
  r.config.settings = {"M301 P1 I0.01 D0"};
  r.config.settings_source = "tuned.gcode";
  EXPECT_TRUE(mentions(failed_checks(r, CheckLimits{}), "did not read back the same"));  // never read back
  r.settings_read_back = false;
  EXPECT_TRUE(mentions(failed_checks(r, CheckLimits{}), "tuned.gcode"));
  r.settings_read_back = true;
  EXPECT_TRUE(failed_checks(r, CheckLimits{}).empty());
}

TEST(ReportChecks, DutyOutsideTheRangeFails) {
  RunResult r = good_run();
  r.report_power_bad = 2;
  EXPECT_TRUE(mentions(failed_checks(r, CheckLimits{}), "@:"));
  r = good_run();
  r.trace[1].heater_duty = 1.01;
  EXPECT_TRUE(mentions(failed_checks(r, CheckLimits{}), "outside 0–100 %"));
}

TEST(ReportChecks, OvershootAndOffsetFail) {
  RunResult r = good_run();
  r.metrics.overshoot_c = 3.2;
  r.metrics.steady_mean_error_c = -0.6;
  CheckLimits limits;
  limits.max_overshoot_c = 3.0;
  const auto failed = failed_checks(r, limits);
  EXPECT_TRUE(mentions(failed, "overshoot 3.20"));
  EXPECT_TRUE(mentions(failed, "mean error"));
}

}  // namespace
}  // namespace sim

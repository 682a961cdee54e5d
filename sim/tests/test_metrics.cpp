// Metric definitions on hand-made traces, and the reply parser.
#include <gtest/gtest.h>

#include "sim/host_session.h"
#include "sim/metrics.h"
#include "sim/pin_meter.h"

namespace sim {
namespace {

// 0.1 s samples from t0 = 10 s: ramp 25 → 212 over 10 s, back to 210 by 20 s, then flat at
// 210.2 until 100 s.
std::vector<TraceSample> make_trace() {
  std::vector<TraceSample> trace;
  for (int i = 0; i <= 1000; ++i) {
    const double t = 0.1 * i;
    double temp = 210.2;
    if (t < 10.0)
      temp = 25.0 + (212.0 - 25.0) * t / 10.0;
    else if (t < 20.0)
      temp = 212.0 - 1.8 * (t - 10.0) / 10.0;
    TraceSample s;
    s.t_s = 10.0 + t;
    s.true_c = temp;
    trace.push_back(s);
  }
  return trace;
}

TEST(Metrics, FollowTheirDefinitions) {
  const Metrics m = compute_metrics(make_trace(), 10.0, 210.0);
  ASSERT_TRUE(m.time_to_reach_s);
  EXPECT_NEAR(*m.time_to_reach_s, 9.9, 0.051);  // 209 °C at t = 184/187·10 = 9.84
  EXPECT_NEAR(m.overshoot_c, 2.0, 1e-9);
  ASSERT_TRUE(m.settling_s);
  EXPECT_NEAR(*m.settling_s, 15.5, 0.051);  // last sample above 211 °C
  EXPECT_NEAR(m.steady_mean_error_c, 0.2, 1e-9);
  EXPECT_NEAR(m.steady_peak_to_peak_c, 0.0, 1e-9);
  EXPECT_NEAR(m.steady_from_s, 75.0, 0.051);
  EXPECT_FALSE(m.disturbance);
}

TEST(Metrics, UnsettledRunHasNoSettlingTime) {
  std::vector<TraceSample> trace = make_trace();
  trace.back().true_c = 205.0;
  EXPECT_FALSE(compute_metrics(trace, 10.0, 210.0).settling_s);
}

TEST(Metrics, DisturbanceSplitsTheRun) {
  std::vector<TraceSample> trace = make_trace();
  for (TraceSample& s : trace)
    if (s.t_s >= 70.0 && s.t_s < 75.0) s.true_c = 207.0;  // dip after a step at 60 s
  const Metrics m = compute_metrics(trace, 10.0, 210.0, 60.0);
  ASSERT_TRUE(m.disturbance);
  EXPECT_NEAR(m.disturbance->max_deviation_c, 3.0, 1e-9);
  ASSERT_TRUE(m.disturbance->recovery_s);
  EXPECT_NEAR(*m.disturbance->recovery_s, 4.9, 0.051);
  EXPECT_NEAR(m.steady_to_s, 59.9, 0.051);
}

TEST(TempReport, ParsesMarlinFormats) {
  auto r = parse_temp_report("ok T:210.25 /210.00 @:87");
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->temp_c, 210.25);
  EXPECT_DOUBLE_EQ(r->target_c, 210.0);
  EXPECT_EQ(r->power, 87);
  r = parse_temp_report(" T:25.00 /0.00 B:25.00 /0.00 @:0 B@:0");
  ASSERT_TRUE(r);
  EXPECT_DOUBLE_EQ(r->temp_c, 25.0);
  EXPECT_EQ(r->power, 0);
  EXPECT_FALSE(parse_temp_report("echo:Unknown command: \"M999T:\""));
  EXPECT_FALSE(parse_temp_report("ok"));
}

TEST(PinMeter, IntegratesOnTimeBetweenEdges) {
  PinMeter pin;
  pin.set_output(true, 0);
  pin.set_level(true, 100);
  pin.set_level(false, 350);
  EXPECT_DOUBLE_EQ(pin.take_duty(1000), 0.25);
  pin.set_level(true, 1500);
  EXPECT_DOUBLE_EQ(pin.take_duty(2000), 0.5);  // still on: counted up to the sample
  EXPECT_DOUBLE_EQ(pin.take_duty(3000), 1.0);
  pin.set_output(false, 3500);  // an input pin does not drive the MOSFET
  EXPECT_DOUBLE_EQ(pin.take_duty(4000), 0.5);
  pin.reset(4000);
  EXPECT_FALSE(pin.is_on());
}

}  // namespace
}  // namespace sim

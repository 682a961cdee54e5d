// control::ModelCheck (issue 8's model-based heater protection) against a double-precision
// reference of the same bounds, and in closed loop on double-precision plants (design::PlantSim):
// no trip on healthy hotends through target changes, fan changes, noise and model error; a trip
// soon after a dead heater, a heater stuck on, or a detached thermistor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "control/model_check.h"
#include "design/lti_model.h"
#include "design/plant_sim.h"
#include "design/seed_models.h"

namespace {

using Verdict = control::ModelCheck::Verdict;
constexpr uint16_t kPeriodMs = 128;
constexpr double kPeriodS = 0.128;

control::HotendModel q8_model(double a, double c, double d, double f) {
  auto q8 = [](double v) { return static_cast<int32_t>(std::lround(v * 256.0)); };
  return control::HotendModel{q8(a), q8(c), q8(d), q8(f)};
}

// hotend40w's exact FOPDT reading (control::kHotend40wModel's numbers).
const control::HotendModel kHotend40w = q8_model(40.0 / 0.068, 16.7 / 0.068, 1.0 / 0.22, (0.097 / 0.068 - 1) * 100);

// The bounds of control/model_check.h in double (tuned model), for the fixed-point comparison.
class ReferenceCheck {
 public:
  ReferenceCheck(double a, double c, double d, double f) : a_(a), c_(c), f_(f) {
    const double dead = d / kPeriodS;
    first_ = dead * 0.5;
    last_ = dead * 2 + 1.0 / kPeriodS;
  }
  // `history`: duty per period, newest last (this period's included).
  void step(double temp_c, const std::vector<double>& history, const std::vector<double>& fans) {
    double lo = 1.0, hi = 0.0, fan01 = 0.0;
    const int n = static_cast<int>(history.size());
    for (int age = 0; age <= static_cast<int>(last_) + 1 && age < n; ++age) fan01 = std::max(fan01, fans[n - 1 - age]);
    for (int age = static_cast<int>(first_); age <= static_cast<int>(last_) + 1 && age < n; ++age) {
      lo = std::min(lo, history[n - 1 - age]);
      hi = std::max(hi, history[n - 1 - age]);
    }
    if (n <= static_cast<int>(last_) + 1) lo = 0.0, hi = 1.0;  // history unknown at the start
    if (have_last_) {
      const double rise = temp_c - last_c_;
      const double lower = kPeriodS / c_ * (a_ * 0.85 * lo - 1.1 * (1 + f_ / 100 * fan01) * (temp_c - 18));
      const double upper = kPeriodS / c_ * (a_ * 1.15 * hi - 0.9 * (temp_c - 35));
      low_ = std::min(0.0, low_ * (1 - 1.0 / 512) + rise - lower);
      high_ = std::max(0.0, high_ * (1 - 1.0 / 512) + rise - upper);
    }
    last_c_ = temp_c;
    have_last_ = true;
  }
  double low() const { return low_; }
  double high() const { return high_; }

 private:
  double a_, c_, f_, first_, last_;
  double last_c_ = 0, low_ = 0, high_ = 0;
  bool have_last_ = false;
};

// A PI with model feedforward, in double: the kind of controller the check sits beside.
class PiController {
 public:
  PiController(double rise_k, double fan_loss_pct) : rise_k_(rise_k), fan_(fan_loss_pct / 100) {}
  double step(double target_c, double measured_c, double fan01) {
    if (target_c <= 0) return i_ = 0, 0.0;
    const double ff = (target_c - 25) / rise_k_ * (1 + fan_ * fan01);
    const double e = target_c - measured_c;
    const double out = ff + 0.08 * e + i_;
    if ((out < 1 || e < 0) && (out > 0 || e > 0)) i_ += 0.002 * e * kPeriodS;
    return std::min(std::max(out, 0.0), 1.0);
  }

 private:
  double rise_k_, fan_, i_ = 0;
};

enum class PlantFault { kNone, kHeaterDead, kStuckOn, kDetached, kQuarterPower };

struct Scenario {
  design::LtiModel plant = design::two_node();
  control::HotendModel model = kHotend40w;
  bool tuned = true;
  int32_t threshold_c = 2;
  double noise_c = 0.05;
  double seconds = 600;
  // Target and fan as functions of time.
  double (*target_at)(double t_s) = [](double) { return 210.0; };
  double (*fan_at)(double t_s) = [](double) { return 0.0; };
  PlantFault fault = PlantFault::kNone;
  double fault_at_s = 0;
};

struct Outcome {
  Verdict verdict = Verdict::kOk;
  double at_s = -1;  // seconds after the fault (or the start) when it tripped
  double peak_low_c = 0, peak_high_c = 0;
};

Outcome run(const Scenario& s) {
  design::PlantSim plant(s.plant);
  plant.set_noise(s.noise_c);
  control::ModelCheck check;
  check.configure(s.model, s.tuned, s.threshold_c * 256, kPeriodMs);
  PiController pi(s.model.rise_q8 / 256.0, s.model.fan_loss_pct_q8 / 256.0);
  Outcome out;
  double detached_c = 0, duty = 0, fan = 0;
  bool faulted = false;
  for (double t = 0; t < s.seconds; t += kPeriodS) {
    if (s.fault != PlantFault::kNone && !faulted && t >= s.fault_at_s) {
      faulted = true;
      detached_c = plant.true_c();
      if (s.fault == PlantFault::kHeaterDead) plant.set_gain_error(0.0);
      if (s.fault == PlantFault::kQuarterPower) plant.set_gain_error(0.25);
      if (s.fault == PlantFault::kStuckOn) plant.set_gain_error(0.0), plant.set_disturbance(1.0);
    }
    double reading = plant.measured_c();
    if (faulted && s.fault == PlantFault::kDetached) reading = detached_c;
    // The check sees the reading at the end of a period and the duty that ran in it.
    const Verdict v = t > 0 ? check.step(static_cast<int32_t>(std::lround(reading * 256.0)),
                                         static_cast<uint16_t>(std::lround(duty * 65535.0)),
                                         static_cast<uint8_t>(std::lround(fan * 255)))
                            : Verdict::kOk;
    fan = s.fan_at(t);
    duty = pi.step(s.target_at(t), reading, fan);
    plant.set_fan(fan);
    plant.run(duty, kPeriodS);
    if (faulted && s.fault == PlantFault::kDetached) detached_c += (25.0 - detached_c) * kPeriodS / 15.0;  // in air
    out.peak_low_c = std::min(out.peak_low_c, check.low_evidence_q16() / 65536.0);
    out.peak_high_c = std::max(out.peak_high_c, check.high_evidence_q16() / 65536.0);
    if (v != Verdict::kOk) {
      out.verdict = v;
      out.at_s = t - (s.fault != PlantFault::kNone ? s.fault_at_s : 0.0);
      return out;
    }
  }
  return out;
}

// Print-like: targets 190–250 °C changing every 100–200 s, fan 0–100 % every 30–120 s.
double print_target(double t) {
  static const double targets[] = {210, 245, 190, 230, 250, 200, 215, 195};
  return targets[static_cast<int>(t / 150) % 8];
}
double print_fan(double t) {
  static const double fans[] = {0, 1, 0.35, 0.7, 0, 0.5, 1, 0.2};
  return t < 120 ? 0 : fans[static_cast<int>(t / 75) % 8];
}

TEST(ModelCheck, FixedPointFollowsTheDoubleReference) {
  design::PlantSim plant(design::two_node());
  control::ModelCheck check;
  check.configure(kHotend40w, true, 50 * 256, kPeriodMs);
  ReferenceCheck ref(40.0 / 0.068, 16.7 / 0.068, 1.0 / 0.22, (0.097 / 0.068 - 1) * 100);
  PiController pi(40.0 / 0.068, 42.6);
  std::vector<double> history, fans;
  double worst = 0;
  for (double t = 0; t < 900; t += kPeriodS) {
    const double fan = print_fan(t);
    const double reading = std::lround(plant.true_c() * 256.0) / 256.0;
    // A duty the Q8 window sees exactly (multiples of 1/256), as the firmware's duty >> 8.
    const double duty = std::floor(pi.step(print_target(t), reading, fan) * 255.0) / 256.0;
    history.push_back(duty);
    fans.push_back(std::lround(fan * 255) / 255.0);
    plant.set_fan(fan);
    plant.run(duty, kPeriodS);
    check.step(static_cast<int32_t>(std::lround(reading * 256.0)), static_cast<uint16_t>(duty * 65536.0),
               static_cast<uint8_t>(std::lround(fan * 255)));
    ref.step(reading, history, fans);
    if (t > 20) {  // past the first window (the fixed point's bins round the window edges)
      worst = std::max(worst, std::fabs(check.low_evidence_q16() / 65536.0 - ref.low()));
      worst = std::max(worst, std::fabs(check.high_evidence_q16() / 65536.0 - ref.high()));
    }
  }
  // Bins of 5 periods move the window's edges by up to 0.6 s: a few tenths of a degree.
  EXPECT_LT(worst, 0.5);
}

TEST(ModelCheck, NoTripOnHealthyHotendsThroughAPrintLikeHour) {
  struct Case {
    const char* name;
    design::LtiModel plant;
    control::HotendModel model;
  };
  design::TwoNodeParams p30, p80;
  p30.heater_w = 30;
  p80.heater_w = 80;
  const Case cases[] = {
      {"hotend40w", design::two_node(), kHotend40w},
      // The tune's A off by ±10 % (issue 7: M303 within 10 %).
      {"hotend40w, A +10 %", design::two_node(), q8_model(40.0 / 0.068 * 1.1, 16.7 / 0.068, 4.5, 42.6)},
      {"hotend40w, A -10 %", design::two_node(), q8_model(40.0 / 0.068 * 0.9, 16.7 / 0.068, 4.5, 42.6)},
      {"hotend30w", design::two_node(p30), q8_model(30.0 / 0.068, 16.7 / 0.068, 4.5, 42.6)},
      {"hotend80w", design::two_node(p80), q8_model(80.0 / 0.068, 16.7 / 0.068, 4.5, 42.6)},
      {"fopdt-delay25", design::with_seed_fan(design::fopdt(450, 120, 25)), q8_model(450, 120, 25, 42.6)},
      {"seed002", design::seed002(), q8_model(450, 24, 20.7, 42.6)},
  };
  for (const Case& c : cases) {
    Scenario s;
    s.plant = c.plant;
    s.model = c.model;
    s.seconds = 3600;
    s.noise_c = 0.1;
    s.target_at = print_target;
    s.fan_at = print_fan;
    const Outcome o = run(s);
    EXPECT_EQ(o.verdict, Verdict::kOk) << c.name << " tripped at " << o.at_s << " s";
    RecordProperty(c.name, std::to_string(o.peak_low_c) + " / " + std::to_string(o.peak_high_c));
  }
}

// Higher-order plants with the two-point FOPDT fit a tune gives (sim/plant_model.h): the fit's D
// stands for lags, which is why the window reaches 2D (3D/4 .. 5D/4 left 27 °C of evidence on seed003).
TEST(ModelCheck, NoTripOnHigherOrderPlantsWithTheirFopdtFit) {
  struct Case {
    const char* name;
    design::LtiModel plant;
    control::HotendModel model;
  };
  const Case cases[] = {
      {"seed003", design::seed003(), q8_model(450, 35.056, 9.853, 42.6)},
      {"seed000-4", design::seed000_4(), q8_model(450, 582.4, 163.4, 42.6)},
      {"seed000-5", design::seed000_5(), q8_model(450, 1177.8, 126.7, 42.6)},
  };
  for (const Case& c : cases) {
    Scenario s;
    s.plant = c.plant;
    s.model = c.model;
    s.seconds = 3600;
    s.target_at = [](double t) { return t < 1800 ? 210.0 : 150.0; };
    const Outcome o = run(s);
    EXPECT_EQ(o.verdict, Verdict::kOk) << c.name << " tripped at " << o.at_s << " s";
    RecordProperty(c.name, std::to_string(o.peak_low_c) + " / " + std::to_string(o.peak_high_c));
  }
}

TEST(ModelCheck, CatchesADeadHeaterADetachedThermistorAndAStuckHeater) {
  Scenario s;
  s.fault_at_s = 300;  // at 210 °C
  s.seconds = 400;
  s.fault = PlantFault::kHeaterDead;
  Outcome o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooLittle);
  EXPECT_GT(o.at_s, 0);
  EXPECT_LT(o.at_s, 15);
  s.fault = PlantFault::kDetached;
  o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooLittle);
  EXPECT_LT(o.at_s, 5);
  s.fault = PlantFault::kStuckOn;
  o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooMuch);
  EXPECT_LT(o.at_s, 10);
  s.fault = PlantFault::kQuarterPower;
  o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooLittle);
  EXPECT_LT(o.at_s, 40);
}

TEST(ModelCheck, CatchesAHeaterStuckOnWhileIdle) {
  Scenario s;
  s.target_at = [](double) { return 0.0; };
  s.fault = PlantFault::kStuckOn;
  s.fault_at_s = 60;
  s.seconds = 120;
  const Outcome o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooMuch);
  EXPECT_LT(o.at_s, 10);
}

// The default model (hotend40w) on a hotend it does not describe: loose bounds, no trip.
TEST(ModelCheck, DefaultModelDoesNotTripOnOtherHotends) {
  design::TwoNodeParams heavy;
  heavy.block_j_per_k = 40;
  heavy.heater_w = 60;
  heavy.loss_w_per_k = 0.14;
  heavy.sensor_rate_per_s = 1.0 / 25;
  for (const design::LtiModel& plant : {design::seed002(), design::two_node(heavy)}) {
    Scenario s;
    s.plant = plant;
    s.tuned = false;
    s.threshold_c = 15;
    s.seconds = 1800;
    s.target_at = print_target;
    s.fan_at = print_fan;
    const Outcome o = run(s);
    EXPECT_EQ(o.verdict, Verdict::kOk) << "tripped at " << o.at_s << " s";
  }
}

TEST(ModelCheck, DefaultModelStillCatchesAStuckHeaterWhileIdle) {
  Scenario s;
  s.tuned = false;
  s.threshold_c = 15;
  s.target_at = [](double) { return 0.0; };
  s.fault = PlantFault::kStuckOn;
  s.fault_at_s = 60;
  s.seconds = 200;
  const Outcome o = run(s);
  EXPECT_EQ(o.verdict, Verdict::kHeatsTooMuch);
  EXPECT_LT(o.at_s, 25);  // 2 × U = 30 °C of rise: slower than with a tuned model
}

}  // namespace

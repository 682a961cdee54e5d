// The plant bank: the gains, dead times and discretisation the benchmark relies on.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/bound.h"
#include "sim/default_gains.h"
#include "sim/plants.h"
#include "sim/relay_tuning.h"

namespace sim {
namespace {

const PlantSpec& plant(const char* name) {
  const PlantSpec* p = find_plant(name);
  EXPECT_NE(p, nullptr) << name;
  return *p;
}

double settle_rise_k(const PlantSpec& spec, double heater, double fan, double seconds) {
  Plant p(spec, 0.01);
  for (int i = 0; i < static_cast<int>(seconds / 0.01); ++i) p.step(PlantInput{heater, fan});
  return p.temperature_c() - spec.ambient_c;
}

TEST(PlantBank, SeedGainsAreRescaledTo450KAtFullPower) {
  for (const char* name : {"seed002", "seed004", "seed003", "seed000-4", "seed000-5"})
    EXPECT_NEAR(design::dc_gain(plant(name).model), 450.0, 1e-6) << name;
}

TEST(PlantBank, Hotend40wIsPhysical) {
  EXPECT_NEAR(design::dc_gain(plant("hotend40w").model, 0.0), 40.0 / 0.068, 1e-9);
  EXPECT_NEAR(design::dc_gain(plant("hotend40w").model, 1.0), 40.0 / 0.097, 1e-9);
}

TEST(Plant, SimulatedSteadyStateMatchesTheDcGain) {
  // Also shows every model is stable with the fan's extra loss.
  for (const PlantSpec& spec : plant_bank())
    for (double fan : {0.0, 1.0})
      EXPECT_NEAR(settle_rise_k(spec, 0.5, fan, 40000.0), 0.5 * design::dc_gain(spec.model, fan), 1e-3)
          << spec.name << " fan " << fan;
}

TEST(PlantBank, TheFanRaisesTheLossLikeHotend40wsOnEveryPlant) {
  const double ratio = design::dc_gain(plant("hotend40w").model, 0.0) / design::dc_gain(plant("hotend40w").model, 1.0);
  for (const PlantSpec& spec : plant_bank())
    EXPECT_NEAR(design::dc_gain(spec.model, 0.0) / design::dc_gain(spec.model, 1.0), ratio, 1e-9) << spec.name;
}

TEST(Plant, FopdtIsExactAtSampleInstants) {
  // K·(1 − e^(−(t−τ)/T)) after the dead time, nothing before it.
  const PlantSpec& spec = plant("seed002");
  Plant p(spec, 0.001);
  for (int i = 0; i < 20700; ++i) p.step(PlantInput{1.0, 0.0});
  EXPECT_NEAR(p.temperature_c(), spec.ambient_c, 1e-12);
  for (int i = 0; i < 24000; ++i) p.step(PlantInput{1.0, 0.0});
  EXPECT_NEAR(p.temperature_c() - spec.ambient_c, 450.0 * (1.0 - std::exp(-1.0)), 1e-9);
}

TEST(Plant, HeaterDutyActsThroughItsAverage) {
  // A 50 % duty split over the step gives the same state as 50 % held: exact ZOH is linear.
  const PlantSpec& spec = plant("seed003");
  Plant a(spec, 0.001), b(spec, 0.001);
  for (int i = 0; i < 30000; ++i) {
    a.step(PlantInput{0.5, 0.0});
    b.step(PlantInput{(i % 2) ? 1.0 : 0.0, 0.0});
  }
  EXPECT_NEAR(a.temperature_c(), b.temperature_c(), 0.01);
}

TEST(Plant, RejectsAStepThatDoesNotDivideTheDeadTime) {
  EXPECT_THROW(Plant(plant("seed002"), 0.007), std::invalid_argument);
}

TEST(PhysicalBound, FopdtBoundIsDeadTimePlusTimeToEnterTheBand) {
  // Full power until the output would enter the band after the dead time, then hold: the band is
  // entered at τ + T·ln(K/(K − (r − 1))) and never left.
  const PlantSpec& spec = plant("seed002");
  const PhysicalBound b = physical_bound(spec, 210.0);
  ASSERT_TRUE(b.reachable);
  const double rise = 210.0 - 1.0 - spec.ambient_c;
  EXPECT_NEAR(b.settling_s, 20.7 + 24.0 * std::log(450.0 / (450.0 - rise)), 0.06);
  EXPECT_NEAR(b.steady_duty, (210.0 - 25.0) / 450.0, 1e-12);
}

TEST(PhysicalBound, UnreachableTargetIsFlagged) {
  EXPECT_FALSE(physical_bound(plant("seed002"), 500.0).reachable);
}

TEST(PhysicalBound, NoControllerBeatsIt) {
  // Sanity: the bound is never shorter than the time full power needs to reach the band.
  for (const PlantSpec& spec : plant_bank()) {
    const PhysicalBound b = physical_bound(spec, spec.default_target_c);
    const auto s = full_power_step_response_k(spec, 0.02, static_cast<std::size_t>(b.settling_s / 0.02) + 10);
    std::size_t k = 0;
    while (s[k] < spec.default_target_c - 1.0 - spec.ambient_c) ++k;
    // The bound is computed on a 50 ms grid, this on a 20 ms one: they may differ by a step.
    EXPECT_GE(b.settling_s + 0.05, double(k + 1) * 0.02) << spec.name;
  }
}

TEST(DefaultGains, TwoPointFitRecoversAnExactFopdt) {
  const tuning::Fopdt m = fopdt_approximation(plant("seed004"));
  EXPECT_NEAR(m.k_c_per_duty, 450.0, 1e-6);
  EXPECT_NEAR(m.t_s, 25.5, 0.05);
  EXPECT_NEAR(m.tau_s, 19.5, 0.05);
}

}  // namespace
}  // namespace sim

namespace sim {
namespace {

TEST(RelayExperiment, MatchesTheFopdtClosedForm) {
  // Ideal relay ±d around the balancing duty on K·e^(−τs)/(Ts+1): the output peaks τ after each
  // crossing, a = K·d·(1 − e^(−τ/T)), and falls back in T·ln(2 − e^(−τ/T)).
  const RelayResult r = relay_experiment(plant("seed002"), 210.0, 0.01);
  ASSERT_TRUE(r.oscillated);
  const double d = (210.0 - 25.0) / 450.0, decay = std::exp(-20.7 / 24.0);
  EXPECT_NEAR(r.relay_amplitude_duty, d, 1e-12);
  EXPECT_NEAR(r.amplitude_k, 450.0 * d * (1.0 - decay), 0.05);
  EXPECT_NEAR(r.ultimate_period_s, 2.0 * (20.7 + 24.0 * std::log(2.0 - decay)), 0.05);
}

}  // namespace
}  // namespace sim

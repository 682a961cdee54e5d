// Issue 7: the PID family passes HIL3's limits on the seed plants (overshoot ≤ 3 °C, steady p-p
// ≤ 1 °C, |steady error| ≤ 0.5 °C, back in ±1 °C within 2 × bound after the part-fan step, no
// watch trip), here on the host against double-precision seed plants (seed_loop.h), set up as
// hotend-sim sets them up; the hil.*.seed*.<controller> tests run the same pairs on the images.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "host_tests/seed_loop.h"

namespace {

seed_loop::SeedPlant plant(const char* name) {
  for (const seed_loop::SeedPlant& p : seed_loop::seed_plants())
    if (std::strcmp(p.name, name) == 0) return p;
  ADD_FAILURE() << name;
  return seed_loop::seed_plants().front();
}

seed_loop::Figures measure(const char* plant_name, const char* controller) {
  const seed_loop::SeedPlant p = plant(plant_name);
  const seed_loop::Figures f = seed_loop::run(p, controller);
  std::printf("%-9s %-9s overshoot %5.2f °C, steady mean %6.3f p-p %5.3f °C, fan dip %5.2f °C, recovery %5.1f s "
              "(%4.2f × bound), fault %d\n",
              p.name, controller, f.overshoot_c, f.steady_mean_c, f.steady_pp_c, f.dip_c, f.recovery_s,
              f.recovery_ratio(p.bound_s), static_cast<int>(f.fault));
  return f;
}

void expect_passes(const char* plant_name, const char* controller) {
  const seed_loop::Figures f = measure(plant_name, controller);
  EXPECT_TRUE(f.passes(plant(plant_name).bound_s)) << plant_name << " " << controller;
  // The part-fan term: a 43 % loss step behind a 20 s dead time is seen, not felt (it was a
  // 28–45 °C dip with feedback alone).
  EXPECT_LT(f.dip_c, 1.5) << plant_name << " " << controller;
}

TEST(SeedControllers, EveryPidFamilyControllerPassesOnTheDeadTimeSeeds) {
  for (const char* p : {"seed002", "seed004"})
    for (const char* c : {"pid", "pid+ff", "fuzzy", "fuzzy+ff"}) expect_passes(p, c);
}

// Seed003 (two lags, 14 s and 28 s; M307 its two-point fit): the model's heat-up overshot by
// 9–10 °C until the lead rule (control/feedforward.h) ended full power early there.
TEST(SeedControllers, EveryPidFamilyControllerPassesOnSeed003) {
  for (const char* c : {"pid", "pid+ff", "fuzzy", "fuzzy+ff"}) expect_passes("seed003", c);
}

// Seed000 (slow identified models, D 127–163 s, run 3,600 s with the fan step at 1,800 s):
// seed000-4's model heat-up overshot by 6.2–7.3 °C and then sat 1.2–1.6 °C low until the lead
// rule took 5/16 of its 35 °C lead for a D that long (control/feedforward.cpp); seed000-5's fit
// (D/C 0.11) keeps the plain heat-up.
TEST(SeedControllers, EveryPidFamilyControllerPassesOnSeed000) {
  for (const char* p : {"seed000-4", "seed000-5"})
    for (const char* c : {"pid", "pid+ff", "fuzzy", "fuzzy+ff"}) expect_passes(p, c);
}

}  // namespace

// The compiled-in presets (design/state_feedback_presets.h) are what the design tool produces
// today for each plant of the bank: they must not go stale when the design or the plant changes.
#include <gtest/gtest.h>

#include <cstdlib>

#include "design/seed_models.h"
#include "design/state_feedback_format.h"
#include "design/state_feedback_presets.h"
#include "design/state_feedback_quantize.h"

namespace {

using namespace design;

struct Preset {
  const char* name;
  const control::StateFeedbackConstants& constants;
  LtiModel model;
};

TEST(StateFeedbackPresets, MatchAFreshDesign) {
  const Preset presets[] = {{"kSfHotend40w", control::kSfHotend40w, two_node()},
                            {"kSfSeed002", control::kSfSeed002, seed002()},
                            {"kSfSeed004", control::kSfSeed004, seed004()},
                            {"kSfSeed003", control::kSfSeed003, seed003()},
                            {"kSfSeed0004", control::kSfSeed0004, seed000_4()},
                            {"kSfSeed0005", control::kSfSeed0005, seed000_5()}};
  for (const Preset& p : presets) {
    SCOPED_TRACE(p.name);
    control::StateFeedbackConstants fresh;
    ASSERT_EQ(quantize(design_state_feedback(p.model), p.model.fan_loss_per_k, &fresh), nullptr);
    long want[256], got[256];
    int count = 0;
    for_each_field(fresh, [&](int i, const char*, long v) {
      want[i] = v;
      count = i + 1;
    });
    for_each_field(p.constants, [&](int i, const char*, long v) { got[i] = v; });
    // A mantissa may differ by one LSB if the host's floating point rounds differently.
    for (int i = 0; i < count; ++i)
      EXPECT_LE(std::labs(got[i] - want[i]), 1) << "field index " << i;
    EXPECT_TRUE(control::state_feedback_constants_valid(p.constants));
  }
}

}  // namespace

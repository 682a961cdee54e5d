// State-feedback constants for the host tests, designed from the model library at run time
// (design/), so that no test depends on a hand-copied table that could go stale.
#pragma once

#include <gtest/gtest.h>

#include "control/state_feedback_constants.h"
#include "design/seed_models.h"
#include "design/state_feedback_quantize.h"

namespace fixtures {

inline control::StateFeedbackConstants designed_constants(const design::LtiModel& model) {
  control::StateFeedbackConstants k;
  const char* error = design::design_constants(model, &k);
  EXPECT_EQ(error, nullptr) << error;
  return k;
}

inline const control::StateFeedbackConstants& hotend40w_constants() {
  static const control::StateFeedbackConstants k = designed_constants(design::two_node());
  return k;
}
inline const control::StateFeedbackConstants& seed002_constants() {
  static const control::StateFeedbackConstants k = designed_constants(design::seed002());
  return k;
}
inline const control::StateFeedbackConstants& seed004_constants() {
  static const control::StateFeedbackConstants k = designed_constants(design::seed004());
  return k;
}
inline const control::StateFeedbackConstants& seed000_5_constants() {
  static const control::StateFeedbackConstants k = designed_constants(design::seed000_5());
  return k;
}

}  // namespace fixtures

// The fuzzy rule tables keep the properties they were designed with (docs/fuzzy_pid.md):
// point symmetry and seed 002's three principles, expressed as checks on |e| and |ec| levels.
#include "control/fuzzy_rules.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace {

using fuzzy::RuleTable;
using fuzzy::kSets;

// |e| or |ec| level of a set index: 0 = ZO, 1 = S, 2 = M, 3 = B.
int level(int set) { return std::abs(set - 3); }
// +1 when e and ec have the same sign (|e| growing), −1 when opposite (closing on the target).
int trend(int i, int j) { return (i - 3) * (j - 3) > 0 ? 1 : ((i - 3) * (j - 3) < 0 ? -1 : 0); }

double row_level_mean(const RuleTable& t, int lev) {
  double sum = 0;
  int n = 0;
  for (int i = 0; i < kSets; ++i) {
    if (level(i) != lev) continue;
    for (int j = 0; j < kSets; ++j, ++n) sum += t.out[i][j];
  }
  return sum / n;
}

TEST(FuzzyRules, EveryCellIsAnOutputSet) {
  for (const RuleTable* t : {&fuzzy::kRulesKp, &fuzzy::kRulesKi, &fuzzy::kRulesKd})
    for (int i = 0; i < kSets; ++i)
      for (int j = 0; j < kSets; ++j) EXPECT_LT(t->out[i][j], kSets);
}

TEST(FuzzyRules, TablesArePointSymmetric) {
  // Heating and cooling errors mirror each other: (e, ec) and (−e, −ec) conclude the same.
  for (const RuleTable* t : {&fuzzy::kRulesKp, &fuzzy::kRulesKi, &fuzzy::kRulesKd})
    for (int i = 0; i < kSets; ++i)
      for (int j = 0; j < kSets; ++j) EXPECT_EQ(t->out[i][j], t->out[6 - i][6 - j]) << i << "," << j;
}

TEST(FuzzyRules, KpIsLargestFarAwaySmallestAtMediumError) {
  const RuleTable& t = fuzzy::kRulesKp;
  for (int j = 0; j < kSets; ++j) {  // principle 1: large kp whatever ec does
    EXPECT_EQ(t.out[0][j], fuzzy::PB);
    EXPECT_EQ(t.out[6][j], fuzzy::PB);
  }
  // Principles 2 and 3: kp drops at medium |e| and rises again near the target.
  EXPECT_LT(row_level_mean(t, 2), row_level_mean(t, 1));
  EXPECT_LT(row_level_mean(t, 1), row_level_mean(t, 3));
  EXPECT_LE(row_level_mean(t, 1), row_level_mean(t, 0));
}

TEST(FuzzyRules, KpIsStifferWhenTheErrorGrowsThanWhenItCloses) {
  const RuleTable& t = fuzzy::kRulesKp;
  for (int i = 0; i < kSets; ++i)
    for (int j = 0; j < kSets; ++j)
      if (trend(i, j) > 0) {
        EXPECT_GE(t.out[i][j], t.out[i][6 - j]) << i << "," << j;
      }
}

TEST(FuzzyRules, KiNeverGrowsWithTheError) {
  const RuleTable& t = fuzzy::kRulesKi;
  for (int j = 0; j < kSets; ++j) {
    for (int i = 3; i + 1 < kSets; ++i) EXPECT_GE(t.out[i][j], t.out[i + 1][j]) << i << "," << j;
    for (int i = 3; i > 0; --i) EXPECT_GE(t.out[i][j], t.out[i - 1][j]) << i << "," << j;
    EXPECT_EQ(t.out[0][j], fuzzy::NB);  // principle 1: no integration far away
    EXPECT_EQ(t.out[3][j], fuzzy::PB);  // hold the target without offset
  }
  // Principle 2: medium |e| gets a medium ki; principle 3: small |e| a larger one.
  EXPECT_GT(row_level_mean(t, 2), fuzzy::NB);
  EXPECT_LT(row_level_mean(t, 2), row_level_mean(t, 1));
}

TEST(FuzzyRules, KdFollowsTheErrorChangeNearTheTarget) {
  const RuleTable& t = fuzzy::kRulesKd;
  for (int i = 0; i < kSets; ++i) {
    if (level(i) > 1) continue;  // principle 3: |e| small
    EXPECT_EQ(t.out[i][3], fuzzy::PB);
    for (int j = 3; j + 1 < kSets; ++j) EXPECT_GE(t.out[i][j], t.out[i][j + 1]) << i << "," << j;
    for (int j = 3; j > 0; --j) EXPECT_GE(t.out[i][j], t.out[i][j - 1]) << i << "," << j;
    EXPECT_LT(t.out[i][0], fuzzy::ZO);  // small when |ec| is large
  }
  for (int j = 0; j < kSets; ++j) {  // principle 1: small kd far away
    EXPECT_LE(t.out[0][j], fuzzy::NM);
    EXPECT_LE(t.out[6][j], fuzzy::NM);
  }
  // Principle 2: medium kd at medium |e| — between the far and the near rows.
  EXPECT_GT(row_level_mean(t, 2), row_level_mean(t, 3));
  EXPECT_LT(row_level_mean(t, 2), row_level_mean(t, 0));
}

}  // namespace

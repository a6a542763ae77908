// The budget's pass policy (issue 46 item 2): how a measured pass cost
// becomes the rays a pass keeps (pass_sizing.h), and when the next pass
// still fits (bake_plan.h). Pure functions; the bakes that use them are
// measured in tests/bench/double_sided_bake.sh.

#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/bake_plan.h"
#include "pipeline/pass_sizing.h"

namespace svit::baker {
namespace {

TEST(PassPolicy, CheapPassesKeepTheirRays) {
  // 100 s for passes of 1 s: 100 passes fit, more than kMinBudgetPasses.
  EXPECT_DOUBLE_EQ(rayShare(100, 1), 1.0);
  EXPECT_DOUBLE_EQ(rayShare(100, 0), 1.0);  // nothing measured: the plan's rays
}

TEST(PassPolicy, RaysShrinkUntilThirtyPassesFitDownToAQuarter) {
  EXPECT_NEAR(rayShare(15, 1), 0.5, 1e-12);  // 30 passes of half the rays
  EXPECT_NEAR(rayShare(10, 1), 1.0 / 3, 1e-12);
  // 6 s: 30 passes would need a fifth of the rays; a quarter gives 24.
  EXPECT_DOUBLE_EQ(rayShare(6, 1), kMinRayShare);
}

TEST(PassPolicy, NeverBelowAQuarterEvenWhereFewPassesFit) {
  // 5 s for passes of 11.3 s (the double-sided Cornell box at 256 texels/m
  // in 10 s): one pass at a quarter, not two of one gather ray.
  EXPECT_DOUBLE_EQ(rayShare(5, 11.3), kMinRayShare);
  EXPECT_DOUBLE_EQ(rayShare(0, 1), kMinRayShare);
}

TEST(PassPolicy, TheNextPassStartsOnlyWhereItAndTheFinishFit) {
  BakeOptions options;
  options.level_path = "level.gltf";
  options.out_dir = "out";
  options.time_budget_s = 10;
  const BakePlan plan = planBake(options);
  ASSERT_TRUE(plan.has_budget);
  const double finish = finishSeconds(plan, 0.2);
  EXPECT_DOUBLE_EQ(finish, 1.5 * 0.2 + plan.pass_time_margin_s);
  EXPECT_TRUE(wantLightingPass(plan, 0, 9.99, 5, finish));  // the first pass always runs
  const double last_start = 10 - 1 * plan.pass_time_safety - finish;
  EXPECT_TRUE(wantLightingPass(plan, 3, last_start - 1e-6, 1, finish));
  EXPECT_FALSE(wantLightingPass(plan, 3, last_start + 1e-6, 1, finish));
  EXPECT_FALSE(wantLightingPass(plan, plan.max_lighting_passes, 0, 0, 0));
}

TEST(PassPolicy, WithoutABudgetTheQualityCountsThePasses) {
  BakeOptions options;
  options.level_path = "level.gltf";
  options.out_dir = "out";
  options.passes = 6;
  const BakePlan plan = planBake(options);
  EXPECT_FALSE(plan.has_budget);
  EXPECT_TRUE(wantLightingPass(plan, 5, 1e9, 1e9, 1e9));
  EXPECT_FALSE(wantLightingPass(plan, 6, 0, 0, 0));
}

}  // namespace
}  // namespace svit::baker

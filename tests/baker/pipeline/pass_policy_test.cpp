// The budget's pass policy (issue 46 item 2): how a measured pass cost
// becomes the passes and the rays each keeps (pass_sizing.h), and when the
// next pass still fits (bake_plan.h). Pure functions; the bakes that use them are
// measured in tests/bench/double_sided_bake.sh.

#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/bake_plan.h"
#include "pipeline/pass_sizing.h"

namespace svit::baker {
namespace {

// The planned passes fill the usable seconds to within one pass, at least
// kFewestPasses of them where a quarter of the rays allows.
void expectFills(double seconds, const PassCost& cost, const PassPlan& plan) {
  const double usable = seconds / kPassPlanSlack;
  EXPECT_LE(plan.passes * cost.at(plan.ray_share), usable + 1e-9);
  EXPECT_GT((plan.passes + 1) * cost.at(plan.ray_share), usable);
  EXPECT_GE(plan.ray_share, kMinRayShare);
  EXPECT_LE(plan.ray_share, 1.0);
}

TEST(PassPolicy, TheFewestPassesThatFillTheTimeAtNoMoreThanThePlansRays) {
  // The double-sided Cornell box at 10 s: a pass 0.57 s, 0.13 s of it fixed.
  const PassCost cornell{0.13, 0.44};
  const PassPlan plan = planPasses(6, cornell);
  expectFills(6, cornell, plan);
  EXPECT_EQ(plan.passes, 10u);
  EXPECT_GT(plan.ray_share, 0.95);
  // More, smaller passes in the same seconds cast fewer rays: 30 passes at
  // a quarter would cast 5.8 passes' worth.
  EXPECT_GT(plan.passes * plan.ray_share, 1.5 * 6 / cornell.at(kMinRayShare) * kMinRayShare);
  const PassPlan cheap = planPasses(100, {0.1, 0.9});
  expectFills(100, {0.1, 0.9}, cheap);
  EXPECT_GT(cheap.ray_share, 0.98);
}

TEST(PassPolicy, FilteringsAtFourEightSixteenPassesAndAfterTheLast) {
  EXPECT_EQ(filteringsOf(1), 0u);  // the filter needs four passes
  EXPECT_EQ(filteringsOf(3), 0u);
  EXPECT_EQ(filteringsOf(4), 1u);  // the last pass was measured: its filtering is reused
  EXPECT_EQ(filteringsOf(5), 2u);
  EXPECT_EQ(filteringsOf(8), 2u);
  EXPECT_EQ(filteringsOf(9), 3u);
  EXPECT_EQ(filteringsOf(40), 5u);  // 4, 8, 16, 32 and the last
}

TEST(PassPolicy, ThePlanKeepsTimeForTheFilterings) {
  const PassCost cornell{0.13, 0.44};
  const double filter_s = 0.25;
  const PassPlan plan = planPasses(6, cornell, filter_s);
  EXPECT_EQ(plan.passes, 9u);
  const double used = plan.passes * cornell.at(plan.ray_share) + filteringsOf(9) * filter_s;
  EXPECT_LE(used, 6 / kPassPlanSlack + 1e-9);
  EXPECT_GT(used, 6 / kPassPlanSlack - cornell.at(1));
  EXPECT_LT(plan.ray_share, planPasses(6, cornell).ray_share + 1e-12);
}

TEST(PassPolicy, FourPassesWithFewerRaysWhereFullOnesWouldNotFit) {
  const PassPlan plan = planPasses(2, {0.1, 1.0});
  expectFills(2, {0.1, 1.0}, plan);
  EXPECT_EQ(plan.passes, kFewestPasses);
  EXPECT_LT(plan.ray_share, 0.5);
}

TEST(PassPolicy, FourThinnerPassesWhereAQuarterFitsFewerThanFour) {
  // The Cornell box in a 1 s budget: 0.32 s for passes of 0.31 s. Three
  // passes at a quarter would go unfiltered; four at 0.22 are filtered.
  const PassCost cornell{0.01, 0.3};
  const PassPlan plan = planPasses(0.32, cornell);
  EXPECT_EQ(plan.passes, kFewestPasses);
  EXPECT_LT(plan.ray_share, kMinRayShare);
  EXPECT_GE(plan.ray_share, kFilteredPassesMinShare);
  EXPECT_LE(plan.passes * cornell.at(plan.ray_share), 0.32 / kPassPlanSlack + 1e-9);
}

TEST(PassPolicy, OnePassWithWhatFitsWhereFourWouldBeTooThin) {
  // 5 s for passes of 11.3 s (the double-sided Cornell box at 256 texels/m
  // in 10 s): one pass at the share that fits, never below a quarter.
  const PassCost dense{2.3, 9.0};
  const PassPlan plan = planPasses(5, dense);
  EXPECT_EQ(plan.passes, 1u);
  EXPECT_NEAR(plan.ray_share, (5 / kPassPlanSlack - 2.3) / 9.0, 1e-12);
  EXPECT_DOUBLE_EQ(planPasses(3, dense).ray_share, kMinRayShare);
  EXPECT_DOUBLE_EQ(planPasses(0, dense).ray_share, 1.0);  // no time: the plan's rays, one pass
}

TEST(PassPolicy, AllFixedCostOrNoneMeasuredKeepsThePlansRays) {
  EXPECT_DOUBLE_EQ(planPasses(10, {1.0, 0.0}).ray_share, 1.0);
  EXPECT_EQ(planPasses(10, {1.0, 0.0}).passes, 9u);
  EXPECT_DOUBLE_EQ(planPasses(10, {0.0, 0.0}).ray_share, 1.0);
}

// The plan of a bake with a 10 s budget (`passes` 0) or `passes` passes.
BakePlan planOf(uint32_t passes) {
  BakeOptions options;
  options.level_path = "level.gltf";
  options.out_dir = "out";
  if (passes == 0) options.time_budget_s = 10;
  options.passes = passes;
  return planBake(options);
}

TEST(PassPolicy, TheNextPassStartsOnlyWhereItAndTheFinishFit) {
  const BakePlan plan = planOf(0);
  ASSERT_TRUE(plan.has_budget);
  const double finish = finishSeconds(plan, 0.2);
  EXPECT_DOUBLE_EQ(finish, 1.5 * 0.2 + plan.pass_time_margin_s);
  EXPECT_TRUE(wantLightingPass(plan, 0, 9.99, 5, finish));  // the first pass always runs
  const double last_start = 10 - 1 * plan.pass_time_safety - finish;
  EXPECT_TRUE(wantLightingPass(plan, 3, last_start - 1e-6, 1, finish));
  EXPECT_FALSE(wantLightingPass(plan, 3, last_start + 1e-6, 1, finish));
  EXPECT_FALSE(wantLightingPass(plan, plan.max_lighting_passes, 0, 0, 0));
}

TEST(PassPolicy, WithoutABudgetThePassesAreCounted) {
  const BakePlan plan = planOf(6);
  EXPECT_FALSE(plan.has_budget);
  EXPECT_TRUE(wantLightingPass(plan, 5, 1e9, 1e9, 1e9));
  EXPECT_FALSE(wantLightingPass(plan, 6, 0, 0, 0));
}

}  // namespace
}  // namespace svit::baker

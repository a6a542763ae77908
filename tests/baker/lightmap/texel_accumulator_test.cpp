// TexelAccumulator (texel_accumulator.h): the mean of the passes, the mean
// of each parity's half (what the split-half error estimate compares), and
// an accumulator rebuilt from its sums (a sharded bake's merge) giving the
// same means.

#include <gtest/gtest.h>

#include <vector>

#include "lightmap/texel_accumulator.h"

namespace svit::baker {
namespace {

// A pass over two texels: direct `a` and indirect 10 `a` in every channel
// of texel 0, twice that in texel 1.
std::vector<TexelIrradiance> pass(float a) {
  return {{{a, a, a}, {10 * a, 10 * a, 10 * a}}, {{2 * a, 2 * a, 2 * a}, {20 * a, 20 * a, 20 * a}}};
}

TEST(TexelAccumulator, HalvesAreTheMeansOfTheEvenAndTheOddPasses) {
  TexelAccumulator accumulator;
  for (int p = 1; p <= 5; ++p) accumulator.add(pass(float(p * p)));
  ASSERT_EQ(accumulator.passes(), 5u);
  EXPECT_EQ(accumulator.halfPasses(false), 3u);
  EXPECT_EQ(accumulator.halfPasses(true), 2u);
  // Passes 0, 2, 4 carry 1, 9, 25 (mean 35 / 3); passes 1, 3 carry 4, 16
  // (mean 10); all five 11.
  const std::vector<TexelIrradiance> even = accumulator.halfMean(false);
  const std::vector<TexelIrradiance> odd = accumulator.halfMean(true);
  const std::vector<TexelIrradiance> all = accumulator.mean();
  EXPECT_FLOAT_EQ(even[0].direct.g, 35.0f / 3.0f);
  EXPECT_FLOAT_EQ(odd[0].direct.g, 10.0f);
  EXPECT_FLOAT_EQ(all[0].direct.g, 11.0f);
  EXPECT_FLOAT_EQ(even[1].indirect.r, 700.0f / 3.0f);
  EXPECT_FLOAT_EQ(odd[1].indirect.b, 200.0f);
  EXPECT_FLOAT_EQ(accumulator.halfDifference()[1].direct.g, 70.0f / 3.0f - 20.0f);
}

TEST(TexelAccumulator, UnequalHalvesAndAnAccumulatorRebuiltFromItsSums) {
  TexelAccumulator accumulator;
  accumulator.add(pass(1));
  accumulator.add(pass(4));                                        // an odd pass
  accumulator.add(pass(7));                                        // an even one
  EXPECT_FLOAT_EQ(accumulator.halfMean(false)[0].direct.r, 4.0f);  // (1 + 7) / 2
  EXPECT_FLOAT_EQ(accumulator.halfMean(true)[0].direct.r, 4.0f);
  accumulator.add(pass(10));                                      // odd
  EXPECT_FLOAT_EQ(accumulator.halfMean(true)[0].direct.r, 7.0f);  // (4 + 10) / 2
  EXPECT_FLOAT_EQ(accumulator.halfMean(true)[1].indirect.g, 140.0f);

  const TexelAccumulator rebuilt(accumulator.sums(), accumulator.oddSums(),
                                 accumulator.quarterSums(), accumulator.passes());
  for (bool odd : {false, true}) {
    EXPECT_FLOAT_EQ(rebuilt.halfMean(odd)[1].direct.b, accumulator.halfMean(odd)[1].direct.b);
    EXPECT_EQ(rebuilt.halfPasses(odd), accumulator.halfPasses(odd));
  }
  EXPECT_FLOAT_EQ(rebuilt.mean()[0].indirect.r, accumulator.mean()[0].indirect.r);
  EXPECT_FLOAT_EQ(rebuilt.quarterDifference(true)[0].direct.g,
                  accumulator.quarterDifference(true)[0].direct.g);
}

TEST(TexelAccumulator, QuartersSplitEachHalfInTwo) {
  TexelAccumulator accumulator;
  EXPECT_EQ(accumulator.quarterDifference(false).size(), 0u);
  for (int p = 1; p <= 7; ++p) accumulator.add(pass(float(p * p)));
  // Passes 0..6 carry 1, 4, 9, 16, 25, 36, 49: quarter 0 is passes 0 and 4
  // (mean 13), quarter 2 passes 2 and 6 (29), quarter 1 passes 1 and 5
  // (20), quarter 3 pass 3 (16).
  EXPECT_EQ(accumulator.quarterPasses(0), 2u);
  EXPECT_EQ(accumulator.quarterPasses(2), 2u);
  EXPECT_EQ(accumulator.quarterPasses(1), 2u);
  EXPECT_EQ(accumulator.quarterPasses(3), 1u);
  EXPECT_FLOAT_EQ(accumulator.quarterDifference(false)[0].direct.r, 13.0f - 29.0f);
  EXPECT_FLOAT_EQ(accumulator.quarterDifference(true)[1].indirect.b, 20.0f * (20.0f - 16.0f));
  TexelAccumulator three;
  for (int p = 1; p <= 3; ++p) three.add(pass(float(p)));
  EXPECT_EQ(three.quarterPasses(3), 0u);
  EXPECT_FLOAT_EQ(three.quarterDifference(true)[0].direct.r, 0.0f);  // no quarter 3 yet
}

}  // namespace
}  // namespace svit::baker

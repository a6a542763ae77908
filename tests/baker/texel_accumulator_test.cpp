// TexelAccumulator (texel_accumulator.h): the mean of the passes, the mean
// of each parity's half (what the split-half error estimate compares), and
// an accumulator rebuilt from its sums (a sharded bake's merge) giving the
// same means.

#include <gtest/gtest.h>

#include <vector>

#include "texel_accumulator.h"

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

  const TexelAccumulator rebuilt(accumulator.sums(), accumulator.oddSums(), accumulator.passes());
  for (bool odd : {false, true}) {
    EXPECT_FLOAT_EQ(rebuilt.halfMean(odd)[1].direct.b, accumulator.halfMean(odd)[1].direct.b);
    EXPECT_EQ(rebuilt.halfPasses(odd), accumulator.halfPasses(odd));
  }
  EXPECT_FLOAT_EQ(rebuilt.mean()[0].indirect.r, accumulator.mean()[0].indirect.r);
}

}  // namespace
}  // namespace svit::baker

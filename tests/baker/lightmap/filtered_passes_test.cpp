// The lightmap filter of the indirect light, guided by each texel's noise
// and applied to each half of the passes on its own (filtered_passes.h,
// lightmap_pages.h): it smooths noise and leaves an edge of the light (a
// contact shadow, the sky's edge under a roof) sharp; the filtered halves'
// difference still measures the noise it leaves, and the product of the
// halves' shifts its bias.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "baker/lightmap_test_util.h"
#include "lightmap/filtered_passes.h"
#include "lightmap/texel_accumulator.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/ray_caster.h"
#include "util/random.h"

namespace svit::baker {
namespace {

// A quad of 56 x 56 texels, one chart, whose indirect light steps from 100
// lux (x < 0.5 m) to 10 (a shadow's edge), each of `passes` passes with
// noise: Gaussian of 20 % of the light, or with `fireflies`, heavy-tailed as
// a final gather's (one pass in 20 finds a bright surface: 10 times the
// light, the others 0.53 of it; the same mean, 2.1 times it per pass).
struct SteppedLight {
  test::HandMapped quad = test::handMappedQuad(64, 0.0625f, 0.875f);
  TexelSet texels;
  TexelAccumulator accumulator;
  double truth(size_t i) const { return texels.samples[i].position.x < 0.5f ? 100.0 : 10.0; }
};

std::unique_ptr<SteppedLight> steppedLight(uint32_t passes, bool fireflies = false) {
  auto s = std::make_unique<SteppedLight>();
  std::unique_ptr<RayCaster> caster = makeBruteForceCaster(s->quad.geometry);
  s->texels = std::move(rasterizeTexels(s->quad.geometry, s->quad.atlas, *caster, {})).value();
  Rng rng(7);
  for (uint32_t p = 0; p < passes; ++p) {
    std::vector<TexelIrradiance> pass(s->texels.samples.size());
    for (size_t i = 0; i < pass.size(); ++i) {
      // Box-Muller: a deterministic standard normal.
      const double u1 = std::max(rng.uniformDouble(), 1e-12), u2 = rng.uniformDouble();
      const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
      const double firefly = (1.0 - 0.05 * 10.0) / 0.95;
      const double factor =
          fireflies ? (rng.uniformDouble() < 0.05 ? 10.0 : firefly) : 1.0 + 0.2 * z;
      const float v = float(s->truth(i) * factor);
      pass[i].indirect = {v, v, v};
    }
    s->accumulator.add(pass);
  }
  return s;
}

// The pages' texel i (no direct light: the indirect, as filtered).
double pageValue(const LightmapPages& pages, const TexelSample& s) {
  return pages.images[s.page].texel(int(s.x), int(s.y)).g;
}

struct Errors {
  double edge_bias = 0;  ///< worst mean relative error of a column within 2 texels of the edge
  double flat_rms = 0;   ///< relative RMS error of the texels 8 or more texels from it
};

Errors errorsOf(const SteppedLight& s, const std::vector<TexelIrradiance>& lighting) {
  PageSettings plain;
  const LightmapPages pages =
      buildLightmapPages(s.quad.geometry, s.quad.atlas, s.texels, lighting, plain);
  const double texel_m = 1.0 / 56.0;
  std::vector<double> column_error(64, 0.0), column_count(64, 0.0);
  double flat_squares = 0, flat_count = 0;
  for (size_t i = 0; i < s.texels.samples.size(); ++i) {
    const TexelSample& t = s.texels.samples[i];
    const double relative = (pageValue(pages, t) - s.truth(i)) / s.truth(i);
    const double from_edge = std::abs(t.position.x - 0.5) / texel_m;
    if (from_edge < 2) {
      column_error[t.x] += relative;
      column_count[t.x] += 1;
    } else if (from_edge >= 8) {
      flat_squares += relative * relative;
      flat_count += 1;
    }
  }
  Errors e;
  for (size_t x = 0; x < 64; ++x) {
    if (column_count[x] > 0)
      e.edge_bias = std::max(e.edge_bias, std::abs(column_error[x] / column_count[x]));
  }
  e.flat_rms = std::sqrt(flat_squares / flat_count);
  return e;
}

PageSettings filterOn() {
  PageSettings settings;
  settings.edge_aware_filter = true;
  return settings;
}

// The mean filtered by `guide` as one filter (not half by half).
std::vector<TexelIrradiance> filteredMean(const SteppedLight& s, const FilterGuide& guide) {
  PageSettings settings = filterOn();
  settings.guide = std::make_shared<FilterGuide>(guide);
  std::vector<TexelIrradiance> mean = s.accumulator.mean();
  const std::vector<Rgb> indirect = filterIndirect(s.quad.atlas, s.texels, mean, settings);
  for (size_t i = 0; i < mean.size(); ++i) mean[i].indirect = indirect[i];
  return mean;
}

// The mean's own guide: its luminance, and its standard error from the
// halves' difference (what the filter used before it went half by half).
FilterGuide selfGuide(const SteppedLight& s) {
  FilterGuide guide = halfGuide(s.quad.atlas, s.texels, s.accumulator, false, 2);
  const std::vector<TexelIrradiance> mean = s.accumulator.mean();
  const double n_even = s.accumulator.halfPasses(false), n = s.accumulator.passes();
  for (size_t i = 0; i < mean.size(); ++i) {
    guide.luminance[i] = mean[i].indirect.g;
    guide.sigma[i] *= float(std::sqrt(n_even / n));  // the even half's to the mean's
  }
  return guide;
}

// The split-half estimate of `difference` (flat texels), as lightmap_error.cpp scales it.
double flatSplitHalf(const SteppedLight& s, const std::vector<TexelIrradiance>& difference) {
  const double texel_m = 1.0 / 56.0;
  const double n_even = s.accumulator.halfPasses(false), n_odd = s.accumulator.halfPasses(true);
  double squares = 0, count = 0;
  for (size_t i = 0; i < s.texels.samples.size(); ++i) {
    if (std::abs(s.texels.samples[i].position.x - 0.5) / texel_m < 8) continue;
    const double relative = difference[i].indirect.g / s.truth(i);
    squares += relative * relative;
    count += 1;
  }
  return std::sqrt(squares / count) * std::sqrt(n_even * n_odd) / (n_even + n_odd);
}

TEST(FilteredPasses, SmoothNoiseAndKeepAnEdgeOfTheLightSharp) {
  const std::unique_ptr<SteppedLight> s = steppedLight(8);
  const FilteredPasses passes = filterPasses(s->quad.atlas, s->texels, s->accumulator, filterOn());
  ASSERT_TRUE(passes.filtered);
  // The same filter blind to noise (every neighbour within its noise).
  FilterGuide everything_noise = selfGuide(*s);
  for (float& sigma : everything_noise.sigma) sigma = 1e30f;
  const Errors none = errorsOf(*s, s->accumulator.mean()), with = errorsOf(*s, passes.mean),
               without = errorsOf(*s, filteredMean(*s, everything_noise));
  std::printf("edge bias: unfiltered %.3f, guided %.3f, blind %.3f; flat RMS: %.4f, %.4f, %.4f\n",
              none.edge_bias, with.edge_bias, without.edge_bias, none.flat_rms, with.flat_rms,
              without.flat_rms);
  // 8 passes of 20 % noise: 7 % a texel unfiltered.
  EXPECT_NEAR(none.flat_rms, 0.2 / std::sqrt(8.0), 0.01);
  EXPECT_LT(with.flat_rms, 0.5 * none.flat_rms);  // the noise smoothed
  EXPECT_LT(with.edge_bias, 0.05);                // the edge left where it is
  EXPECT_GT(without.edge_bias, 0.5);              // what a blind filter does to it
}

// Heavy-tailed noise, as a final gather's: the split-half of the halves
// filtered each on its own is within 1.5 times the filtered mean's true
// error; the same filter guided by the mean itself leaves more noise than
// its halves show.
TEST(FilteredPasses, HalvesStillMeasureTheNoiseLeftUnderFireflies) {
  const std::unique_ptr<SteppedLight> s = steppedLight(16, true);
  const FilteredPasses passes = filterPasses(s->quad.atlas, s->texels, s->accumulator, filterOn());
  const Errors none = errorsOf(*s, s->accumulator.mean());
  const Errors halves = errorsOf(*s, passes.mean);
  const double halves_estimate = flatSplitHalf(*s, passes.difference);
  // Self-guided: the mean and the halves' difference through one filter.
  const FilterGuide self = selfGuide(*s);
  const Errors self_guided = errorsOf(*s, filteredMean(*s, self));
  PageSettings self_settings = filterOn();
  self_settings.guide = std::make_shared<FilterGuide>(self);
  std::vector<TexelIrradiance> difference = s->accumulator.halfDifference();
  const std::vector<Rgb> filtered_difference =
      filterIndirect(s->quad.atlas, s->texels, difference, self_settings);
  for (size_t i = 0; i < difference.size(); ++i) difference[i].indirect = filtered_difference[i];
  const double self_estimate = flatSplitHalf(*s, difference);
  std::printf(
      "flat RMS: unfiltered %.4f (split-half %.4f), half by half %.4f (%.4f), "
      "self-guided %.4f (%.4f)\n",
      none.flat_rms, flatSplitHalf(*s, s->accumulator.halfDifference()), halves.flat_rms,
      halves_estimate, self_guided.flat_rms, self_estimate);
  EXPECT_LT(halves.flat_rms, 0.8 * none.flat_rms);
  EXPECT_GT(halves_estimate, halves.flat_rms / 1.5);
  EXPECT_LT(halves_estimate, halves.flat_rms * 1.5);
  EXPECT_LT(self_estimate, 0.85 * self_guided.flat_rms);  // why the halves go on their own
}

// A filter blind to noise smears the step: the halves' shifts' product
// reads that smear's square (the bias no halves' difference sees).
TEST(FilteredPasses, TheHalvesShiftsProductReadsTheFiltersBias) {
  const std::unique_ptr<SteppedLight> s = steppedLight(16);
  PageSettings blind = filterOn();
  blind.filter_noise_sigmas = 1e15;  // every neighbour within the noise
  const FilteredPasses passes = filterPasses(s->quad.atlas, s->texels, s->accumulator, blind);
  // The smear of the noiseless step by the same weights (all 1 but the
  // spatial and the normal ones, which the light does not change).
  std::vector<TexelIrradiance> truth(s->texels.samples.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    const float v = float(s->truth(i));
    truth[i].indirect = {v, v, v};
  }
  PageSettings truth_settings = blind;
  truth_settings.guide = std::make_shared<FilterGuide>(
      halfGuide(s->quad.atlas, s->texels, s->accumulator, false, blind.filter_radius_texels));
  const std::vector<Rgb> smeared = filterIndirect(s->quad.atlas, s->texels, truth, truth_settings);
  double bias_squares = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double shift = double(smeared[i].g) - s->truth(i);
    bias_squares += shift * shift;
  }
  std::printf("bias^2: estimated %.4g, of the noiseless step %.4g\n", passes.bias_squares,
              bias_squares);
  EXPECT_GT(bias_squares, 1e3);  // the smear is there
  EXPECT_NEAR(passes.bias_squares / bias_squares, 1.0, 0.2);
  // The guided filter barely moves the edge: far less bias.
  const FilteredPasses guided = filterPasses(s->quad.atlas, s->texels, s->accumulator, filterOn());
  EXPECT_LT(guided.bias_squares, 0.05 * bias_squares);
}

TEST(FilteredPasses, NoFilterWithFewerThanFourPassesNorWithoutAGuide) {
  const std::unique_ptr<SteppedLight> s = steppedLight(3);
  const FilteredPasses passes = filterPasses(s->quad.atlas, s->texels, s->accumulator, filterOn());
  EXPECT_FALSE(passes.filtered);
  const std::vector<TexelIrradiance> mean = s->accumulator.mean();
  const LightmapPages pages =
      buildLightmapPages(s->quad.geometry, s->quad.atlas, s->texels, mean, filterOn());
  for (size_t i = 0; i < s->texels.samples.size(); ++i) {
    ASSERT_EQ(passes.mean[i].indirect.g, mean[i].indirect.g) << "texel " << i;
    ASSERT_EQ(pageValue(pages, s->texels.samples[i]), mean[i].indirect.g) << "texel " << i;
  }
}

}  // namespace
}  // namespace svit::baker

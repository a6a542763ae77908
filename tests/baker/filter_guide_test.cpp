// The lightmap filter of the indirect light, guided by each texel's noise
// (filter_guide.h, lightmap_pages.h): it smooths noise and leaves an edge
// of the light (a contact shadow, the sky's edge under a roof) sharp.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "svit/baker/lightmap_pages.h"
#include "svit/baker/ray_caster.h"
#include "filter_guide.h"
#include "lightmap_test_util.h"
#include "random.h"
#include "texel_accumulator.h"

namespace svit::baker {
namespace {

// A quad of 56 x 56 texels, one chart, whose indirect light steps from 100
// lux (x < 0.5 m) to 10 (a shadow's edge), each of `passes` passes with
// Gaussian noise of 20 % of the light.
struct SteppedLight {
  test::HandMapped quad = test::handMappedQuad(64, 0.0625f, 0.875f);
  TexelSet texels;
  TexelAccumulator accumulator;
  double truth(size_t i) const { return texels.samples[i].position.x < 0.5f ? 100.0 : 10.0; }
};

std::unique_ptr<SteppedLight> steppedLight(uint32_t passes) {
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
      const float v = float(s->truth(i) * (1.0 + 0.2 * z));
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

Errors errorsOf(const SteppedLight& s, const PageSettings& settings) {
  const LightmapPages pages =
      buildLightmapPages(s.quad.geometry, s.quad.atlas, s.texels, s.accumulator.mean(), settings);
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

TEST(FilterGuide, SmoothsNoiseAndKeepsAnEdgeOfTheLightSharp) {
  const std::unique_ptr<SteppedLight> s = steppedLight(8);
  PageSettings plain;
  PageSettings guided;
  guided.edge_aware_filter = true;
  guided.guide = filterGuide(s->quad.atlas, s->texels, s->accumulator, guided.filter_radius_texels);
  ASSERT_NE(guided.guide, nullptr);
  // The same filter blind to noise (every neighbour within its noise).
  PageSettings blind = guided;
  auto everything_noise = std::make_shared<FilterGuide>(*guided.guide);
  for (float& sigma : everything_noise->sigma) sigma = 1e30f;
  blind.guide = everything_noise;
  const Errors none = errorsOf(*s, plain), with = errorsOf(*s, guided),
               without = errorsOf(*s, blind);
  std::printf("edge bias: unfiltered %.3f, guided %.3f, blind %.3f; flat RMS: %.4f, %.4f, %.4f\n",
              none.edge_bias, with.edge_bias, without.edge_bias, none.flat_rms, with.flat_rms,
              without.flat_rms);
  // 8 passes of 20 % noise: 7 % a texel unfiltered.
  EXPECT_NEAR(none.flat_rms, 0.2 / std::sqrt(8.0), 0.01);
  EXPECT_LT(with.flat_rms, 0.5 * none.flat_rms);  // the noise smoothed
  EXPECT_LT(with.edge_bias, 0.05);                // the edge left where it is
  EXPECT_GT(without.edge_bias, 0.5);              // what a blind filter does to it
}

TEST(FilterGuide, NoGuideWithFewerThanTwoPassesAndNoFilterWithoutOne) {
  const std::unique_ptr<SteppedLight> s = steppedLight(1);
  EXPECT_EQ(filterGuide(s->quad.atlas, s->texels, s->accumulator, 2), nullptr);
  PageSettings unguided;
  unguided.edge_aware_filter = true;
  const LightmapPages pages = buildLightmapPages(s->quad.geometry, s->quad.atlas, s->texels,
                                                 s->accumulator.mean(), unguided);
  const std::vector<TexelIrradiance> mean = s->accumulator.mean();
  for (size_t i = 0; i < s->texels.samples.size(); ++i)
    ASSERT_EQ(pageValue(pages, s->texels.samples[i]), mean[i].indirect.g) << "texel " << i;
}

}  // namespace
}  // namespace svit::baker

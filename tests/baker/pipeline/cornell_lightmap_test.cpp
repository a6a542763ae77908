// Lightmaps through the library stages: the Cornell box has finite texels,
// no empty texel within reach of a bilinear lookup at any sample point, and
// reflected flux consistent with the radiosity solver; smooth UV seams agree.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "baker/test_scenes.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/texel_lighting.h"
#include "svit/level.h"

namespace svit::baker {
namespace {

struct CornellBake {
  Scene scene;
  BakeGeometry geometry;
  std::unique_ptr<RayCaster> caster;
  std::unique_ptr<RadiositySolver> solver;
  LightmapAtlas atlas;
  TexelSet texels;
  std::vector<TexelIrradiance> lighting;
  LightmapPages pages;
};

// One bake shared by the tests of this file (it takes a few seconds).
const CornellBake& cornell() {
  static const std::unique_ptr<CornellBake> bake = [] {
    auto b = std::make_unique<CornellBake>();
    b->scene = std::move(loadLevel(SVIT_CORNELL_GLTF)).value();
    b->geometry = std::move(flattenStaticGeometry(b->scene)).value();
    b->caster = std::move(makeEmbreeCaster(b->geometry)).value();
    RadiositySettings settings;
    b->solver =
        std::move(RadiositySolver::create(b->scene, b->geometry, *b->caster, settings)).value();
    StopRule stop;
    stop.max_passes = 6;
    EXPECT_TRUE(b->solver->improve(stop).ok());
    AtlasSettings atlas_settings;
    atlas_settings.texels_per_m = 24;
    b->atlas = std::move(buildLightmapAtlas(b->scene, b->geometry, atlas_settings)).value();
    b->texels =
        std::move(rasterizeTexels(b->geometry, b->atlas, *b->caster, RasterSettings{})).value();
    TexelLightingSettings lighting;
    lighting.gather_rays = 256;
    b->lighting =
        std::move(lightTexels(b->scene, b->geometry, *b->caster, *b->solver, b->texels, lighting))
            .value();
    PageSettings page_settings;
    b->pages = buildLightmapPages(b->geometry, b->atlas, b->texels, b->lighting, page_settings);
    return b;
  }();
  return *bake;
}

TEST(CornellLightmap, EveryTexelIsFinite) {
  const CornellBake& b = cornell();
  for (const LightmapImage& page : b.pages.images) {
    for (float v : page.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  }
}

TEST(CornellLightmap, BilinearLookupsAtSurfacePointsReadOnlyFilledTexels) {
  // Every covered texel's sample point, and 9 points inside every triangle:
  // the 2x2 texels a bilinear lookup reads must all be filled (covered or
  // dilated). Points under the boxes are excluded: their texels are dropped
  // on purpose (no light leaks under objects resting on the floor).
  const CornellBake& b = cornell();
  const int w = b.texels.page_width, h = b.texels.page_height;
  auto footprintFilled = [&](uint32_t page, Vec2 uv) {
    const float x = uv.x * float(w) - 0.5f, y = uv.y * float(h) - 0.5f;
    const int x0 = std::clamp(int(std::floor(x)), 0, w - 1),
              y0 = std::clamp(int(std::floor(y)), 0, h - 1);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const auto& valid = b.pages.valid[page];
    return valid[size_t(y0) * size_t(w) + size_t(x0)] &&
           valid[size_t(y0) * size_t(w) + size_t(x1)] &&
           valid[size_t(y1) * size_t(w) + size_t(x0)] && valid[size_t(y1) * size_t(w) + size_t(x1)];
  };
  size_t checked = 0, unfilled = 0;
  for (const TexelSample& s : b.texels.samples) {
    const Vec2* uv = &b.atlas.triangle_uv[size_t(s.triangle) * 3];
    const Vec2 p{(1 - s.u - s.v) * uv[0].x + s.u * uv[1].x + s.v * uv[2].x,
                 (1 - s.u - s.v) * uv[0].y + s.u * uv[1].y + s.v * uv[2].y};
    ++checked;
    if (!footprintFilled(s.page, p)) ++unfilled;
  }
  std::printf("%zu sample points checked, %zu read an empty texel\n", checked, unfilled);
  EXPECT_EQ(unfilled, 0u);
}

TEST(LightmapSeams, SmoothSeamsAgree) {
  // A floor of 3x3 separate quads (separate objects, so separate charts)
  // under a point light: their shared edges are UV seams on a flat surface.
  // After stitching, bilinear reads at matching points on both sides agree.
  test::SceneBuilder builder;
  const int grey = builder.material({0.5f, 0.5f, 0.5f});
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const float x0 = float(i), x1 = float(i + 1), z0 = float(j), z1 = float(j + 1);
      builder.addQuad("tile", {x0, 0, z0}, {x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}, grey);
    }
  }
  builder.addPointLight({1.2f, 1.0f, 1.7f}, 100.0f);
  const Scene& scene = builder.scene();
  const BakeGeometry geometry = std::move(flattenStaticGeometry(scene)).value();
  const std::unique_ptr<RayCaster> caster = std::move(makeEmbreeCaster(geometry)).value();
  const std::unique_ptr<RadiositySolver> solver =
      std::move(RadiositySolver::create(scene, geometry, *caster, RadiositySettings{})).value();
  StopRule stop;
  stop.max_passes = 2;
  ASSERT_TRUE(solver->improve(stop).ok());
  AtlasSettings atlas_settings;
  atlas_settings.texels_per_m = 16;
  const LightmapAtlas atlas =
      std::move(buildLightmapAtlas(scene, geometry, atlas_settings)).value();
  const TexelSet texels =
      std::move(rasterizeTexels(geometry, atlas, *caster, RasterSettings{})).value();
  const std::vector<TexelIrradiance> lighting =
      std::move(lightTexels(scene, geometry, *caster, *solver, texels, TexelLightingSettings{}))
          .value();
  const LightmapPages pages = buildLightmapPages(geometry, atlas, texels, lighting, PageSettings{});
  const std::vector<SeamPoint> seam = findSeamPoints(geometry, atlas);
  size_t compared = 0, disagreeing = 0;
  double worst = 0;
  for (const SeamPoint& p : seam) {
    const double ya = luminance(pages.images[p.page_a].sampleBilinear(p.uv_a));
    const double yb = luminance(pages.images[p.page_b].sampleBilinear(p.uv_b));
    ++compared;
    const double difference = std::abs(ya - yb) / std::max(ya, yb);
    worst = std::max(worst, difference);
    if (difference > 0.01) ++disagreeing;
  }
  std::printf("%zu seam points compared, %zu differ by more than 1%%, worst %.2f%%\n", compared,
              disagreeing, 100.0 * worst);
  // 12 shared edges of 1 m at 16 texels/m, 2 points per texel.
  EXPECT_GT(compared, 300u);
  // Unstitched, the two sides differ by up to ~4.5% here (measured); a
  // 1% bound therefore tests the stitching, not the lighting.
  EXPECT_EQ(disagreeing, 0u);
}

TEST(CornellLightmap, ReflectedFluxMatchesTheSolver) {
  // Sum over texels of albedo * E * (the texel's share of its triangle's
  // world area) against the solver's sum over triangles of albedo * E * A.
  const CornellBake& b = cornell();
  const int w = b.texels.page_width, h = b.texels.page_height;
  std::vector<double> uv_area_texels(b.geometry.triangleCount());
  for (size_t t = 0; t < b.geometry.triangleCount(); ++t) {
    const Vec2* uv = &b.atlas.triangle_uv[t * 3];
    uv_area_texels[t] = 0.5 *
                        std::abs(double(uv[1].x - uv[0].x) * (uv[2].y - uv[0].y) -
                                 double(uv[2].x - uv[0].x) * (uv[1].y - uv[0].y)) *
                        w * h;
  }
  // Coverage is shared between triangles in a texel; weight each sample by
  // its winner's area per texel (chart interiors dominate).
  double lightmap = 0;
  for (size_t i = 0; i < b.texels.samples.size(); ++i) {
    const TexelSample& s = b.texels.samples[i];
    const double texel_area = b.geometry.areas_m2[s.triangle] / uv_area_texels[s.triangle];
    const Rgb& albedo = b.geometry.albedo[s.triangle];
    const TexelIrradiance& e = b.lighting[i];
    const Rgb total{e.direct.r + e.indirect.r, e.direct.g + e.indirect.g,
                    e.direct.b + e.indirect.b};
    lightmap += luminance({albedo.r * total.r, albedo.g * total.g, albedo.b * total.b}) *
                s.coverage * texel_area;
  }
  const std::vector<Rgb> irradiance = b.solver->triangleIrradiance(true);
  double solver = 0;
  for (size_t t = 0; t < b.geometry.triangleCount(); ++t) {
    const Rgb& a = b.geometry.albedo[t];
    solver += luminance({a.r * irradiance[t].r, a.g * irradiance[t].g, a.b * irradiance[t].b}) *
              b.geometry.areas_m2[t];
  }
  std::printf("reflected flux: lightmap %.4f lm, solver %.4f lm (%+.2f%%)\n", lightmap, solver,
              100.0 * (lightmap / solver - 1.0));
  EXPECT_NEAR(lightmap, solver, 0.01 * solver);
}

}  // namespace
}  // namespace svit::baker

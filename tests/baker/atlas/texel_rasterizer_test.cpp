// Exact texel rasterization of a lightmap atlas (rasterizeTexels,
// lightmap_atlas.h; texel_rasterizer.cpp): texel-centre samples, partial
// edge texels whose coverage sums to the UV area, texels under solid
// geometry dropped or moved out, and mismatched atlases rejected.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "baker/lightmap_test_util.h"
#include "baker/test_scenes.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

using test::addSolidBox;
using test::flatten;
using test::HandMapped;
using test::handMappedQuad;
using test::SceneBuilder;

TEST(TexelRasterizer, QuadCoveringFourByFourTexelsSamplesTexelCentres) {
  // Page 8x8, quad at UV [0.25, 0.75]^2 = texels 2..5 exactly (all values
  // exact in float).
  HandMapped h = handMappedQuad(8, 0.25f, 0.5f);
  std::unique_ptr<RayCaster> caster = makeBruteForceCaster(h.geometry);
  Expected<TexelSet> set = rasterizeTexels(h.geometry, h.atlas, *caster, RasterSettings{});
  ASSERT_TRUE(set.ok()) << set.status().message();
  ASSERT_EQ(set->samples.size(), 16u);
  for (const TexelSample& s : set->samples) {
    EXPECT_GE(s.x, 2u);
    EXPECT_LE(s.x, 5u);
    EXPECT_GE(s.y, 2u);
    EXPECT_LE(s.y, 5u);
    EXPECT_FLOAT_EQ(s.coverage, 1.0f);
    // Texel centre (x + 0.5) / 8 in UV -> world (uv - 0.25) / 0.5; the
    // diagonal texels too (the texel-wide centroid lies on the shared edge).
    EXPECT_NEAR(s.position.x, ((s.x + 0.5) / 8.0 - 0.25) / 0.5, 1e-6) << s.x << "," << s.y;
    EXPECT_NEAR(s.position.y, ((s.y + 0.5) / 8.0 - 0.25) / 0.5, 1e-6) << s.x << "," << s.y;
    EXPECT_FLOAT_EQ(s.position.z, 0.0f);
    EXPECT_FLOAT_EQ(s.normal.z, 1.0f);
    EXPECT_EQ(set->sampleAt(0, s.x, s.y), int32_t(&s - set->samples.data()));
  }
  EXPECT_EQ(std::count(set->texel_to_sample.begin(), set->texel_to_sample.end(), -1), 64 - 16);
}

TEST(TexelRasterizer, EdgeTexelsArePartialAndCoverageSumsToTheUvArea) {
  // One triangle at arbitrary texel positions on a 16x16 page.
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addMesh("tri", {{0, 0, 0}, {2, 0.3f, 0}, {0.7f, 1.9f, 0.2f}}, grey);
  const BakeGeometry geometry = flatten(b.scene());
  LightmapAtlas atlas;
  atlas.page_width = atlas.page_height = 16;
  atlas.page_count = 1;
  atlas.triangle_page = {0};
  atlas.triangle_chart = {0};
  atlas.triangle_uv = {{1.3f / 16, 1.7f / 16}, {13.2f / 16, 3.1f / 16}, {4.1f / 16, 14.6f / 16}};
  std::unique_ptr<RayCaster> caster = makeBruteForceCaster(geometry);
  Expected<TexelSet> set = rasterizeTexels(geometry, atlas, *caster, RasterSettings{});
  ASSERT_TRUE(set.ok()) << set.status().message();
  double coverage = 0;
  size_t partial = 0, full = 0;
  for (const TexelSample& s : set->samples) {
    EXPECT_GT(s.coverage, 0.0f);
    EXPECT_LE(s.coverage, 1.0f);
    coverage += s.coverage;
    (s.coverage < 1.0f ? partial : full)++;
    // Inside the triangle: barycentrics in [0, 1], position on the plane.
    EXPECT_GE(s.u, 0.0f);
    EXPECT_GE(s.v, 0.0f);
    EXPECT_LE(s.u + s.v, 1.0f + 1e-6f);
    const Vec3 a = geometry.corner(0, 0), p1 = geometry.corner(0, 1), p2 = geometry.corner(0, 2);
    const float w = 1.0f - s.u - s.v;
    EXPECT_NEAR(s.position.x, w * a.x + s.u * p1.x + s.v * p2.x, 1e-5);
    EXPECT_NEAR(s.position.y, w * a.y + s.u * p1.y + s.v * p2.y, 1e-5);
    EXPECT_NEAR(s.position.z, w * a.z + s.u * p1.z + s.v * p2.z, 1e-5);
    // The sample's UV lies in its texel.
    const double su = ((1 - s.u - s.v) * 1.3 + s.u * 13.2 + s.v * 4.1);
    const double sv = ((1 - s.u - s.v) * 1.7 + s.u * 3.1 + s.v * 14.6);
    EXPECT_GE(su, s.x - 1e-4);
    EXPECT_LE(su, s.x + 1 + 1e-4);
    EXPECT_GE(sv, s.y - 1e-4);
    EXPECT_LE(sv, s.y + 1 + 1e-4);
  }
  EXPECT_GT(partial, 10u);
  EXPECT_GT(full, 10u);
  // Clipping is exact, so the coverage adds up to the UV area (texel units)
  // up to float storage of each coverage (6e-8 relative).
  const double uv_area = 0.5 * std::fabs((13.2 - 1.3) * (14.6 - 1.7) - (3.1 - 1.7) * (4.1 - 1.3));
  EXPECT_NEAR(coverage / uv_area, 1.0, 1e-4);
}

TEST(TexelRasterizer, FloorTexelsUnderASolidBoxAreBuriedOrMovedOut) {
  // Floor [0,1]^2 (x-z) facing +y on a 10x10 page: texel = 0.1 m, texel
  // (i, j) spans x in [i/10, (i+1)/10], z likewise. A solid box rests on it
  // over [0.33, 0.54]^2: texel 4 is fully under it, texel 3 is 70% under
  // (its centre 0.35 inside), texel 5 is 40% under (centre outside).
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, grey);
  const float lo = 0.33f, hi = 0.54f;
  addSolidBox(b, "box", {lo, 0, lo}, {hi, 0.3f, hi}, grey);
  const BakeGeometry geometry = flatten(b.scene());
  LightmapAtlas atlas;
  atlas.page_width = atlas.page_height = 10;
  atlas.page_count = 2;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const bool floor = geometry.instance[t] == 0;
    atlas.triangle_page.push_back(floor ? 0 : 1);
    atlas.triangle_chart.push_back(uint32_t(geometry.instance[t]));
    // The box's faces are not under test: zero UV area on page 1 (no texels).
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = geometry.corner(t, k);
      atlas.triangle_uv.push_back(floor ? Vec2{p.x, p.z} : Vec2{0.5f, 0.5f});
    }
  }
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(geometry);
  ASSERT_TRUE(caster.ok()) << caster.status().message();

  // Without probes every floor texel keeps its centre, some inside the box.
  RasterSettings no_probes;
  no_probes.leak_probe_texels = 0;
  Expected<TexelSet> plain = rasterizeTexels(geometry, atlas, **caster, no_probes);
  ASSERT_TRUE(plain.ok()) << plain.status().message();
  EXPECT_GE(plain->sampleAt(0, 4, 4), 0);

  Expected<TexelSet> set = rasterizeTexels(geometry, atlas, **caster, RasterSettings{});
  ASSERT_TRUE(set.ok()) << set.status().message();
  EXPECT_EQ(set->sampleAt(0, 4, 4), kBuriedTexel)
      << "the texel wholly under the box is buried (black, never dilated over)";
  size_t floor_samples = 0;
  for (const TexelSample& s : set->samples) {
    if (s.page != 0) continue;
    ++floor_samples;
    const bool under =
        s.position.x > lo && s.position.x < hi && s.position.z > lo && s.position.z < hi;
    EXPECT_FALSE(under) << "texel " << s.x << "," << s.y << " samples (" << s.position.x << ", "
                        << s.position.z << ") under the box";
    EXPECT_EQ(s.position.y, 0.0f);
  }
  EXPECT_EQ(floor_samples, 99u);
  // Texels (3, 3) and (3, 4), their centres under the box, moved out across
  // its -x wall, still in their texel.
  for (uint32_t j = 3; j <= 4; ++j) {
    const int32_t i = set->sampleAt(0, 3, j);
    ASSERT_GE(i, 0);
    const TexelSample& s = set->samples[size_t(i)];
    EXPECT_LT(s.position.x, lo);
    EXPECT_GE(s.position.x, 0.3f);
    EXPECT_GE(s.position.z, j / 10.0f - 1e-6f);
    EXPECT_LE(s.position.z, (j + 1) / 10.0f + 1e-6f);
  }
  // Texel (5, 5), 40% x 40% under, keeps its centre outside the box.
  const int32_t k = set->sampleAt(0, 5, 5);
  ASSERT_GE(k, 0);
  EXPECT_NEAR(set->samples[size_t(k)].position.x, 0.55f, 1e-6);
  EXPECT_NEAR(set->samples[size_t(k)].position.z, 0.55f, 1e-6);
}

TEST(TexelRasterizer, LeakingSamplesLeaveTheSolidRatherThanGoDeeper) {
  // Floor as above under a wide box [0.28, 0.82]^2. Texel (3, 5) lies wholly
  // under it, its centre 0.07 m (< 1 texel) from the -x wall, so a probe
  // sees that wall's back; its far corners are 0.12 m from every wall, out
  // of the probes' reach, but deeper inside: it must be dropped, not moved
  // there. Texels whose centres are farther than a texel from every wall,
  // like (4, 5), are out of the short probes' reach by design and keep
  // their sample (the lighting sees the box's black back faces from it).
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("floor", {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, grey);
  const float lo = 0.28f, hi = 0.82f;
  addSolidBox(b, "box", {lo, 0, lo}, {hi, 0.5f, hi}, grey);
  const BakeGeometry geometry = flatten(b.scene());
  LightmapAtlas atlas;
  atlas.page_width = atlas.page_height = 10;
  atlas.page_count = 2;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const bool floor = geometry.instance[t] == 0;
    atlas.triangle_page.push_back(floor ? 0 : 1);
    atlas.triangle_chart.push_back(uint32_t(geometry.instance[t]));
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = geometry.corner(t, k);
      atlas.triangle_uv.push_back(floor ? Vec2{p.x, p.z} : Vec2{0.5f, 0.5f});
    }
  }
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(geometry);
  ASSERT_TRUE(caster.ok()) << caster.status().message();
  RasterSettings no_probes;
  no_probes.leak_probe_texels = 0;
  Expected<TexelSet> plain = rasterizeTexels(geometry, atlas, **caster, no_probes);
  Expected<TexelSet> set = rasterizeTexels(geometry, atlas, **caster, RasterSettings{});
  ASSERT_TRUE(plain.ok() && set.ok());
  EXPECT_EQ(set->sampleAt(0, 3, 5), kBuriedTexel);
  EXPECT_GE(set->sampleAt(0, 4, 5), 0);
  // Whatever moved went out of the box.
  for (const TexelSample& s : set->samples) {
    if (s.page != 0) continue;
    const TexelSample& before = plain->samples[size_t(plain->sampleAt(0, s.x, s.y))];
    if (std::memcmp(&s.position, &before.position, sizeof s.position) == 0) continue;
    const bool under =
        s.position.x > lo && s.position.x < hi && s.position.z > lo && s.position.z < hi;
    EXPECT_FALSE(under) << "texel " << s.x << "," << s.y << " moved to (" << s.position.x << ", "
                        << s.position.z << "), under the box";
  }
}

TEST(TexelRasterizer, MismatchedAtlasIsRejected) {
  HandMapped h = handMappedQuad(8, 0.25f, 0.5f);
  std::unique_ptr<RayCaster> caster = makeBruteForceCaster(h.geometry);
  LightmapAtlas bad = h.atlas;
  bad.triangle_page[1] = 3;
  Expected<TexelSet> set = rasterizeTexels(h.geometry, bad, *caster, RasterSettings{});
  ASSERT_FALSE(set.ok());
  EXPECT_EQ(set.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(set.status().message().find("face 1 is on page 3"), std::string::npos)
      << set.status().message();
  bad = h.atlas;
  bad.triangle_uv.pop_back();
  EXPECT_FALSE(rasterizeTexels(h.geometry, bad, *caster, RasterSettings{}).ok());
  // A back face of a one-sided triangle.
  bad = h.atlas;
  bad.back_triangles = {0};
  bad.triangle_page.push_back(0);
  bad.triangle_chart.push_back(7);
  for (int k = 0; k < 3; ++k) bad.triangle_uv.push_back(bad.triangle_uv[size_t(k)]);
  set = rasterizeTexels(h.geometry, bad, *caster, RasterSettings{});
  ASSERT_FALSE(set.ok());
  EXPECT_NE(set.status().message().find("back face 0 names triangle 0, not a double-sided"),
            std::string::npos)
      << set.status().message();
}
}  // namespace
}  // namespace svit::baker

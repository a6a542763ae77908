// Lightmap atlas (xatlas and authored TEXCOORD_1) on scenes built in code:
// density, disjoint texels, pages, authored UVs, errors, atlas and texels
// identical for one and two threads, also when xatlas charts in several
// groups. The texel rasterizer is in texel_rasterizer_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "atlas/atlas_instances.h"
#include "atlas/xatlas_unwrap.h"
#include "baker/lightmap_test_util.h"
#include "baker/test_scenes.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

using test::addSolidBox;
using test::flatten;
using test::SceneBuilder;

/// A room with a box and a disk in it: walls, floor and curved-free but
/// varied charts, every chart at least ~16 texels wide at 16 texels/m.
Scene furnishedRoom() {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addRoom("room", {0, 0, 0}, {4, 3, 5}, grey);
  addSolidBox(b, "box", {1, 0, 1}, {2, 1, 2.5f}, grey);
  b.addDisk("lamp", {2, 2.9f, 2.5f}, 1.0f, 24, false, grey);
  return b.scene();
}

/// Adds a second instance of mesh `mesh`, moved by `offset`.
void addInstance(Scene& scene, int mesh, Vec3 offset) {
  Node node;
  node.name = scene.meshes[size_t(mesh)].name + " copy";
  node.mesh = mesh;
  node.world_from_node.m[12] = offset.x;
  node.world_from_node.m[13] = offset.y;
  node.world_from_node.m[14] = offset.z;
  scene.nodes.push_back(node);
  Instance instance;
  instance.node = int(scene.nodes.size() - 1);
  instance.mesh = mesh;
  instance.world_from_object = node.world_from_node;
  scene.instances.push_back(instance);
}

/// UV corners of triangle t in texel units.
void texelCorners(const LightmapAtlas& atlas, size_t t, double x[3], double y[3]) {
  for (int k = 0; k < 3; ++k) {
    x[k] = double(atlas.triangle_uv[t * 3 + size_t(k)].x) * atlas.page_width;
    y[k] = double(atlas.triangle_uv[t * 3 + size_t(k)].y) * atlas.page_height;
  }
}

double texelArea(const LightmapAtlas& atlas, size_t t) {
  double x[3], y[3];
  texelCorners(atlas, t, x, y);
  return 0.5 * std::fabs((x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]));
}

/// Whether (px, py) lies strictly inside triangle t's UVs: farther than
/// 1e-4 texel from every edge, so points on an edge two triangles of a
/// chart share count for neither (the conservative side of an overlap test).
bool strictlyInside(const LightmapAtlas& atlas, size_t t, double px, double py) {
  double x[3], y[3];
  texelCorners(atlas, t, x, y);
  const double twice = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
  if (twice == 0.0) return false;
  for (int k = 0; k < 3; ++k) {
    const int a = k, b = (k + 1) % 3;
    const double ex = x[b] - x[a], ey = y[b] - y[a];
    const double side = (ex * (py - y[a]) - ey * (px - x[a])) * (twice > 0 ? 1.0 : -1.0);
    if (side <= 1e-4 * std::hypot(ex, ey)) return false;
  }
  return true;
}

/// Owner (triangle index, or -1) of each of 4x4 sub-points per texel of each
/// page; fails the test where two triangles cover one sub-point.
std::vector<int64_t> ownerRaster(const LightmapAtlas& atlas, int sub = 4) {
  const int w = atlas.page_width * sub, h = atlas.page_height * sub;
  std::vector<int64_t> owner(size_t(atlas.page_count) * size_t(w) * size_t(h), -1);
  size_t overlaps = 0;
  for (size_t t = 0; t < atlas.triangle_page.size(); ++t) {
    double x[3], y[3];
    texelCorners(atlas, t, x, y);
    const int i0 = std::max(0, int(std::floor(std::min({x[0], x[1], x[2]}) * sub)));
    const int i1 = std::min(w - 1, int(std::ceil(std::max({x[0], x[1], x[2]}) * sub)));
    const int j0 = std::max(0, int(std::floor(std::min({y[0], y[1], y[2]}) * sub)));
    const int j1 = std::min(h - 1, int(std::ceil(std::max({y[0], y[1], y[2]}) * sub)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        if (!strictlyInside(atlas, t, (i + 0.5) / sub, (j + 0.5) / sub)) continue;
        int64_t& o =
            owner[(size_t(atlas.triangle_page[t]) * size_t(h) + size_t(j)) * size_t(w) + size_t(i)];
        if (o >= 0 && overlaps++ < 5)
          ADD_FAILURE() << "triangles " << o << " and " << t << " overlap on page "
                        << atlas.triangle_page[t];
        o = int64_t(t);
      }
    }
  }
  EXPECT_EQ(overlaps, 0u);
  return owner;
}

// The same pages, charts and UVs, bit for bit.
void expectSameAtlas(const LightmapAtlas& a, const LightmapAtlas& b) {
  EXPECT_EQ(a.page_count, b.page_count);
  EXPECT_EQ(a.page_width, b.page_width);
  EXPECT_EQ(a.page_height, b.page_height);
  EXPECT_EQ(a.triangle_page, b.triangle_page);
  EXPECT_EQ(a.triangle_chart, b.triangle_chart);
  ASSERT_EQ(a.triangle_uv.size(), b.triangle_uv.size());
  EXPECT_EQ(
      std::memcmp(a.triangle_uv.data(), b.triangle_uv.data(), a.triangle_uv.size() * sizeof(Vec2)),
      0);
}

TEST(LightmapAtlas, XatlasPlacesEveryTriangleAtTheTexelDensityWithoutOverlap) {
  const Scene scene = furnishedRoom();
  const BakeGeometry geometry = flatten(scene);
  AtlasSettings settings;
  settings.texels_per_m = 16;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, geometry, settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_FALSE(atlas->authored);
  ASSERT_EQ(atlas->page_count, 1);  // ~100 m2 x 256 texels/m2 fits one 2048 page
  EXPECT_LE(atlas->page_width, settings.max_page_size);
  EXPECT_LE(atlas->page_height, settings.max_page_size);
  ASSERT_EQ(atlas->triangle_page.size(), geometry.triangleCount());
  ASSERT_EQ(atlas->triangle_uv.size(), geometry.triangleCount() * 3);
  ASSERT_EQ(atlas->triangle_chart.size(), geometry.triangleCount());
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    EXPECT_LT(atlas->triangle_page[t], uint32_t(atlas->page_count));
    for (int k = 0; k < 3; ++k) {
      const Vec2& uv = atlas->triangle_uv[t * 3 + size_t(k)];
      EXPECT_TRUE(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f) << "triangle " << t;
    }
    // Every chart here is planar, so xatlas maps it isometrically; it then
    // rounds each chart's extents up to whole texels (texel-centre
    // alignment): with the smallest chart side 1 m x 16 texels/m that
    // stretches area by at most (17/16)^2 = 1.13, inside the 20% allowed.
    const double expected =
        double(geometry.areas_m2[t]) * settings.texels_per_m * settings.texels_per_m;
    EXPECT_NEAR(texelArea(*atlas, t) / expected, 1.0, 0.2) << "triangle " << t;
  }
  ownerRaster(*atlas);
  // The two triangles of one wall quad share a chart; different walls do not.
  EXPECT_EQ(atlas->triangle_chart[0], atlas->triangle_chart[1]);
  EXPECT_NE(atlas->triangle_chart[0], atlas->triangle_chart[2]);
}

TEST(LightmapAtlas, TwoInstancesOfOneMeshGetDisjointTexels) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int mesh = b.addQuad("tile", {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, grey);
  addInstance(b.scene(), mesh, {3, 0, 0});
  const BakeGeometry geometry = flatten(b.scene());
  ASSERT_EQ(geometry.triangleCount(), 4u);
  AtlasSettings settings;
  settings.texels_per_m = 16;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(b.scene(), geometry, settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_FALSE(atlas->authored);
  const int sub = 4;
  const std::vector<int64_t> owner = ownerRaster(*atlas, sub);
  // Texels (not just sub-points) touched by each instance must not meet.
  std::set<size_t> texels[2];
  const size_t w = size_t(atlas->page_width) * sub, h = size_t(atlas->page_height) * sub;
  for (size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    const size_t page = i / (w * h), y = (i % (w * h)) / w, x = i % w;
    const size_t texel =
        (page * size_t(atlas->page_height) + y / sub) * size_t(atlas->page_width) + x / sub;
    texels[geometry.instance[size_t(owner[i])]].insert(texel);
  }
  EXPECT_GT(texels[0].size(), 200u);  // ~16 x 16
  EXPECT_GT(texels[1].size(), 200u);
  for (size_t t : texels[0]) EXPECT_EQ(texels[1].count(t), 0u) << "texel " << t << " is shared";
  EXPECT_NE(atlas->triangle_chart[0], atlas->triangle_chart[2]);
}

// A large instance is charted in consecutive pieces: every triangle once,
// none over the piece size, in order.
TEST(LightmapAtlas, RangePiecesCutLargeInstancesIntoConsecutivePieces) {
  const std::vector<InstanceRange> ranges = {{0, 0, 512}, {1, 512, 530}};
  const std::vector<InstanceRange> pieces = rangePieces(ranges, 100);
  ASSERT_EQ(pieces.size(), 7u);  // 512 in 6 pieces of 85-86, 18 whole
  size_t next = 0;
  for (const InstanceRange& p : pieces) {
    EXPECT_EQ(p.first, next);
    EXPECT_GT(p.end, p.first);
    EXPECT_LE(p.end - p.first, 100u);
    EXPECT_EQ(p.instance, p.first < 512 ? 0u : 1u);
    next = p.end;
  }
  EXPECT_EQ(next, 530u);
  EXPECT_EQ(rangePieces(ranges, 0).size(), 2u);
}

// A 2 x 2 m floor of 512 triangles in one mesh, charted in pieces of at
// most 100: every triangle placed at the texel density without overlap,
// and no chart spans two pieces (charts end at piece borders).
TEST(LightmapAtlas, PiecesOfAnInstanceAreChartedApartWithoutOverlap) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  std::vector<Vec3> corners;
  const int n = 16;
  const float step = 2.0f / n;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Vec3 a{i * step, 0, j * step}, c{(i + 1) * step, 0, (j + 1) * step};
      const Vec3 b2{i * step, 0, (j + 1) * step}, d{(i + 1) * step, 0, j * step};
      corners.insert(corners.end(), {a, b2, c, a, c, d});
    }
  }
  b.addMesh("floor", corners, grey);
  const BakeGeometry geometry = flatten(b.scene());
  ASSERT_EQ(geometry.triangleCount(), 512u);
  AtlasSettings settings;
  settings.texels_per_m = 32;
  settings.chart_piece_triangles = 100;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(b.scene(), geometry, settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  ownerRaster(*atlas);
  const std::vector<InstanceRange> pieces = rangePieces(instanceRanges(geometry), 100);
  std::map<uint32_t, size_t> chart_piece;
  for (size_t p = 0; p < pieces.size(); ++p) {
    for (size_t t = pieces[p].first; t < pieces[p].end; ++t) {
      const double expected = double(geometry.areas_m2[t]) * 32.0 * 32.0;
      EXPECT_NEAR(texelArea(*atlas, t) / expected, 1.0, 0.2) << "triangle " << t;
      const auto [it, first] = chart_piece.emplace(atlas->triangle_chart[t], p);
      EXPECT_EQ(it->second, p) << "chart " << it->first << " spans pieces";
    }
  }
  EXPECT_GE(chart_piece.size(), pieces.size());
}

TEST(LightmapAtlas, SmallPagesForceSeveralPages) {
  const Scene scene = furnishedRoom();
  const BakeGeometry geometry = flatten(scene);
  AtlasSettings settings;
  settings.texels_per_m = 8;  // ~100 m2 x 64 = 6400 texels > one 64x64 page
  settings.max_page_size = 64;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, geometry, settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_GE(atlas->page_count, 2);
  EXPECT_LE(atlas->page_width, 64);
  EXPECT_LE(atlas->page_height, 64);
  std::set<uint32_t> used_pages(atlas->triangle_page.begin(), atlas->triangle_page.end());
  EXPECT_EQ(used_pages.size(), size_t(atlas->page_count));
  // A chart lives on one page: chart ids are unique across pages.
  std::vector<int64_t> chart_page;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const uint32_t c = atlas->triangle_chart[t];
    if (chart_page.size() <= c) chart_page.resize(c + 1, -1);
    if (chart_page[c] < 0) chart_page[c] = atlas->triangle_page[t];
    EXPECT_EQ(chart_page[c], int64_t(atlas->triangle_page[t])) << "chart " << c;
  }
  ownerRaster(*atlas);
}

TEST(LightmapAtlas, AuthoredUvsAreKeptAndInstancesGetTheirOwnPage) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int mesh = b.addQuad("panel", {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}, grey);
  // TEXCOORD_1 covering [0.25, 0.75]^2: a quarter of the page for 4 m2.
  Mesh& m = b.scene().meshes[size_t(mesh)];
  for (const Vec3& p : m.positions) m.uv1.push_back({0.25f + p.x * 0.25f, 0.25f + p.z * 0.25f});
  addInstance(b.scene(), mesh, {5, 0, 0});
  const BakeGeometry geometry = flatten(b.scene());
  AtlasSettings settings;
  settings.texels_per_m = 16;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(b.scene(), geometry, settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  EXPECT_TRUE(atlas->authored);
  EXPECT_EQ(atlas->page_count, 2);
  // 16 texels/m x sqrt(4 m2 / 0.25 of the page) = 64 texels a side.
  EXPECT_EQ(atlas->page_width, 64);
  EXPECT_EQ(atlas->page_height, 64);
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    EXPECT_EQ(atlas->triangle_page[t], geometry.instance[t]);
    for (int k = 0; k < 3; ++k) {
      const Vec2 expected = m.uv1[m.indices[geometry.mesh_triangle[t] * 3 + size_t(k)]];
      EXPECT_EQ(atlas->triangle_uv[t * 3 + size_t(k)].x, expected.x);
      EXPECT_EQ(atlas->triangle_uv[t * 3 + size_t(k)].y, expected.y);
    }
  }
  // One chart per instance (the quad is continuous in UV), distinct ids.
  EXPECT_EQ(atlas->triangle_chart[0], atlas->triangle_chart[1]);
  EXPECT_EQ(atlas->triangle_chart[2], atlas->triangle_chart[3]);
  EXPECT_NE(atlas->triangle_chart[0], atlas->triangle_chart[2]);

  // A mesh without TEXCOORD_1 sends the whole scene to xatlas.
  b.addQuad("plain", {0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}, grey);
  const BakeGeometry mixed = flatten(b.scene());
  Expected<LightmapAtlas> fallback = buildLightmapAtlas(b.scene(), mixed, settings);
  ASSERT_TRUE(fallback.ok()) << fallback.status().message();
  EXPECT_FALSE(fallback->authored);
  ownerRaster(*fallback);
}

TEST(LightmapAtlas, BadSettingsAreRejected) {
  const Scene scene = furnishedRoom();
  const BakeGeometry geometry = flatten(scene);
  AtlasSettings settings;
  settings.texels_per_m = 0;
  Expected<LightmapAtlas> a = buildLightmapAtlas(scene, geometry, settings);
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(a.status().message().find("texels_per_m"), std::string::npos) << a.status().message();
  settings.texels_per_m = 16;
  settings.max_page_size = 8;
  Expected<LightmapAtlas> b = buildLightmapAtlas(scene, geometry, settings);
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(b.status().message().find("max_page_size 8"), std::string::npos)
      << b.status().message();
}

TEST(LightmapAtlas, TriangleXatlasDropsIsAnErrorNamingIt) {
  // A well-shaped speck (0.1 mm sides) passes flattenStaticGeometry's
  // relative degeneracy test, but at 1 texel/m its 5e-9 texel^2 are below
  // xatlas's zero-area threshold (FLT_EPSILON in texel units), so xatlas
  // leaves it out of every chart.
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("wall", {0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}, grey);
  b.addMesh("speck", {{1, 1, 1}, {1, 1, 1.0001f}, {1.0001f, 1, 1}}, grey);
  const BakeGeometry geometry = flatten(b.scene());
  ASSERT_EQ(geometry.triangleCount(), 3u);
  AtlasSettings settings;
  settings.texels_per_m = 1;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(b.scene(), geometry, settings);
  ASSERT_FALSE(atlas.ok());
  EXPECT_EQ(atlas.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(atlas.status().message().find("mesh 'speck') triangle 0"), std::string::npos)
      << atlas.status().message();
}

/// A corrugated sheet: `panels` strips folded alternately up and down by
/// 90 degrees (so each strip is a chart of its own), each strip a grid of
/// `grid` x `grid` quads, 0.5 m a side: 2 panels grid^2 triangles.
std::vector<Vec3> corrugatedSheet(int panels, int grid) {
  std::vector<Vec3> corners;
  const float side = 0.5f, step = side / float(grid), rise = side * 0.70710678f;
  for (int p = 0; p < panels; ++p) {
    // Strip p runs from x0 at height y0 to x0 + rise at height y1.
    const float x0 = float(p) * rise, y0 = (p % 2) ? rise : 0.0f, y1 = (p % 2) ? 0.0f : rise;
    for (int i = 0; i < grid; ++i) {
      for (int j = 0; j < grid; ++j) {
        auto at = [&](int a, int b) {
          const float f = float(a) / float(grid);
          return Vec3{x0 + f * rise, y0 + f * (y1 - y0), float(b) * step};
        };
        const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        corners.insert(corners.end(), {a, c, b, a, d, c});
      }
    }
  }
  return corners;
}

TEST(LightmapAtlas, SeveralChartingGroupsPackDisjointAndIdenticallyForOneAndTwoThreads) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int mesh = b.addMesh("sheet", corrugatedSheet(8, 16), grey);  // 4096 triangles
  for (int i = 1; i < 10; ++i) addInstance(b.scene(), mesh, {0, 0, 1.0f * float(i)});
  const BakeGeometry geometry = flatten(b.scene());
  // More than two groups' worth, each instance well inside one group.
  ASSERT_GT(geometry.triangleCount(), 2 * kXatlasGroupTriangles);
  ASSERT_LT(4096u, kXatlasGroupTriangles);
  LightmapAtlas atlases[2];
  for (int run = 0; run < 2; ++run) {
    AtlasSettings settings;
    settings.texels_per_m = 16;
    settings.threads = run + 1;
    Expected<LightmapAtlas> atlas = buildLightmapAtlas(b.scene(), geometry, settings);
    ASSERT_TRUE(atlas.ok()) << atlas.status().message();
    atlases[run] = *atlas;
  }
  expectSameAtlas(atlases[0], atlases[1]);

  const LightmapAtlas& atlas = atlases[1];
  // Instances are charted separately: a chart id names one instance's
  // triangles only, whichever group charted them (ids are atlas-wide).
  std::map<uint32_t, uint32_t> chart_instance;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const auto [it, added] = chart_instance.emplace(atlas.triangle_chart[t], geometry.instance[t]);
    EXPECT_EQ(it->second, geometry.instance[t]) << "chart " << atlas.triangle_chart[t];
  }
  EXPECT_GE(chart_instance.size(), 8u * 10u);  // a chart per strip at least
  // Charts of different groups overlapped in their own layouts; packed,
  // no texel is touched by two charts (padding keeps them apart).
  const int sub = 4;
  const std::vector<int64_t> owner = ownerRaster(atlas, sub);
  const size_t w = size_t(atlas.page_width) * sub, h = size_t(atlas.page_height) * sub;
  std::map<size_t, uint32_t> texel_chart;
  size_t shared = 0;
  for (size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    const size_t page = i / (w * h), y = (i % (w * h)) / w, x = i % w;
    const size_t texel =
        (page * size_t(atlas.page_height) + y / sub) * size_t(atlas.page_width) + x / sub;
    const uint32_t chart = atlas.triangle_chart[size_t(owner[i])];
    const auto [it, added] = texel_chart.emplace(texel, chart);
    if (it->second != chart && shared++ < 5)
      ADD_FAILURE() << "texel " << texel << " is shared by charts " << it->second << " and "
                    << chart;
  }
  EXPECT_EQ(shared, 0u);
  // Every triangle is placed at the density (planar strips: isometric up to
  // the rounding of each chart to whole texels, 9/8 a side at most here).
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const double expected = double(geometry.areas_m2[t]) * 16.0 * 16.0;
    EXPECT_NEAR(texelArea(atlas, t) / expected, 1.0, 0.3) << "triangle " << t;
  }
}

bool sameSample(const TexelSample& a, const TexelSample& b) {
  return a.page == b.page && a.x == b.x && a.y == b.y && a.triangle == b.triangle &&
         std::memcmp(&a.u, &b.u, sizeof a.u) == 0 && std::memcmp(&a.v, &b.v, sizeof a.v) == 0 &&
         std::memcmp(&a.position, &b.position, sizeof a.position) == 0 &&
         std::memcmp(&a.normal, &b.normal, sizeof a.normal) == 0 &&
         std::memcmp(&a.coverage, &b.coverage, sizeof a.coverage) == 0;
}

TEST(LightmapAtlas, AtlasAndTexelsAreIdenticalForOneAndTwoThreads) {
  const Scene scene = furnishedRoom();
  const BakeGeometry geometry = flatten(scene);
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(geometry);
  ASSERT_TRUE(caster.ok()) << caster.status().message();
  LightmapAtlas atlases[2];
  TexelSet sets[2];
  for (int run = 0; run < 2; ++run) {
    AtlasSettings atlas_settings;
    atlas_settings.texels_per_m = 16;
    atlas_settings.threads = run + 1;
    Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, geometry, atlas_settings);
    ASSERT_TRUE(atlas.ok()) << atlas.status().message();
    RasterSettings raster_settings;
    raster_settings.threads = run + 1;
    Expected<TexelSet> set = rasterizeTexels(geometry, *atlas, **caster, raster_settings);
    ASSERT_TRUE(set.ok()) << set.status().message();
    atlases[run] = *atlas;
    sets[run] = *set;
  }
  expectSameAtlas(atlases[0], atlases[1]);
  ASSERT_EQ(sets[0].samples.size(), sets[1].samples.size());
  EXPECT_GT(sets[0].samples.size(), 10000u);
  for (size_t i = 0; i < sets[0].samples.size(); ++i) {
    ASSERT_TRUE(sameSample(sets[0].samples[i], sets[1].samples[i])) << "sample " << i;
  }
  EXPECT_EQ(sets[0].texel_to_sample, sets[1].texel_to_sample);
}

/// A double-sided 2 x 2 m panel over a one-sided 1 x 1 m tile, with
/// TEXCOORD_1 on both when `authored`.
Scene panelAndTile(bool authored) {
  SceneBuilder b;
  const int one_sided = b.material({0.5f, 0.5f, 0.5f});
  const int two_sided = b.material({0.5f, 0.5f, 0.5f}, {0, 0, 0}, true);
  const int panel = b.addQuad("panel", {0, 1, 0}, {0, 1, 2}, {2, 1, 2}, {2, 1, 0}, two_sided);
  const int tile = b.addQuad("tile", {0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, one_sided);
  if (authored) {
    Mesh& p = b.scene().meshes[size_t(panel)];
    for (const Vec3& q : p.positions) p.uv1.push_back({0.05f + q.x * 0.2f, 0.05f + q.z * 0.2f});
    Mesh& t = b.scene().meshes[size_t(tile)];
    for (const Vec3& q : t.positions) t.uv1.push_back({0.6f + q.x * 0.3f, 0.6f + q.z * 0.3f});
  }
  return b.scene();
}

// A lightmap per side: the double-sided panel's back is a face of its own,
// with texels no front shares (xatlas) or the same UVs on a twin page
// (authored), its samples on the panel with the normal turned over.
TEST(LightmapAtlas, DoubleSidedTrianglesGetABackOfTheirOwn) {
  for (const bool authored : {false, true}) {
    SCOPED_TRACE(authored ? "authored" : "xatlas");
    const Scene scene = panelAndTile(authored);
    const BakeGeometry geometry = flatten(scene);
    ASSERT_EQ(geometry.triangleCount(), 4u);
    AtlasSettings settings;
    settings.texels_per_m = 16;
    Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, geometry, settings);
    ASSERT_TRUE(atlas.ok()) << atlas.status().message();
    EXPECT_EQ(atlas->authored, authored);
    EXPECT_EQ(atlas->back_triangles, (std::vector<uint32_t>{0, 1}));
    ASSERT_EQ(atlas->faceCount(), 6u);
    EXPECT_EQ(atlas->face(0, 1), 4u);
    EXPECT_EQ(atlas->face(1, 1), 5u);
    EXPECT_EQ(atlas->face(2, 1), 2u);  // one-sided: the front serves both
    EXPECT_EQ(atlas->faceTriangle(5), 1u);
    for (uint32_t t : {0u, 1u}) {
      EXPECT_NEAR(texelArea(*atlas, atlas->face(t, 1)), texelArea(*atlas, t),
                  1e-3 * texelArea(*atlas, t));
      EXPECT_NE(atlas->triangle_chart[atlas->face(t, 1)], atlas->triangle_chart[t]);
    }
    if (authored) {
      EXPECT_EQ(atlas->page_count, 2);  // the panel's page and its back's twin
      EXPECT_EQ(atlas->triangle_page[4], 1u);
      EXPECT_EQ(atlas->triangle_uv[4 * 3 + 1].x, atlas->triangle_uv[0 * 3 + 1].x);
    } else {
      ownerRaster(*atlas);  // no two faces share a sub-texel point
    }
    Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(geometry);
    ASSERT_TRUE(caster.ok()) << caster.status().message();
    Expected<TexelSet> set = rasterizeTexels(geometry, *atlas, **caster, RasterSettings{});
    ASSERT_TRUE(set.ok()) << set.status().message();
    size_t backs = 0, fronts_of_panel = 0;
    for (const TexelSample& s : set->samples) {
      EXPECT_EQ(s.triangle, atlas->faceTriangle(s.face));
      EXPECT_EQ(s.page, atlas->triangle_page[s.face]);
      if (atlas->isBack(s.face)) {
        ++backs;
        EXPECT_EQ(s.normal.y, -1.0f) << "a back sample faces down";
      } else if (s.triangle < 2) {
        ++fronts_of_panel;
        EXPECT_EQ(s.normal.y, 1.0f);
      }
    }
    EXPECT_GE(backs, 900u);  // 4 m2 at 16 texels/m: ~1024 a side (authored: 30 x 30)
    EXPECT_NEAR(double(backs), double(fronts_of_panel), 0.05 * double(fronts_of_panel));
  }
}

}  // namespace
}  // namespace svit::baker

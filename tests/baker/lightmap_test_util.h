#pragma once
// Helpers of the lightmap atlas and texel rasterizer tests: solid boxes,
// flattened static geometry, and a hand-mapped quad with an atlas of its own.

#include <gtest/gtest.h>

#include <string>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "test_scenes.h"

namespace svit::test {

using baker::BakeGeometry;
using baker::LightmapAtlas;

/// Axis-aligned solid box [lo, hi]: addRoom's faces turned outwards.
inline void addSolidBox(SceneBuilder& b, const std::string& name, Vec3 lo, Vec3 hi, int material) {
  const float x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
  auto quad = [&](const std::string& face, Vec3 p, Vec3 q, Vec3 r, Vec3 s) {
    b.addQuad(name + face, p, s, r, q, material);
  };
  quad(" bottom", {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0});
  quad(" top", {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1});
  quad(" -x", {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1});
  quad(" +x", {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0});
  quad(" -z", {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0});
  quad(" +z", {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1});
}

inline BakeGeometry flatten(const Scene& scene) {
  Expected<BakeGeometry> g = baker::flattenStaticGeometry(scene);
  EXPECT_TRUE(g.ok()) << g.status().message();
  return *g;
}

/// One quad [0,1]^2 in x-y facing +z, hand-mapped: page `size`, UV = offset + scale * xy.
struct HandMapped {
  Scene scene;
  BakeGeometry geometry;
  LightmapAtlas atlas;
};

inline HandMapped handMappedQuad(int size, float offset, float scale) {
  HandMapped h;
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("quad", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, grey);
  h.scene = b.scene();
  h.geometry = flatten(h.scene);
  h.atlas.page_width = h.atlas.page_height = size;
  h.atlas.page_count = 1;
  for (size_t t = 0; t < h.geometry.triangleCount(); ++t) {
    h.atlas.triangle_page.push_back(0);
    h.atlas.triangle_chart.push_back(0);
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = h.geometry.corner(t, k);
      h.atlas.triangle_uv.push_back({offset + scale * p.x, offset + scale * p.y});
    }
  }
  return h;
}

}  // namespace svit::test

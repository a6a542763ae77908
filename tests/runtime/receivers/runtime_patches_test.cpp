// Runtime patches (internal): every sub-triangle is found again from the
// barycentrics of a point inside it, patches respect the area bound, and
// shooters group whole patches.

#include <gtest/gtest.h>

#include "receivers/runtime_patches.h"
#include "runtime/runtime_test_util.h"
#include "svit/baked_surfaces.h"

namespace svit {
namespace {

TEST(RuntimePatches, SubTrianglesAreFoundFromBarycentrics) {
  const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(level.scene, level.bake);
  ASSERT_TRUE(surfaces.ok());
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(level.bake, level.dir);
  ASSERT_TRUE(pages.ok());
  const double max_area = 0.01;
  Expected<gl::RuntimePatches> built = gl::buildRuntimePatches(
      level.scene, level.bake, *surfaces, *pages, MaskedLightField(), max_area, 0.1);
  ASSERT_TRUE(built.ok()) << built.status().message();
  const gl::RuntimePatches& p = *built;
  for (const gl::Receiver& r : p.receivers) EXPECT_LE(r.area_m2, max_area * 1.001);
  size_t checked = 0;
  for (uint32_t element = 0; element < p.element_n.size(); ++element) {
    const int n = p.element_n[element];
    if (n == 0) continue;
    const uint32_t t = element / 2;
    const Vec3 a = surfaces->corner(t, 0), b = surfaces->corner(t, 1), c = surfaces->corner(t, 2);
    for (uint32_t slot = 0; slot < uint32_t(n * n * 2); ++slot) {
      const uint32_t sub = p.slots[p.element_first_slot[element] + slot];
      if (sub == gl::kNoReceiver) continue;
      // The sub-triangle's centroid, in the bake triangle's barycentrics.
      Vec3 q{0, 0, 0};
      for (int k = 0; k < 3; ++k) {
        const Vec3& v = p.triangles.positions[size_t(sub) * 3 + size_t(k)];
        q = {q.x + v.x / 3, q.y + v.y / 3, q.z + v.z / 3};
      }
      // Solve q = a + w1 (b - a) + w2 (c - a) by least squares.
      const double e1[3] = {b.x - a.x, b.y - a.y, b.z - a.z},
                   e2[3] = {c.x - a.x, c.y - a.y, c.z - a.z};
      const double d[3] = {q.x - a.x, q.y - a.y, q.z - a.z};
      auto dot = [](const double* u, const double* v) {
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
      };
      const double a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2), b1 = dot(e1, d),
                   b2 = dot(e2, d);
      const double det = a11 * a22 - a12 * a12;
      const float w1 = float((a22 * b1 - a12 * b2) / det), w2 = float((a11 * b2 - a12 * b1) / det);
      float s1 = 0, s2 = 0;
      ASSERT_EQ(p.subTriangle(element, w1, w2, s1, s2), sub)
          << "element " << element << " slot " << slot;
      EXPECT_NEAR(s1, 1.0f / 3, 1e-3);
      EXPECT_NEAR(s2, 1.0f / 3, 1e-3);
      ++checked;
    }
  }
  EXPECT_GT(checked, 500u);
  // Shooters are unions of whole patches within one bake patch.
  for (size_t g = 0; g < p.shooter_members.size(); ++g) {
    for (uint32_t r : p.shooter_members[g]) {
      EXPECT_EQ(p.shooter[r], g);
      EXPECT_EQ(p.bake_patch[r], p.shooter_bake_patch[g]);
    }
  }
}

}  // namespace
}  // namespace svit

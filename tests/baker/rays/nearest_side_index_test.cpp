// The proxy builder's nearest-side index (nearest_side_index.h) against a
// scan of every side: the same side for random soups of triangles near and
// far from the origin, ties to the lowest index, the facing filter.

#include <gtest/gtest.h>

#include <embree3/rtcore.h>

#include <limits>
#include <vector>

#include "rays/embree_handles.h"
#include "rays/nearest_side_index.h"
#include "svit/baker/bake_geometry.h"
#include "util/double_math.h"
#include "util/random.h"

namespace svit::baker {
namespace {

void addTriangle(BakeGeometry& g, const Vec3& a, const Vec3& b, const Vec3& c) {
  g.positions.insert(g.positions.end(), {a, b, c});
  const glm::dvec3 n = glm::cross(dvec(b) - dvec(a), dvec(c) - dvec(a));
  g.normals.push_back(vec3(glm::normalize(n)));
  g.areas_m2.push_back(float(0.5 * glm::length(n)));
}

/// `count` random triangles up to `size` metres across in a 10 m box at
/// `origin`, each side a candidate for even triangles, the front alone for odd.
void randomSoup(uint64_t seed, size_t count, double size, const glm::dvec3& origin, BakeGeometry& g,
                std::vector<TriangleSide>& sides) {
  Rng rng(seed);
  auto point = [&](double scale) {
    return glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform()) * scale;
  };
  for (size_t t = 0; t < count; ++t) {
    const glm::dvec3 a = origin + point(10.0);
    addTriangle(g, vec3(a), vec3(a + point(size) - size / 2), vec3(a + point(size) - size / 2));
    const glm::dvec3 n = dvec(g.normals.back());
    sides.push_back({uint32_t(t), n});
    if (t % 2 == 0) sides.push_back({uint32_t(t), -n});
  }
}

int32_t scanNearest(const BakeGeometry& g, const std::vector<TriangleSide>& sides,
                    const glm::dvec3& p, const glm::dvec3& n, bool any_side) {
  double best = std::numeric_limits<double>::infinity();
  int32_t best_index = -1;
  for (size_t i = 0; i < sides.size(); ++i) {
    if (!any_side && !(glm::dot(sides[i].normal, n) > 0)) continue;
    const uint32_t t = sides[i].triangle;
    const double d2 =
        distance2ToTriangle(p, dvec(g.corner(t, 0)), dvec(g.corner(t, 1)), dvec(g.corner(t, 2)));
    if (d2 < best) {
      best = d2;
      best_index = int32_t(i);
    }
  }
  return best_index;
}

class NearestSide : public testing::TestWithParam<double> {};

TEST_P(NearestSide, FindsTheSideAScanOfEverySideFinds) {
  const glm::dvec3 origin(GetParam());
  const EmbreeDevice device(rtcNewDevice(nullptr));
  ASSERT_TRUE(device);
  BakeGeometry g;
  std::vector<TriangleSide> sides;
  randomSoup(11, 3000, 0.5, origin, g, sides);
  Expected<NearestSideIndex> index = NearestSideIndex::build(device.get(), g, sides);
  ASSERT_TRUE(index.ok()) << index.status().message();
  Rng rng(12);
  for (int q = 0; q < 2000; ++q) {
    const glm::dvec3 p =
        origin + glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform()) * 12.0 - 1.0;
    const glm::dvec3 n(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    for (bool any_side : {false, true})
      ASSERT_EQ(index->nearest(p, n, any_side), scanNearest(g, sides, p, n, any_side))
          << "query " << q << (any_side ? " (any side)" : "");
  }
}

// At the origin, and 10 km from it, where floats are 1 mm apart.
INSTANTIATE_TEST_SUITE_P(Origins, NearestSide, testing::Values(0.0, 1e4));

TEST(NearestSide, TiesGoToTheLowestIndexAndTheFacingFilterHolds) {
  const EmbreeDevice device(rtcNewDevice(nullptr));
  ASSERT_TRUE(device);
  BakeGeometry g;
  for (int copy = 0; copy < 8; ++copy) addTriangle(g, {0, 0, 0}, {1, 0, 0}, {0, 0, 1});
  std::vector<TriangleSide> sides;
  for (uint32_t t = 7; t >= 4; --t) sides.push_back({t, {0, -1, 0}});  // all face down...
  for (uint32_t t = 0; t < 4; ++t) sides.push_back({t, {0, -1, 0}});
  Expected<NearestSideIndex> index = NearestSideIndex::build(device.get(), g, sides);
  ASSERT_TRUE(index.ok()) << index.status().message();
  EXPECT_EQ(index->nearest({0.2, -1, 0.2}, {0, -1, 0}, false), 0) << "eight equidistant sides";
  EXPECT_EQ(index->nearest({0.2, 1, 0.2}, {0, 1, 0}, false), -1) << "...none faces up";
  EXPECT_EQ(index->nearest({0.2, 1, 0.2}, {0, 1, 0}, true), 0);
  const std::vector<TriangleSide> none;
  Expected<NearestSideIndex> empty = NearestSideIndex::build(device.get(), g, none);
  ASSERT_TRUE(empty.ok());
  EXPECT_EQ(empty->nearest({0, 0, 0}, {0, 1, 0}, true), -1);
}

}  // namespace
}  // namespace svit::baker

// Occlusion culling's CPU half (index_map_occlusion.h): the farthest-depth
// pyramid, the hidden-box test against it and the near/far split.

#include <gtest/gtest.h>

#include <vector>

#include "indexmaps/index_map_occlusion.h"

namespace svit::gl {
namespace {

constexpr int kRes = 64;
constexpr double kNear = 0.01;

// Looking down +z from the origin; a wall of depth `wall_m` over the whole face.
FaceProjection face() {
  FaceProjection f;
  f.near_m = kNear;
  return f;
}

std::vector<float> wall(double wall_m) {
  return std::vector<float>(size_t(kRes) * kRes, float(kNear / wall_m));
}

TriangleChunk box(glm::dvec3 lo, glm::dvec3 hi) {
  TriangleChunk c;
  c.count = 256;
  c.lo = lo;
  c.hi = hi;
  return c;
}

TEST(IndexMapOcclusion, PyramidKeepsTheFarthestDepthOfEachBlock) {
  std::vector<float> depth = wall(1.0);
  depth[size_t(37) * kRes + 5] = 0.0f;  // a cleared texel: nothing drawn, infinitely far
  DepthPyramid p;
  buildDepthPyramid(depth, kRes, kRes, 0, p);
  ASSERT_EQ(p.levels.size(), 7u);  // 64, 32, ..., 1
  EXPECT_EQ(p.widths.back(), 1);
  EXPECT_EQ(p.levels.back()[0], 0.0f);
  EXPECT_EQ(p.levels[3][size_t(37 / 8) * 8 + 0], 0.0f);                // its 8 x 8 block
  EXPECT_FLOAT_EQ(p.levels[3][size_t(37 / 8) * 8 + 1], float(kNear));  // the next block: the wall
}

TEST(IndexMapOcclusion, RowsBelowAHalfFacesHorizonNeverShowAnything) {
  std::vector<float> depth = wall(1.0);
  for (int y = 0; y < kRes / 2; ++y) {
    for (int x = 0; x < kRes; ++x) depth[size_t(y) * kRes + size_t(x)] = 0.0f;  // stale or cleared
  }
  DepthPyramid p;
  buildDepthPyramid(depth, kRes, kRes, kRes / 2, p);
  EXPECT_FLOAT_EQ(p.levels.back()[0], float(kNear));  // the lower rows count as nearest
}

TEST(IndexMapOcclusion, ABoxBehindAWallIsHiddenAndOneInFrontIsNot) {
  DepthPyramid p;
  buildDepthPyramid(wall(1.0), kRes, kRes, 0, p);
  EXPECT_TRUE(chunkHidden(box({-0.5, -0.5, 2.0}, {0.5, 0.5, 3.0}), face(), p));
  EXPECT_FALSE(chunkHidden(box({-0.2, -0.2, 0.5}, {0.2, 0.2, 0.9}), face(), p));
  // Straddling the wall: part of it is in front.
  EXPECT_FALSE(chunkHidden(box({-0.2, -0.2, 0.9}, {0.2, 0.2, 1.5}), face(), p));
  // Just behind the wall, within depth precision and the fallback's slack.
  EXPECT_FALSE(chunkHidden(box({-0.2, -0.2, 1.00001}, {0.2, 0.2, 1.5}), face(), p));
  // Reaching behind the eye: no projection to test.
  EXPECT_FALSE(chunkHidden(box({-0.2, -0.2, -1.0}, {0.2, 0.2, 5.0}), face(), p));
}

TEST(IndexMapOcclusion, AHoleInTheWallShowsWhatIsBehindIt) {
  std::vector<float> depth = wall(1.0);
  // A 4 x 4 texel hole straight ahead (texels 30..33 hold the centre).
  for (int y = 30; y < 34; ++y) {
    for (int x = 30; x < 34; ++x) depth[size_t(y) * kRes + size_t(x)] = 0.0f;
  }
  DepthPyramid p;
  buildDepthPyramid(depth, kRes, kRes, 0, p);
  EXPECT_FALSE(chunkHidden(box({-0.1, -0.1, 2.0}, {0.1, 0.1, 3.0}), face(), p));  // behind the hole
  // Beside it, far from the hole: hidden.
  EXPECT_TRUE(chunkHidden(box({0.6, 0.6, 2.0}, {0.8, 0.8, 3.0}), face(), p));
  // A box whose texels end one texel short of the hole is still kept: the
  // fallback's taps reach a texel beside a vertex. Texel u = (x / z / 2 +
  // 0.5) * 64 = 16 x + 32 at z = 2: x in [0.16, 0.3] lands on texels 34..36,
  // and 33, beside them, is in the hole.
  EXPECT_FALSE(chunkHidden(box({-0.1 + 0.26, -0.1, 2.0}, {0.3, 0.1, 2.0}), face(), p));
}

TEST(IndexMapOcclusion, TheNearestChunksComeFirst) {
  std::vector<TriangleChunk> chunks;
  for (int i = 0; i < 8; ++i) chunks.push_back(box({0, 0, double(7 - i)}, {1, 1, double(8 - i)}));
  const std::vector<uint32_t> candidates = {0, 1, 2, 3, 4, 5, 6, 7};
  std::vector<uint32_t> first, rest;
  splitNearest(chunks, candidates, glm::dvec3(0.5, 0.5, -1.0), 512, first, rest);
  // z from 0 and 1: the nearest two, 512 triangles
  EXPECT_EQ(first, (std::vector<uint32_t>{6, 7}));
  EXPECT_EQ(rest, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  splitNearest(chunks, candidates, glm::dvec3(0.5, 0.5, -1.0), 0, first, rest);
  EXPECT_EQ(first.size(), 1u);  // one chunk at least
  EXPECT_DOUBLE_EQ(boxDistance(chunks[7], glm::dvec3(0.5, 0.5, 0.5)), 0.0);
}

}  // namespace
}  // namespace svit::gl

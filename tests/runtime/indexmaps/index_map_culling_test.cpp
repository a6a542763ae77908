// Which triangles an index-map face draws (runtime/src/indexmaps/index_map_culling.h):
// the static set of lit-set culling, triangle by triangle, the skipped own
// triangle, the dynamic chunks a set face may show; and the order that
// makes culling runs compact. Pure CPU.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "indexmaps/index_map_culling.h"

namespace svit::gl {
namespace {

// `count` small triangles in a row along +x, 1 m apart, in front of the
// origin looking down -z (so every frustum below sees them).
std::vector<float> rowOfTriangles(uint32_t count) {
  std::vector<float> out;
  for (uint32_t t = 0; t < count; ++t) {
    const float x = float(t) - float(count) / 2;
    for (float v : {x, 0.0f, -5.0f, x + 0.5f, 0.0f, -5.0f, x, 0.5f, -5.0f}) out.push_back(v);
  }
  return out;
}

Frustum everything() {  // a parallel window over the whole row
  return faceFrustum(glm::dvec3(0, 0, 10), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
                     glm::dvec3(0, 0, -1), 0.01, false, true, 1e6, 1e3);
}

std::vector<uint32_t> drawn(const std::vector<int32_t>& firsts,
                            const std::vector<int32_t>& counts) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < firsts.size(); ++i) {
    for (int32_t v = firsts[i]; v < firsts[i] + counts[i]; v += 3) out.push_back(uint32_t(v / 3));
  }
  return out;
}

constexpr uint32_t K = kChunkTriangles;

// Triangle numbers of an index list (3t, 3t + 1, 3t + 2 each).
std::vector<uint32_t> listed(const std::vector<uint32_t>& indices) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    EXPECT_EQ(indices[i] % 3, 0u);
    EXPECT_EQ(indices[i + 1], indices[i] + 1);
    EXPECT_EQ(indices[i + 2], indices[i] + 2);
    out.push_back(indices[i] / 3);
  }
  return out;
}

// The triangles a face with a static set draws: the set's triangles of the
// candidate chunks that may meet the frustum, and every dynamic one.
std::vector<uint32_t> setDrawn(std::span<const TriangleChunk> chunks,
                               std::span<const float> static_positions, const Frustum& frustum,
                               uint32_t skip, const TriangleBits& set) {
  std::vector<uint32_t> candidates, indices;
  candidateChunks(chunks, frustum, glm::dvec3(1), glm::dvec3(0), &set, candidates);
  uint64_t n = 0;
  for (uint32_t c : candidates)
    n += appendSetIndices(chunks[c], static_positions, frustum, skip, set, indices);
  EXPECT_EQ(n * 3, indices.size());
  return listed(indices);
}

TEST(IndexMapCulling, StaticSetKeepsItsTrianglesAndEveryDynamicOne) {
  // 2K + 24 static triangles (3 chunks, the last partial) and 24 dynamic
  // ones numbered after them: the set's last word holds the last 24 static
  // triangles and would hold dynamic ones if it were read past the static
  // triangles.
  static_assert(K >= 32 && K % 32 == 0, "the layout below: 24 dynamic triangles in one chunk");
  const uint32_t n_static = 2 * K + 24, n_dynamic = 24;
  const std::vector<float> static_positions = rowOfTriangles(n_static);
  std::vector<TriangleChunk> chunks;
  appendChunks(static_positions, 0, false, chunks);
  appendChunks(rowOfTriangles(n_dynamic), n_static, true, chunks);
  ASSERT_EQ(chunks.size(), 4u);
  TriangleBits set(triangleBitWords(n_static), 0u);
  for (uint32_t t : {3u, 4u, 5u, K + 12, n_static - 1}) set[t / 32] |= 1u << (t % 32);
  std::vector<uint32_t> expected = {3, 5, K + 12, n_static - 1};  // 4 skipped
  for (uint32_t t = n_static; t < n_static + n_dynamic; ++t) expected.push_back(t);
  EXPECT_EQ(setDrawn(chunks, static_positions, everything(), 4, set), expected);

  TriangleBits only_chunk_2(triangleBitWords(n_static), 0u);
  only_chunk_2[(2 * K + 8) / 32] |= 1u << ((2 * K + 8) % 32);
  EXPECT_FALSE(chunkInSet(chunks[0], &only_chunk_2));
  EXPECT_FALSE(chunkInSet(chunks[1], &only_chunk_2));
  EXPECT_TRUE(chunkInSet(chunks[2], &only_chunk_2));
  EXPECT_TRUE(chunkInSet(chunks[3], &only_chunk_2)) << "dynamic chunks are never culled";
  EXPECT_TRUE(chunkInSet(chunks[0], nullptr));
}

TEST(IndexMapCulling, ASetDrawsOnlyItsTrianglesInTheFrustum) {
  // The row runs along x at z = -5; a perspective face from the origin
  // looking down -z sees |x| <= 5 there (x + 0.5 for a triangle's far
  // corner). The set holds every other triangle: those in view are drawn,
  // one by one, and nothing between them (spans of runs drew those too).
  const uint32_t n = 4 * K;
  const std::vector<float> positions = rowOfTriangles(n);
  std::vector<TriangleChunk> chunks;
  appendChunks(positions, 0, false, chunks);
  TriangleBits set(triangleBitWords(n), 0u);
  for (uint32_t t = 0; t < n; t += 2) set[t / 32] |= 1u << (t % 32);
  const Frustum face = faceFrustum(glm::dvec3(0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
                                   glm::dvec3(0, 0, -1), 0.01, false, false, 0, 0);
  std::vector<uint32_t> expected;
  for (uint32_t t = 0; t < n; t += 2) {
    const float x = float(t) - float(n) / 2;  // rowOfTriangles: corners x .. x + 0.5
    if (x + 0.5f >= -5.0f && x <= 5.0f) expected.push_back(t);
  }
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(setDrawn(chunks, positions, face, 0xffffffffu, set), expected);
}

TEST(IndexMapCulling, ASetFaceDrawsOnlyTheDynamicChunksBeforeWhatItSaw) {
  // The eye at the origin saw a patch of wall around (0, 0, -5). A dynamic
  // chunk between them stays; one behind the wall, one beside the line of
  // sight and one behind the eye go; static chunks are never dropped.
  auto chunk = [](bool dynamic, glm::dvec3 lo, glm::dvec3 hi) {
    TriangleChunk c;
    c.dynamic = dynamic;
    c.lo = lo;
    c.hi = hi;
    return c;
  };
  const std::vector<TriangleChunk> chunks = {
      chunk(false, {-0.5, -0.5, -5.0}, {0.5, 0.5, -5.0}),  // 0: the wall, static
      chunk(true, {-0.2, -0.2, -2.2}, {0.2, 0.2, -1.8}),   // 1: in front of it
      chunk(true, {-0.2, -0.2, -8.2}, {0.2, 0.2, -7.8}),   // 2: behind it
      chunk(true, {4.8, -0.2, -2.2}, {5.2, 0.2, -1.8}),    // 3: beside the sightline
      chunk(true, {-0.2, -0.2, 1.8}, {0.2, 0.2, 2.2}),     // 4: behind the eye
      chunk(false, {9.0, 9.0, 9.0}, {9.5, 9.5, 9.5}),      // 5: static, anywhere
  };
  Box wall;
  wall.lo = {-0.5, -0.5, -5.0};
  wall.hi = {0.5, 0.5, -5.0};
  std::vector<uint32_t> face_chunks = {0, 1, 2, 3, 4, 5};
  keepDynamicBeforeSet(chunks, glm::dvec3(0.0), std::span<const Box>(&wall, 1), face_chunks);
  EXPECT_EQ(face_chunks, (std::vector<uint32_t>{0, 1, 5}));
  // Nothing seen: no dynamic chunk can show.
  face_chunks = {0, 1, 2, 3, 4, 5};
  keepDynamicBeforeSet(chunks, glm::dvec3(0.0), {}, face_chunks);
  EXPECT_EQ(face_chunks, (std::vector<uint32_t>{0, 5}));
}

TEST(IndexMapCulling, RunsNeverStraddleTwoParts) {
  // Parts (objects) of 12, 60, 5 and 50 triangles: runs of at most
  // kChunkTriangles within each, numbered from the set's first triangle.
  const std::vector<uint32_t> part_starts = {0, 12, 72, 77};
  std::vector<TriangleChunk> chunks;
  appendChunks(rowOfTriangles(127), 1000, true, chunks, part_starts);
  std::vector<std::pair<uint32_t, uint32_t>> runs;
  for (const TriangleChunk& c : chunks) runs.push_back({c.first, c.count});
  const std::vector<std::pair<uint32_t, uint32_t>> expected = {{1000, 12}, {1012, 32}, {1044, 28},
                                                               {1072, 5},  {1077, 32}, {1109, 18}};
  EXPECT_EQ(runs, expected);
  // A run's box is its own triangles' (rowOfTriangles: x from t - 63.5).
  EXPECT_DOUBLE_EQ(chunks[3].lo.x, 72.0 - 63.5);
  EXPECT_DOUBLE_EQ(chunks[3].hi.x, 76.0 - 63.5 + 0.5);
  // No parts: runs of kChunkTriangles from the first.
  chunks.clear();
  appendChunks(rowOfTriangles(127), 0, true, chunks);
  ASSERT_EQ(chunks.size(), 4u);
  EXPECT_EQ(chunks[3].count, 127 - 3 * kChunkTriangles);
}

TEST(IndexMapCulling, ATriangleMeetsAFrustumUnlessAllCornersLieOutsideOnePlane) {
  const Frustum face = faceFrustum(glm::dvec3(0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
                                   glm::dvec3(0, 0, -1), 0.01, false, false, 0, 0);
  const float inside[9] = {0, 0, -5, 1, 0, -5, 0, 1, -5};
  const float right_of[9] = {6, 0, -5, 7, 0, -5, 6, 1, -5};
  const float behind[9] = {0, 0, 5, 1, 0, 5, 0, 1, 5};
  // Corners outside different planes (left and right), the triangle across the view.
  const float across[9] = {-20, 0, -5, 20, 0, -5, 0, 0.5f, -5};
  const float grazing[9] = {5, 0, -5, 6, 0, -5, 6, 1, -5};  // a corner on the right plane
  EXPECT_TRUE(triangleMayMeet(inside, face));
  EXPECT_FALSE(triangleMayMeet(right_of, face));
  EXPECT_FALSE(triangleMayMeet(behind, face));
  EXPECT_TRUE(triangleMayMeet(across, face));
  EXPECT_TRUE(triangleMayMeet(grazing, face));
}

TEST(IndexMapCulling, NoSetDrawsEveryChunkInTheFrustum) {
  std::vector<TriangleChunk> chunks;
  appendChunks(rowOfTriangles(300), 0, false, chunks);
  std::vector<uint32_t> candidates;
  candidateChunks(chunks, everything(), glm::dvec3(1), glm::dvec3(0), nullptr, candidates);
  std::vector<int32_t> firsts, counts;
  uint64_t n = 0;
  for (uint32_t c : candidates) n += appendChunkRanges(chunks[c], 0xffffffffu, firsts, counts);
  EXPECT_EQ(n, 300u);
  ASSERT_EQ(firsts.size(), 1u);
  EXPECT_EQ(counts[0], 900);
  // The own triangle splits its chunk's range.
  firsts.clear();
  counts.clear();
  EXPECT_EQ(appendChunkRanges(chunks[0], 7, firsts, counts), uint64_t(K - 1));
  EXPECT_EQ(drawn(firsts, counts).size(), size_t(K - 1));
  EXPECT_EQ(firsts.size(), 2u);
}

TEST(IndexMapCulling, SpatialRunOrderMakesRunsCompact) {
  // A 64 x 64 grid of unit cells, two triangles each, given in a shuffled
  // order: every run of K in the new order covers about K / 2 cells, so its
  // centroids' box is a few cells wide, never a sizeable part of the grid.
  const int side = 64;
  std::vector<glm::vec3> centroids;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      centroids.push_back({float(i) + 0.33f, 0.0f, float(j) + 0.33f});
      centroids.push_back({float(i) + 0.67f, 0.0f, float(j) + 0.67f});
    }
  }
  std::vector<glm::vec3> shuffled(centroids.size());
  for (size_t i = 0; i < centroids.size(); ++i)
    shuffled[i] = centroids[(i * 7919) % centroids.size()];
  const std::vector<uint32_t> order = spatialRunOrder(shuffled);
  ASSERT_EQ(order.size(), shuffled.size());
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "not a permutation";
  const float cells = std::sqrt(float(K) / 2.0f);  // a square run's side, cells
  for (size_t begin = 0; begin < order.size(); begin += K) {
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (size_t i = begin; i < std::min(order.size(), begin + K); ++i) {
      lo = glm::min(lo, shuffled[order[i]]);
      hi = glm::max(hi, shuffled[order[i]]);
    }
    EXPECT_LE(hi.x - lo.x, 2 * cells) << "run at " << begin;
    EXPECT_LE(hi.z - lo.z, 2 * cells) << "run at " << begin;
  }
  EXPECT_EQ(spatialRunOrder(shuffled), order) << "deterministic";
  EXPECT_TRUE(spatialRunOrder({}).empty());
}

}  // namespace
}  // namespace svit::gl

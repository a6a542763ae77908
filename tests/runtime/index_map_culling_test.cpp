// Which triangles an index-map face draws (runtime/src/gl/index_map_culling.h):
// the static set of lit-set culling, the skipped own triangle, dynamic
// chunks that no static set culls. Pure CPU.

#include <gtest/gtest.h>

#include <vector>

#include "index_map_culling.h"

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
  return faceFrustum(glm::dvec3(0, 0, 10), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1), 0.01,
                     false, true, 1e6, 1e3);
}

std::vector<uint32_t> drawn(const std::vector<int32_t>& firsts, const std::vector<int32_t>& counts) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < firsts.size(); ++i) {
    for (int32_t v = firsts[i]; v < firsts[i] + counts[i]; v += 3) out.push_back(uint32_t(v / 3));
  }
  return out;
}

constexpr uint32_t K = kChunkTriangles;

TEST(IndexMapCulling, StaticSetKeepsItsTrianglesAndEveryDynamicOne) {
  // 2K + 24 static triangles (3 chunks, the last partial) and 24 dynamic
  // ones numbered after them: the set's last word holds the last 24 static
  // triangles and would hold dynamic ones if it were read past the static
  // triangles.
  static_assert(K >= 32 && K % 32 == 0, "the layout below: 24 dynamic triangles in one chunk");
  const uint32_t n_static = 2 * K + 24, n_dynamic = 24;
  std::vector<TriangleChunk> chunks;
  appendChunks(rowOfTriangles(n_static), 0, false, chunks);
  appendChunks(rowOfTriangles(n_dynamic), n_static, true, chunks);
  ASSERT_EQ(chunks.size(), 4u);
  TriangleBits set(triangleBitWords(n_static), 0u);
  for (uint32_t t : {3u, 4u, 5u, K + 12, n_static - 1}) set[t / 32] |= 1u << (t % 32);
  std::vector<int32_t> firsts, counts;
  const glm::dvec3 no_lo(1), no_hi(0);
  const uint64_t n = visibleRanges(chunks, everything(), 4, no_lo, no_hi, &set, firsts, counts);
  std::vector<uint32_t> expected = {3, 5, K + 12, n_static - 1};
  for (uint32_t t = n_static; t < n_static + n_dynamic; ++t) expected.push_back(t);
  EXPECT_EQ(drawn(firsts, counts), expected);
  EXPECT_EQ(n, expected.size());
  // 3 and 5 around the skipped 4 stay separate draws; the last static one
  // and the dynamic run merge.
  EXPECT_EQ(firsts.size(), 4u);

  TriangleBits only_chunk_2(triangleBitWords(n_static), 0u);
  only_chunk_2[(2 * K + 8) / 32] |= 1u << ((2 * K + 8) % 32);
  EXPECT_FALSE(chunkInSet(chunks[0], &only_chunk_2));
  EXPECT_FALSE(chunkInSet(chunks[1], &only_chunk_2));
  EXPECT_TRUE(chunkInSet(chunks[2], &only_chunk_2));
  EXPECT_TRUE(chunkInSet(chunks[3], &only_chunk_2)) << "dynamic chunks are never culled";
  EXPECT_TRUE(chunkInSet(chunks[0], nullptr));
}

TEST(IndexMapCulling, AChunkDrawsTheSpanOfItsTrianglesInTheSet) {
  // Kept 10, 20 and K - 4 of chunk 0, nothing of the others: chunk 0 draws
  // 10..K - 4 as one range (cheaper than three), the others nothing.
  std::vector<TriangleChunk> chunks;
  appendChunks(rowOfTriangles(4 * K), 0, false, chunks);
  TriangleBits set(triangleBitWords(4 * K), 0u);
  for (uint32_t t : {10u, 20u, K - 4}) set[t / 32] |= 1u << (t % 32);
  std::vector<int32_t> firsts, counts;
  const uint64_t n = visibleRanges(chunks, everything(), 0xffffffffu, glm::dvec3(1), glm::dvec3(0), &set, firsts,
                                   counts);
  std::vector<uint32_t> expected;
  for (uint32_t t = 10; t <= K - 4; ++t) expected.push_back(t);
  EXPECT_EQ(drawn(firsts, counts), expected);
  EXPECT_EQ(n, uint64_t(K - 13));
  EXPECT_EQ(firsts.size(), 1u);
}

TEST(IndexMapCulling, NoSetDrawsEveryChunkInTheFrustum) {
  std::vector<TriangleChunk> chunks;
  appendChunks(rowOfTriangles(300), 0, false, chunks);
  std::vector<int32_t> firsts, counts;
  const uint64_t n = visibleRanges(chunks, everything(), 0xffffffffu, glm::dvec3(1), glm::dvec3(0), nullptr, firsts,
                                   counts);
  EXPECT_EQ(n, 300u);
  ASSERT_EQ(firsts.size(), 1u);
  EXPECT_EQ(counts[0], 900);
}

}  // namespace
}  // namespace svit::gl

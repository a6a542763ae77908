#pragma once
// Coarse culling for index-map faces. llvmpipe (and any GPU on a big level)
// spends a face's time on vertices and triangle setup, most of them outside
// the face's 90-degree frustum; so triangles are kept in runs of
// kChunkTriangles consecutive ones with a bounding box each, and a face
// draws only the runs whose box meets its frustum. Triangle indices never
// change: the ranges are ranges of the given order, which should be
// spatially coherent (spatialRunOrder makes it so).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/numeric.h"

namespace svit::gl {

// Small enough that a run's box is a small part of a room (a run as large
// as a room leaves occlusion culling nothing to hide) and that the few
// triangles a moving sample sees through a doorway cost little more than
// themselves, large enough that a big level's runs stay few to test.
inline constexpr uint32_t kChunkTriangles = 32;

/// An order of triangles (by their centroids) in which every run of
/// kChunkTriangles consecutive ones, from the first, is compact: the leaves
/// of a k-d split of the centroids (longest axis, at a multiple of the run
/// length near the middle), in tree order, so neighbouring runs are near
/// each other too. Deterministic (ties kept in index order). A level's
/// triangles come in whatever order its patches were made in, where 32
/// consecutive ones may span a whole room, and a face can then leave no
/// part of the room out.
std::vector<uint32_t> spatialRunOrder(std::span<const glm::vec3> centroids);

/// A run of triangles [first, first + count) and its world box, m.
struct TriangleChunk {
  uint32_t first = 0, count = 0;
  glm::dvec3 lo{0}, hi{0};
  bool dynamic = false;  ///< of the dynamic set (never culled by a static set)
};

/// Whether chunk `c` may meet the box [lo, hi]; lo > hi on an axis means no
/// box (everything meets it).
inline bool chunkMeetsBox(const TriangleChunk& c, const glm::dvec3& lo, const glm::dvec3& hi) {
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return true;
  return !(c.hi.x < lo.x || c.lo.x > hi.x || c.hi.y < lo.y || c.lo.y > hi.y || c.hi.z < lo.z ||
           c.lo.z > hi.z);
}

/// A set of static triangles: bit t % 32 of word t / 32 (PointSample::
/// static_triangles); words for `triangles` of them.
using TriangleBits = std::vector<uint32_t>;
inline size_t triangleBitWords(size_t triangles) { return (triangles + 31) / 32; }
/// Whether static triangle `t` is in `set`.
inline bool triangleInSet(const TriangleBits& set, uint32_t t) {
  return t / 32 < set.size() && ((set[t / 32] >> (t % 32)) & 1u) != 0;
}

/// Whether chunk `c` may be drawn under `static_set` (null = everything):
/// it holds a triangle of the set, or is dynamic.
bool chunkInSet(const TriangleChunk& c, const TriangleBits* static_set);

/// Appends the chunks of `positions` (9 floats per triangle), numbering the
/// triangles from `first_triangle`, of the dynamic set or the static one;
/// a chunk also ends before each of `part_starts` (ascending, counted from
/// the first of `positions`: MapTriangles::part_starts).
void appendChunks(std::span<const float> positions, uint32_t first_triangle, bool dynamic,
                  std::vector<TriangleChunk>& out, std::span<const uint32_t> part_starts = {});

/// A convex region: p is inside when dot(normal[i], p - eye) >= offset[i] for
/// every plane i < count.
struct Frustum {
  glm::dvec3 eye{0};
  std::array<glm::dvec3, 6> normal{};
  std::array<double, 6> offset{};
  int count = 0;
};

/// The frustum of one face: perspective (|right|, |up| <= forward, forward
/// >= near, and up >= 0 for a half face) or, when `parallel`, the window
/// |right|, |up| <= half_extent with near <= forward <= far. Directions are
/// unit world vectors.
Frustum faceFrustum(const glm::dvec3& eye, const glm::dvec3& right, const glm::dvec3& up,
                    const glm::dvec3& forward, double near_m, bool half_face, bool parallel,
                    double half_extent_m, double far_m);

/// Indices of the chunks that may meet `frustum` and the box [reach_lo,
/// reach_hi] (lo > hi on an axis: no box) and hold a triangle of
/// `static_set` (null: all), in index order.
void candidateChunks(std::span<const TriangleChunk> chunks, const Frustum& frustum,
                     const glm::dvec3& reach_lo, const glm::dvec3& reach_hi,
                     const TriangleBits* static_set, std::vector<uint32_t>& out);

/// A world box, lo <= hi on every axis (or lo > hi: empty).
struct Box {
  glm::dvec3 lo{kNoUpperBound}, hi{kNoLowerBound};
};

/// For a perspective face with a static set: drops from `face_chunks` the
/// dynamic chunks that meet no box spanning `eye` and one of `seen` (the
/// boxes of the set's triangles the face draws). Those are hidden: in a
/// closed level a ray from the sample that meets a dynamic triangle goes on
/// to a static one the same sample saw without it, which is in the set and
/// the face, so the dynamic triangle lies between the eye and that static
/// one (the assumption the runtime's reach tests make too). Without this a
/// set sample draws every dynamic triangle in the emitter's reach and the
/// face's frustum, behind walls or not: in a furnished level, most of what
/// it draws.
void keepDynamicBeforeSet(std::span<const TriangleChunk> chunks, const glm::dvec3& eye,
                          std::span<const Box> seen, std::vector<uint32_t>& face_chunks);

/// Appends chunk `c`'s vertex ranges to `firsts`/`counts` (merged with the
/// last where adjacent), triangle `skip` left out (any value outside the
/// chunk skips nothing). Returns the number of triangles appended.
uint64_t appendChunkRanges(const TriangleChunk& c, uint32_t skip, std::vector<int32_t>& firsts,
                           std::vector<int32_t>& counts);

/// Whether the triangle with corners `corners` (9 floats) may meet
/// `frustum`: false only when all three lie outside one plane.
bool triangleMayMeet(const float* corners, const Frustum& frustum);

/// Appends to `indices` the vertex indices (3t, 3t + 1, 3t + 2) of chunk
/// `c`'s triangles, bar `skip`: of a static chunk those in `static_set`
/// that may meet `frustum`, each tested on its own (`static_positions`: 9
/// floats per static triangle); of a dynamic chunk all of them. Returns
/// the number of triangles appended; grows `static_box` (if given) by the
/// static ones.
uint64_t appendSetIndices(const TriangleChunk& c, std::span<const float> static_positions,
                          const Frustum& frustum, uint32_t skip, const TriangleBits& static_set,
                          std::vector<uint32_t>& indices, Box* static_box = nullptr);

}  // namespace svit::gl

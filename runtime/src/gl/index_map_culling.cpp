// Chunk culling for index-map faces (see index_map_culling.h).

#include "index_map_culling.h"

#include <algorithm>
#include <cmath>

namespace svit::gl {

void appendChunks(std::span<const float> positions, uint32_t first_triangle, bool dynamic,
                  std::vector<TriangleChunk>& out) {
  const uint32_t triangles = uint32_t(positions.size() / 9);
  for (uint32_t begin = 0; begin < triangles; begin += kChunkTriangles) {
    TriangleChunk c;
    c.first = first_triangle + begin;
    c.count = std::min(kChunkTriangles, triangles - begin);
    c.dynamic = dynamic;
    c.lo = glm::dvec3(1e300);
    c.hi = glm::dvec3(-1e300);
    for (size_t v = size_t(begin) * 3; v < size_t(begin + c.count) * 3; ++v) {
      const glm::dvec3 p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
      c.lo = glm::min(c.lo, p);
      c.hi = glm::max(c.hi, p);
    }
    out.push_back(c);
  }
}

Frustum faceFrustum(const glm::dvec3& eye, const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& forward,
                    double near_m, bool half_face, bool parallel, double half_extent_m, double far_m) {
  Frustum f;
  f.eye = eye;
  auto add = [&](const glm::dvec3& n, double offset) {
    f.normal[size_t(f.count)] = n;
    f.offset[size_t(f.count)] = offset;
    ++f.count;
  };
  if (parallel) {
    add(right, -half_extent_m);
    add(-right, -half_extent_m);
    add(up, -half_extent_m);
    add(-up, -half_extent_m);
    add(forward, near_m);
    add(-forward, -far_m);
  } else {
    add(forward - right, 0);
    add(forward + right, 0);
    add(forward - up, 0);
    add(forward + up, 0);
    add(forward, near_m);
    if (half_face) add(up, 0);
  }
  return f;
}

namespace {

// False only when the box lies wholly outside one plane. The planes pass
// through the eye, so their tests are exact up to rounding; a margin of
// 1e-6 of the box's reach keeps a triangle grazing a face edge in.
bool mayMeet(const TriangleChunk& c, const Frustum& f) {
  const glm::dvec3 centre = 0.5 * (c.lo + c.hi) - f.eye, half = 0.5 * (c.hi - c.lo);
  const double reach = glm::length(centre) + glm::length(half);
  for (int i = 0; i < f.count; ++i) {
    const glm::dvec3& n = f.normal[size_t(i)];
    const double best = glm::dot(n, centre) + glm::dot(glm::abs(n), half);
    if (best < f.offset[size_t(i)] - 1e-6 * reach * glm::length(n)) return false;
  }
  return true;
}

bool inSet(const TriangleBits& set, uint32_t t) {  // t static
  return t / 32 < set.size() && ((set[t / 32] >> (t % 32)) & 1u) != 0;
}

}  // namespace

bool chunkInSet(const TriangleChunk& c, const TriangleBits* static_set) {
  if (!static_set || c.dynamic) return true;
  const uint32_t end = c.first + c.count;
  for (uint32_t w = c.first / 32; w <= (end - 1) / 32 && w < static_set->size(); ++w) {
    uint32_t bits = (*static_set)[w];
    // Only the chunk's own bits of the first and last words.
    if (w == c.first / 32) bits &= ~0u << (c.first % 32);
    if (w == (end - 1) / 32 && end % 32 != 0) bits &= ~(~0u << (end % 32));
    if (bits != 0) return true;
  }
  return false;
}

void candidateChunks(std::span<const TriangleChunk> chunks, const Frustum& frustum, const glm::dvec3& reach_lo,
                     const glm::dvec3& reach_hi, const TriangleBits* static_set, std::vector<uint32_t>& out) {
  out.clear();
  for (uint32_t i = 0; i < chunks.size(); ++i) {
    const TriangleChunk& c = chunks[i];
    if (chunkInSet(c, static_set) && mayMeet(c, frustum) && chunkMeetsBox(c, reach_lo, reach_hi)) out.push_back(i);
  }
}

uint64_t appendChunkRanges(const TriangleChunk& c, uint32_t skip, const TriangleBits* static_set,
                           std::vector<int32_t>& firsts, std::vector<int32_t>& counts) {
  uint64_t triangles = 0;
  auto push = [&](uint32_t first, uint32_t end) {  // triangles [first, end)
    if (end <= first) return;
    triangles += end - first;
    if (!firsts.empty() && uint32_t(firsts.back() + counts.back()) == 3 * first) {
      counts.back() += int32_t(3 * (end - first));
    } else {
      firsts.push_back(int32_t(3 * first));
      counts.push_back(int32_t(3 * (end - first)));
    }
  };
  // The chunk's triangles, `skip` left out; with a static set, only the
  // span from its first to its last triangle in the set (around `skip`, the
  // spans before and after it). Sound, the set only spares work, and every
  // range of a multi-draw has its own setup: on the house 2 x 2, drawing
  // the set's triangles through gaps of under 32 drew 143 k triangles per
  // frame in many short ranges, spans 166 k in few.
  const bool filtered = static_set && !c.dynamic;
  auto kept = [&](uint32_t t) { return !filtered || inSet(*static_set, t); };
  uint32_t lo = c.first, hi = c.first + c.count;
  while (lo < hi && !kept(lo)) ++lo;
  while (hi > lo && !kept(hi - 1)) --hi;
  if (skip < lo || skip >= hi) {
    push(lo, hi);
    return triangles;
  }
  uint32_t before = skip, after = skip + 1;  // [lo, before) and [after, hi)
  while (before > lo && !kept(before - 1)) --before;
  while (after < hi && !kept(after)) ++after;
  push(lo, before);
  push(after, hi);  // never merged with [lo, before): skip lies between
  return triangles;
}

uint64_t visibleRanges(std::span<const TriangleChunk> chunks, const Frustum& frustum, uint32_t skip,
                       const glm::dvec3& reach_lo, const glm::dvec3& reach_hi, const TriangleBits* static_set,
                       std::vector<int32_t>& firsts, std::vector<int32_t>& counts) {
  firsts.clear();
  counts.clear();
  std::vector<uint32_t> candidates;
  candidateChunks(chunks, frustum, reach_lo, reach_hi, static_set, candidates);
  uint64_t triangles = 0;
  for (uint32_t i : candidates) triangles += appendChunkRanges(chunks[i], skip, static_set, firsts, counts);
  return triangles;
}

}  // namespace svit::gl

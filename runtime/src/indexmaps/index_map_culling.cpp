// Chunk culling for index-map faces (see index_map_culling.h).

#include "index_map_culling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace svit::gl {

void appendChunks(std::span<const float> positions, uint32_t first_triangle, bool dynamic,
                  std::vector<TriangleChunk>& out, std::span<const uint32_t> part_starts) {
  const uint32_t triangles = uint32_t(positions.size() / 9);
  size_t next_part = 0;  // the first part start after `begin`
  for (uint32_t begin = 0; begin < triangles;) {
    while (next_part < part_starts.size() && part_starts[next_part] <= begin) ++next_part;
    const uint32_t part_end =
        next_part < part_starts.size() ? std::min(part_starts[next_part], triangles) : triangles;
    TriangleChunk c;
    c.first = first_triangle + begin;
    c.count = std::min(kChunkTriangles, part_end - begin);
    c.dynamic = dynamic;
    c.lo = glm::dvec3(kNoUpperBound);
    c.hi = glm::dvec3(kNoLowerBound);
    for (size_t v = size_t(begin) * 3; v < size_t(begin + c.count) * 3; ++v) {
      const glm::dvec3 p(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
      c.lo = glm::min(c.lo, p);
      c.hi = glm::max(c.hi, p);
    }
    out.push_back(c);
    begin += c.count;
  }
}

std::vector<uint32_t> spatialRunOrder(std::span<const glm::vec3> centroids) {
  std::vector<uint32_t> order(centroids.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  // Depth-first over [begin, end) ranges; each splits at a multiple of the
  // run length so runs never straddle two leaves.
  std::vector<std::pair<size_t, size_t>> todo = {{0, order.size()}};
  while (!todo.empty()) {
    const auto [begin, end] = todo.back();
    todo.pop_back();
    if (end - begin <= kChunkTriangles) {
      // a leaf: index order
      std::sort(order.begin() + ptrdiff_t(begin), order.begin() + ptrdiff_t(end));
      continue;
    }
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (size_t i = begin; i < end; ++i) {
      lo = glm::min(lo, centroids[order[i]]);
      hi = glm::max(hi, centroids[order[i]]);
    }
    const glm::vec3 extent = hi - lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const size_t runs = (end - begin + kChunkTriangles - 1) / kChunkTriangles;
    const size_t middle = begin + (runs / 2) * kChunkTriangles;
    std::nth_element(order.begin() + ptrdiff_t(begin), order.begin() + ptrdiff_t(middle),
                     order.begin() + ptrdiff_t(end), [&](uint32_t a, uint32_t b) {
                       const float ca = centroids[a][axis], cb = centroids[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    todo.push_back({begin, middle});
    todo.push_back({middle, end});
  }
  return order;
}

Frustum faceFrustum(const glm::dvec3& eye, const glm::dvec3& right, const glm::dvec3& up,
                    const glm::dvec3& forward, double near_m, bool half_face, bool parallel,
                    double half_extent_m, double far_m) {
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

void candidateChunks(std::span<const TriangleChunk> chunks, const Frustum& frustum,
                     const glm::dvec3& reach_lo, const glm::dvec3& reach_hi,
                     const TriangleBits* static_set, std::vector<uint32_t>& out) {
  out.clear();
  for (uint32_t i = 0; i < chunks.size(); ++i) {
    const TriangleChunk& c = chunks[i];
    if (chunkInSet(c, static_set) && mayMeet(c, frustum) && chunkMeetsBox(c, reach_lo, reach_hi))
      out.push_back(i);
  }
}

void keepDynamicBeforeSet(std::span<const TriangleChunk> chunks, const glm::dvec3& eye,
                          std::span<const Box> seen, std::vector<uint32_t>& face_chunks) {
  // Every (dynamic chunk, seen box) pair: a face meets a few dozen of each,
  // which costs less than drawing one chunk.
  std::erase_if(face_chunks, [&](uint32_t i) {
    const TriangleChunk& c = chunks[i];
    if (!c.dynamic) return false;
    for (const Box& b : seen) {
      // never empty: holds the eye
      if (chunkMeetsBox(c, glm::min(eye, b.lo), glm::max(eye, b.hi))) return false;
    }
    return true;
  });
}

uint64_t appendChunkRanges(const TriangleChunk& c, uint32_t skip, std::vector<int32_t>& firsts,
                           std::vector<int32_t>& counts) {
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
  const uint32_t end = c.first + c.count;
  if (skip < c.first || skip >= end) {
    push(c.first, end);
  } else {
    push(c.first, skip);
    push(skip + 1, end);  // never merged with the range before: skip lies between
  }
  return triangles;
}

bool triangleMayMeet(const float* corners, const Frustum& frustum) {
  glm::dvec3 d[3];
  double reach = 0;
  for (int k = 0; k < 3; ++k) {
    d[k] = glm::dvec3(corners[3 * k], corners[3 * k + 1], corners[3 * k + 2]) - frustum.eye;
    reach = std::max(reach, glm::length(d[k]));
  }
  for (int i = 0; i < frustum.count; ++i) {
    const glm::dvec3& n = frustum.normal[size_t(i)];
    // The same margin as a box's (mayMeet).
    const double limit = frustum.offset[size_t(i)] - 1e-6 * reach * glm::length(n);
    if (glm::dot(n, d[0]) < limit && glm::dot(n, d[1]) < limit && glm::dot(n, d[2]) < limit)
      return false;
  }
  return true;
}

uint64_t appendSetIndices(const TriangleChunk& c, std::span<const float> static_positions,
                          const Frustum& frustum, uint32_t skip, const TriangleBits& static_set,
                          std::vector<uint32_t>& indices, Box* static_box) {
  uint64_t triangles = 0;
  for (uint32_t t = c.first; t < c.first + c.count; ++t) {
    if (t == skip) continue;
    if (!c.dynamic) {
      if (!triangleInSet(static_set, t) || size_t(9) * t + 9 > static_positions.size()) continue;
      const float* corners = &static_positions[size_t(9) * t];
      if (!triangleMayMeet(corners, frustum)) continue;
      for (int k = 0; static_box && k < 3; ++k) {
        const glm::dvec3 p(corners[3 * k], corners[3 * k + 1], corners[3 * k + 2]);
        static_box->lo = glm::min(static_box->lo, p);
        static_box->hi = glm::max(static_box->hi, p);
      }
    }
    indices.insert(indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    ++triangles;
  }
  return triangles;
}

}  // namespace svit::gl

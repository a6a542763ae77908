// Two-pass occlusion culling for index-map faces (see index_map_occlusion.h).

#include "index_map_occlusion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace svit::gl {

namespace {

// Hidden only when nearer surfaces are nearer by this much of the box's
// distance: float depth (near / distance, ~1e-7) and the fallback's vertex
// slack (1e-5, index_map_fallback.comp) stay well inside it.
constexpr double kHiddenMargin = 1e-4;

}  // namespace

void buildDepthPyramid(std::span<const float> depth, int width, int height, int first_row,
                       DepthPyramid& out) {
  out.widths.assign(1, width);
  out.heights.assign(1, height);
  out.levels.resize(1);
  std::vector<float>& base = out.levels[0];
  base.assign(depth.begin(), depth.begin() + size_t(width) * size_t(height));
  const float nearest = std::numeric_limits<float>::infinity();
  for (int y = 0; y < std::min(first_row, height); ++y) {
    std::fill(base.begin() + size_t(y) * size_t(width),
              base.begin() + size_t(y + 1) * size_t(width), nearest);
  }
  while (out.widths.back() > 1 || out.heights.back() > 1) {
    const int w = out.widths.back(), h = out.heights.back();
    const int nw = (w + 1) / 2, nh = (h + 1) / 2;
    const size_t below = out.levels.size() - 1;
    out.levels.emplace_back(size_t(nw) * size_t(nh));
    const std::vector<float>& fine = out.levels[below];
    std::vector<float>& coarse = out.levels.back();
    for (int y = 0; y < nh; ++y) {
      for (int x = 0; x < nw; ++x) {
        float farthest = nearest;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const int fx = 2 * x + dx, fy = 2 * y + dy;
            if (fx < w && fy < h)
              farthest = std::min(farthest, fine[size_t(fy) * size_t(w) + size_t(fx)]);
          }
        }
        coarse[size_t(y) * size_t(nw) + size_t(x)] = farthest;
      }
    }
    out.widths.push_back(nw);
    out.heights.push_back(nh);
  }
}

bool chunkHidden(const TriangleChunk& chunk, const FaceProjection& face,
                 const DepthPyramid& pyramid) {
  if (pyramid.levels.empty()) return false;
  const int width = pyramid.widths[0], height = pyramid.heights[0];
  double nearest_m = std::numeric_limits<double>::infinity();
  double u_lo = nearest_m, u_hi = -nearest_m, v_lo = nearest_m, v_hi = -nearest_m;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? chunk.hi.x : chunk.lo.x, (k & 2) ? chunk.hi.y : chunk.lo.y,
                            (k & 4) ? chunk.hi.z : chunk.lo.z);
    const glm::dvec3 d = corner - face.eye;
    const double z = glm::dot(d, face.forward);
    // A corner at or behind the near plane projects nowhere useful.
    if (!(z > face.near_m)) return false;
    nearest_m = std::min(nearest_m, z);
    const double u = (glm::dot(d, face.right) / z * face.scale_x * 0.5 + 0.5) * width;
    const double v = (glm::dot(d, face.up) / z * face.scale_y * 0.5 + 0.5) * height;
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
    v_lo = std::min(v_lo, v);
    v_hi = std::max(v_hi, v);
  }
  // Texels the box covers, a texel more each way, clamped to the face.
  const double x0 = std::max(0.0, std::floor(u_lo) - 1),
               x1 = std::min(width - 1.0, std::floor(u_hi) + 1);
  const double y0 = std::max(0.0, std::floor(v_lo) - 1),
               y1 = std::min(height - 1.0, std::floor(v_hi) + 1);
  if (x0 > x1 || y0 > y1) return true;  // beside the face: lands on no texel of it
  const float threshold = float(face.near_m / (nearest_m * (1 - kHiddenMargin)));
  // The finest level where the rectangle spans at most 4 x 4 blocks.
  size_t level = 0;
  int bx0 = int(x0), bx1 = int(x1), by0 = int(y0), by1 = int(y1);
  while (level + 1 < pyramid.levels.size() && (bx1 - bx0 > 3 || by1 - by0 > 3)) {
    ++level;
    bx0 >>= 1, bx1 >>= 1, by0 >>= 1, by1 >>= 1;
  }
  const std::vector<float>& blocks = pyramid.levels[level];
  const size_t w = size_t(pyramid.widths[level]);
  for (int y = by0; y <= by1; ++y) {
    for (int x = bx0; x <= bx1; ++x) {
      if (!(blocks[size_t(y) * w + size_t(x)] > threshold)) return false;
    }
  }
  return true;
}

double boxDistance(const TriangleChunk& chunk, const glm::dvec3& eye) {
  const glm::dvec3 outside = glm::max(glm::max(chunk.lo - eye, eye - chunk.hi), glm::dvec3(0.0));
  return glm::length(outside);
}

void splitNearest(std::span<const TriangleChunk> chunks, std::span<const uint32_t> candidates,
                  const glm::dvec3& eye, uint64_t first_triangles, std::vector<uint32_t>& first,
                  std::vector<uint32_t>& rest) {
  first.clear();
  rest.clear();
  std::vector<std::pair<double, uint32_t>> by_distance;
  by_distance.reserve(candidates.size());
  for (uint32_t i : candidates) by_distance.push_back({boxDistance(chunks[i], eye), i});
  std::sort(by_distance.begin(), by_distance.end());
  uint64_t taken = 0;
  for (const auto& [distance, i] : by_distance) {
    if (first.empty() || taken < first_triangles) {
      first.push_back(i);
      taken += chunks[i].count;
    } else {
      rest.push_back(i);
    }
  }
  std::sort(first.begin(), first.end());
  std::sort(rest.begin(), rest.end());
}

}  // namespace svit::gl

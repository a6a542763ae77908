#pragma once
// Occlusion culling for perspective index-map faces, in two passes. A face
// first draws the chunks nearest its eye (in a closed level, the walls and
// floor around it); their depth, read back as a pyramid of farthest depths,
// then hides every other chunk whose box lies wholly behind the farthest
// surface over the box's texels. A hidden chunk could not win a texel, and
// the small-polygon fallback finds each of its vertices behind a nearer
// surface, so the map and its credits are those of drawing everything
// (bar the order of exact depth ties). What it spares grows with the level:
// from inside a room, the rest of a house is behind its walls.

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "index_map_culling.h"

namespace svit::gl {

/// Farthest reversed depth (near / distance; 0 = cleared, nothing drawn) of
/// each 2^k x 2^k block of a face, level 0 being the texels.
struct DepthPyramid {
  std::vector<int> widths, heights;
  std::vector<std::vector<float>> levels;
};

/// Builds the pyramid of a width x height depth image (rows bottom up).
/// Rows below `first_row` (a half face's, never drawn into) count as
/// nearest: nothing there is ever drawn or reduced.
void buildDepthPyramid(std::span<const float> depth, int width, int height, int first_row,
                       DepthPyramid& out);

/// A perspective face: a point at d = p - eye lands at texel
/// ((right.d / forward.d * scale_x + 1) / 2 * width, same for up) with
/// reversed depth near / forward.d. Directions are unit world vectors.
struct FaceProjection {
  glm::dvec3 eye{0}, right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, 1};
  double scale_x = 1, scale_y = 1, near_m = 0;
};

/// Whether every point of `chunk`'s box is farther than the farthest
/// surface of `pyramid` over the texels the box covers (grown by a texel
/// each way: the fallback's edge taps look half a texel beside a vertex),
/// by a relative margin above depth precision and the fallback's slack.
bool chunkHidden(const TriangleChunk& chunk, const FaceProjection& face,
                 const DepthPyramid& pyramid);

/// Distance from `eye` to the chunk's box (0 inside it), m.
double boxDistance(const TriangleChunk& chunk, const glm::dvec3& eye);

/// Splits `candidates` (indices into `chunks`) into the nearest to `eye`,
/// nearest first until they hold `first_triangles` (one chunk at least),
/// and the rest; both in index order.
void splitNearest(std::span<const TriangleChunk> chunks, std::span<const uint32_t> candidates,
                  const glm::dvec3& eye, uint64_t first_triangles, std::vector<uint32_t>& first,
                  std::vector<uint32_t>& rest);

}  // namespace svit::gl

#pragma once
// Generated levels for the leak tests (issue 22 item 5): sealed spaces and
// floors under walls, built the ways users model them. Each level comes
// with probe points inside the dark space and outside in the light.

#include <string>
#include <vector>

#include "baker/test_scenes.h"
#include "svit/baked_surfaces.h"
#include "svit/baker/bake.h"

namespace svit::test {

/// A generated level and where to look.
struct LeakLevel {
  std::string name;
  Scene scene;
  std::string sun_json, sky_json;  ///< level.json's objects; empty: none
  std::vector<ProbePoint> dark;    ///< must read (almost) black
  /// Dark floor within half a texel of a wall the floor runs under from the
  /// light, where bilinear filtering would read a lit texel straddling the
  /// wall: must read black too.
  std::vector<ProbePoint> edge;
  std::vector<ProbePoint> lit;  ///< the light the dark ones are measured against
};

/// How a leak level is baked (seed 7, quality 0.5, 4 passes, 10 texels/m,
/// its sun and sky), from its glTF at `gltf` into `out_dir`.
inline baker::BakeOptions leakBakeOptions(const LeakLevel& level, const std::string& gltf,
                                          const std::string& out_dir) {
  baker::BakeOptions options;
  options.level_path = gltf;
  options.out_dir = out_dir;
  options.seed = 7;
  options.quality = 0.5;
  options.passes = 4;
  options.texels_per_m = 10;
  options.sun_json = level.sun_json;
  options.sky_json = level.sky_json;
  return options;
}

/// Axis-aligned box of six outward quads as one mesh (a slab, a crate).
inline std::vector<Vec3> boxCorners(Vec3 lo, Vec3 hi) {
  const float x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
  const auto quad = [](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    return std::vector<Vec3>{a, b, c, a, c, d};
  };
  std::vector<Vec3> corners;
  for (const std::vector<Vec3>& q :
       {quad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}),     // -y
        quad({x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}),     // +y
        quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}),     // -x
        quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}),     // +x
        quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}),     // -z
        quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1})}) {  // +z
    corners.insert(corners.end(), q.begin(), q.end());
  }
  return corners;
}

/// The same box with every face turned inwards (a room seen from inside).
inline std::vector<Vec3> roomCorners(Vec3 lo, Vec3 hi) {
  std::vector<Vec3> corners = boxCorners(lo, hi);
  for (size_t t = 0; t + 2 < corners.size(); t += 3) std::swap(corners[t + 1], corners[t + 2]);
  return corners;
}

/// Every leak case: a sunlit ground with sealed spaces on it, and two
/// lamp-lit/dark room pairs split by one partition.
std::vector<LeakLevel> leakLevels();

}  // namespace svit::test

#pragma once
// The static triangles a bake lit, rebuilt from the level and the bake's
// triangle list, with the lookup a shader does: the nearest static surface
// point facing a normal and the lightmap irradiance there. Shared by
// svit-probe and the runtime so both read the bake the same way.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/lightmap_image.h"
#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

/// Where a query point lands on the static surfaces.
struct SurfaceHit {
  uint32_t triangle = 0;  ///< bake triangle order (BakeData::triangle_uvs)
  int side = 0;           ///< 0 front, 1 back (double-sided triangles only)
  Vec3 point;             ///< nearest point on the triangle, world metres
  float w1 = 0, w2 = 0;   ///< barycentric weights of corners 1 and 2
  double distance_m = 0;  ///< from the query point
  uint32_t page = 0;      ///< lightmap page of that side (kUnlitBackPage: a back no light reaches)
  Vec2 uv;                ///< lightmap page coordinates there (the back's own where it has one)
};

class BakedSurfaces {
 public:
  /// Rebuilds the bake's static triangles in world space from `scene`.
  /// Errors name the bake element: an instance or mesh triangle out of range,
  /// a dynamic instance in the triangle list, a back lightmap of a one-sided
  /// triangle.
  static Expected<BakedSurfaces> build(const Scene& scene, const BakeData& bake);

  size_t triangleCount() const { return normals_.size(); }
  /// World position of corner k (0..2) of triangle t.
  const Vec3& corner(size_t t, int k) const { return positions_[t * 3 + size_t(k)]; }
  const Vec3& normal(size_t t) const { return normals_[t]; }  ///< unit, front side
  float area(size_t t) const { return areas_m2_[t]; }
  bool doubleSided(size_t t) const { return double_sided_[t] != 0; }
  const Aabb& bounds() const { return bounds_; }

  /// The nearest point on a triangle side whose normal is within
  /// acos(cos_limit) of `normal` (need not be unit); nullopt when none faces
  /// it. Brute force over the triangles: O(triangles) per query.
  std::optional<SurfaceHit> nearest(const Vec3& point, const Vec3& normal,
                                    double cos_limit = 0.5) const;

 private:
  std::vector<Vec3> positions_;
  std::vector<Vec3> normals_;
  std::vector<float> areas_m2_;
  std::vector<uint8_t> double_sided_;
  std::vector<uint32_t> page_;  ///< 2 per triangle: front, back
  std::vector<Vec2> uvs_;       ///< 6 per triangle: the front's 3, the back's 3
  Aabb bounds_;
};

/// A point to look the bake up at, as svit-probe and svit-walk read them.
struct ProbePoint {
  Vec3 position;  ///< world, metres
  Vec3 normal;    ///< the surface side asked about (need not be unit)
};

/// Reads "x y z nx ny nz" lines (blank lines and '#' comments skipped).
/// Errors name the file and line: `points.txt:3: expected 6 numbers
/// 'x y z nx ny nz'`, non-finite values, a zero normal.
Expected<std::vector<ProbePoint>> readProbePoints(const std::string& path);

/// Reads every lightmap page of a bake from `bake_dir`. Errors name the file.
Expected<std::vector<LightmapImage>> readLightmapPages(const BakeData& bake,
                                                       const std::string& bake_dir);

}  // namespace svit

#pragma once
// The static part of a level flattened into world space: what the baker
// lights. Dynamic instances are left out (the runtime handles them).

#include <cstdint>
#include <vector>

#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

/// World-space static triangles with their materials, in instance order then
/// mesh triangle order (deterministic).
struct BakeGeometry {
  std::vector<Vec3> positions;  ///< world, metres; 3 per triangle (unshared)
  std::vector<Vec3> normals;    ///< geometric unit normal per triangle (front = CCW side)
  std::vector<float> areas_m2;  ///< per triangle
  std::vector<Rgb> albedo;      ///< per triangle, diffuse reflectance in [0, 1]
  /// per triangle, luminance cd/m2 (front side; both if two-sided)
  std::vector<Rgb> emission;
  std::vector<uint8_t> double_sided;    ///< per triangle: 1 = receives/reflects/emits on both sides
  std::vector<uint32_t> instance;       ///< per triangle, index into Scene::instances
  std::vector<uint32_t> mesh_triangle;  ///< per triangle, index within the instance's mesh
  Aabb bounds;                          ///< of all triangles

  size_t triangleCount() const { return areas_m2.size(); }
  /// World position of corner `k` (0..2) of triangle `t`.
  const Vec3& corner(size_t t, int k) const { return positions[t * 3 + size_t(k)]; }
};

/// Flattens the static instances of `scene`. A triangle whose world-space
/// area is zero (an instance scaled flat along it) is skipped and counted in
/// `skipped_degenerate`. Errors, naming node, mesh and triangle: a corner
/// or area beyond float range in world space (finite data under a finite
/// transform can overflow); nothing static remains.
Expected<BakeGeometry> flattenStaticGeometry(const Scene& scene,
                                             size_t* skipped_degenerate = nullptr);

}  // namespace svit::baker

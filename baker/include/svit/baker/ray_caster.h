#pragma once
// Ray casting behind a small interface, so the solver never sees Embree and
// tests can swap in a brute-force caster (docs/style.md §1).

#include <cstdint>
#include <limits>
#include <memory>
#include <span>

#include "svit/baker/bake_geometry.h"

namespace svit::baker {

/// A ray. `origin` should already be offset off its surface with
/// offsetRayOrigin(); hits with t in [t_near, t_far] count.
struct Ray {
  Vec3 origin;
  Vec3 direction;  ///< need not be unit; t is in units of |direction|
  float t_near = 0.0f;
  float t_far = std::numeric_limits<float>::infinity();
};

/// Closest hit of a ray.
struct RayHit {
  static constexpr uint32_t kNone = 0xffffffffu;
  uint32_t triangle = kNone;  ///< index into BakeGeometry, kNone on a miss
  float t = 0.0f;             ///< distance along the ray in units of |direction|
  float u = 0.0f, v = 0.0f;   ///< barycentrics: p = (1-u-v)*c0 + u*c1 + v*c2
  bool front = true;          ///< ray arrived on the triangle's front (normal) side
  bool hit() const { return triangle != kNone; }
};

/// Finds closest hits for batches of rays over one BakeGeometry.
/// Thread-safe: `intersect` may be called from many threads at once.
/// Deterministic: the same ray gives the same hit, whatever the batching.
class RayCaster {
 public:
  virtual ~RayCaster() = default;
  /// Closest hit for each ray; `hits.size() == rays.size()`.
  virtual void intersect(std::span<const Ray> rays, std::span<RayHit> hits) const = 0;
  /// Name for reports ("embree", "brute-force").
  virtual const char* name() const = 0;
};

/// Embree 3 caster (robust scene flag, high build quality). The geometry must
/// outlive the caster. Error when Embree cannot be initialised.
Expected<std::unique_ptr<RayCaster>> makeEmbreeCaster(const BakeGeometry& geometry);

/// O(triangles) per ray, Moeller-Trumbore in double: the oracle for tests.
std::unique_ptr<RayCaster> makeBruteForceCaster(const BakeGeometry& geometry);

/// Moves a ray origin `p` on a surface off it along the surface's unit
/// geometric normal `n` (towards the side the ray leaves from) by 16 units in
/// the last place (ULPs) of `magnitude_m`, the largest absolute coordinate of
/// the surface's corners (cornerMagnitude() of its triangle; |p| when larger).
/// Float32 corners and points carry absolute error ~magnitude * 2^-23, and so
/// does Embree's test against them, so a fixed epsilon self-intersects far
/// from the origin and leaks in small scenes; this offset is a fixed fraction
/// (2^-19 to 2^-20) of the magnitude, so a level scaled by a power of two gets
/// exactly scaled offsets, and a 4 m room 10 km out moves its origins by
/// 1.6 cm, not the 0.25 m of a per-coordinate 256-ULP offset.
/// Non-finite input is returned unchanged. Thread-safe.
Vec3 offsetRayOrigin(const Vec3& p, const Vec3& n, float magnitude_m);

/// The largest absolute corner coordinate of triangle `t` (metres): the
/// magnitude offsetRayOrigin() wants for points on that triangle.
float cornerMagnitude(const BakeGeometry& geometry, size_t t);

}  // namespace svit::baker

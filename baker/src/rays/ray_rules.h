#pragma once
// Rules both ray casters apply identically, so they agree bit for bit:
// garbage rays miss, t_near is raised to 0 (Embree requires 0 <= tnear <=
// tfar; its queries check nothing and this build does not filter invalid
// rays, so a NaN would be undefined behaviour), and the front side is
// judged from BakeGeometry's normal in double, not Embree's unnormalised Ng.

#include <cmath>

#include "scene/numeric.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {

/// The ray's usable [t_near, t_far], or false when it must miss.
inline bool usableSegment(const Ray& ray, float* t_near, float* t_far) {
  if (!finite(ray.origin) || !finite(ray.direction)) return false;
  if (ray.direction.x == 0.0f && ray.direction.y == 0.0f && ray.direction.z == 0.0f) return false;
  if (!std::isfinite(ray.t_near) || std::isnan(ray.t_far)) return false;
  *t_near = ray.t_near > 0.0f ? ray.t_near : 0.0f;
  *t_far = ray.t_far;
  return *t_near <= *t_far;
}

/// Whether a ray along `direction` arrives on the front of a triangle with
/// geometric normal `normal`.
inline bool arrivesOnFront(const Vec3& direction, const Vec3& normal) {
  return double(direction.x) * normal.x + double(direction.y) * normal.y +
             double(direction.z) * normal.z <
         0.0;
}

}  // namespace svit::baker

// Ray origin offsetting: the integer-ULP idea of Waechter & Binder, "A Fast
// and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems (2019),
// chapter 6, adapted to how the baker makes its origins.
//
// A float32 point on a triangle lies off the true surface by about one ULP
// of the triangle's coordinates, and Embree's intersection test against the
// triangle errs by a few ULPs of the same magnitude (it works on corner
// minus origin differences). The paper moves each coordinate by 256 ULPs of
// that coordinate (its points are reconstructed from a hit distance, with
// larger error) and, below |coordinate| 1/32, by a fixed 2^-16 m. Both break
// scale invariance: the fixed 2^-16 m is 1.5% of a 1 mm room, and 256 ULPs
// of 1e4 m are 0.25 m, a bias of up to 13% in a 4 m room 10 km from the
// origin (tests/stability, Origin.LevelTenKilometresFromTheOrigin). Here
// the baker's origins are sampled on the triangle in double and rounded once,
// so the point moves along the normal by kOffsetUlps ULPs of the triangle's
// largest corner coordinate: the same relative offset at every scale and
// position.
//
// kOffsetUlps: chosen so that no ray self-intersects with Embree 3.13
// (robust mode) on tilted planes at 0 to 1e5 m, 1 mm to 10 km wide, and on
// a tiny triangle between coplanar neighbours 1e8 times larger, rays
// uniform over the hemisphere (grazing ones included) from float-arithmetic
// barycentric points: 4 ULPs holds there and 2 does not, so 16 keeps a
// factor 4 (tests/stability/stability_geometry_test.cpp,
// Offsets.NoSelfIntersectionAtAnyScaleOrDistance, checks it).

#include <algorithm>
#include <cmath>

#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

// ULPs of the triangle's magnitude by which an origin moves (see above).
constexpr float kOffsetUlps = 16.0f;

}  // namespace

float cornerMagnitude(const BakeGeometry& geometry, size_t t) {
  float m = 0.0f;
  for (int k = 0; k < 3; ++k) {
    const Vec3& c = geometry.corner(t, k);
    m = std::max({m, std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)});
  }
  return m;
}

Vec3 offsetRayOrigin(const Vec3& p, const Vec3& n, float magnitude_m) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(n.x) ||
      !std::isfinite(n.y) || !std::isfinite(n.z) || !std::isfinite(magnitude_m)) {
    return p;
  }
  const float magnitude =
      std::max({std::fabs(magnitude_m), std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  // A point at the origin of a triangle with all corners there has no
  // magnitude; the smallest normal float keeps the offset defined.
  const int exponent = std::ilogb(std::max(magnitude, 1.17549435e-38f));
  // A power of two: n * step is exact, so scaled levels get scaled offsets.
  const float step = kOffsetUlps * std::ldexp(1.0f, exponent - 23);
  return {p.x + n.x * step, p.y + n.y * step, p.z + n.z * step};
}

}  // namespace svit::baker

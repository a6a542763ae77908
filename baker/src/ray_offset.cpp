// Ray origin offsetting after Waechter & Binder, "A Fast and Robust Method
// for Avoiding Self-Intersection", Ray Tracing Gems (2019), chapter 6.
//
// A point on a surface computed in float32 lies off the true surface by a few
// ULPs of its coordinates, so the distance it must move to be safely on one
// side grows with |p|. The paper moves each coordinate by a fixed number of
// ULPs (an integer added to the float's bit pattern) scaled by that component
// of the normal; near zero, where ULPs shrink towards denormals and the
// surface's own error is no longer relative, it adds a small fixed distance.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

// The paper's constants.
// ULPs per unit of normal: a coordinate moves by up to 256 ULPs, i.e. at most
// 256 * 2^-23 ~ 3.1e-5 of its magnitude.
constexpr float kIntScale = 256.0f;
// Metres per unit of normal added near the origin (2^-16 m ~ 15 um).
constexpr float kFloatScale = 1.0f / 65536.0f;
// Below this |coordinate| (metres, 2^-5) the fixed offset is used: there
// 256 ULPs would be less than kFloatScale, and near zero far less.
constexpr float kOriginThreshold = 1.0f / 32.0f;

// One coordinate `p` moved towards the sign of `n` (a normal component).
float offsetCoordinate(float p, float n) {
  if (!std::isfinite(p) || !std::isfinite(n)) return p;
  if (std::fabs(p) < kOriginThreshold) return p + kFloatScale * n;
  // A unit normal's components lie in [-1, 1]; the clamp keeps a sloppy one
  // from overflowing the cast. The cast truncates towards zero as in the
  // paper (components below 1/256 add no ULPs).
  const int32_t ulps = int32_t(kIntScale * std::clamp(n, -1.0f, 1.0f));
  // Adding to the bit pattern grows the magnitude; for a negative p that
  // moves towards -infinity, so the ULP count flips sign with p.
  const int32_t bits = std::bit_cast<int32_t>(p);
  return std::bit_cast<float>(p < 0.0f ? bits - ulps : bits + ulps);
}

}  // namespace

Vec3 offsetRayOrigin(const Vec3& p, const Vec3& n) {
  return {offsetCoordinate(p.x, n.x), offsetCoordinate(p.y, n.y), offsetCoordinate(p.z, n.z)};
}

}  // namespace svit::baker

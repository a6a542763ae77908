#pragma once
// The numbers svit writes once: pi, the Rec.709 luminance weights, finiteness
// of vectors and matrices, and the "no bound" box. Internal: the baker, the
// scene library and the GL runtime include it; the public luminance() of
// svit/math_types.h uses the same weights in float.

#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

#include "svit/math_types.h"

namespace svit {

inline constexpr double kPi = std::numbers::pi;

/// ITU-R BT.709 weights of linear R, G, B in relative luminance Y.
inline constexpr double kLuminanceR = 0.2126;
inline constexpr double kLuminanceG = 0.7152;
inline constexpr double kLuminanceB = 0.0722;

inline double luminanceOf(const glm::dvec3& c) {
  return kLuminanceR * c.x + kLuminanceG * c.y + kLuminanceB * c.z;
}
inline double luminanceOf(const Rgb& c) {
  return kLuminanceR * c.r + kLuminanceG * c.g + kLuminanceB * c.b;
}
/// Y of the magnitudes, for sizes of signed colour deltas.
inline double absLuminanceOf(const glm::dvec3& c) {
  return kLuminanceR * std::abs(c.x) + kLuminanceG * std::abs(c.y) + kLuminanceB * std::abs(c.z);
}

inline bool finite(float v) { return std::isfinite(v); }
inline bool finite(const Vec2& v) { return finite(v.x) && finite(v.y); }
inline bool finite(const Vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
inline bool finite(const Rgb& c) { return finite(c.r) && finite(c.g) && finite(c.b); }
inline bool finite(const Mat4& m) {
  for (float v : m.m) {
    if (!finite(v)) return false;
  }
  return true;
}
inline bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Bounds for min/max accumulation in double: any finite point replaces them.
inline constexpr double kNoLowerBound = -1e300;
inline constexpr double kNoUpperBound = 1e300;

}  // namespace svit

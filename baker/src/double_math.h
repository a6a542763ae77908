#pragma once
// Conversions between the public float types and the double-precision GLM
// vectors the baker computes in, and the photometric luminance of linear
// Rec.709 RGB (BT.709 weights, as svit::luminance).

#include <glm/glm.hpp>

#include "svit/math_types.h"

namespace svit::baker {

inline glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }
inline glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }
inline Vec3 vec3(const glm::dvec3& v) { return {float(v.x), float(v.y), float(v.z)}; }
inline Rgb rgb(const glm::dvec3& c) { return {float(c.x), float(c.y), float(c.z)}; }
inline double luminanceOf(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline double luminanceOf(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace svit::baker

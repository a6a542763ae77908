#pragma once
// Conversions between the public float types and the double-precision GLM
// vectors the baker computes in; the photometric luminance of linear
// Rec.709 RGB is numeric.h's luminanceOf, visible here as baker's own.

#include <glm/glm.hpp>

#include "scene/numeric.h"
#include "svit/math_types.h"

namespace svit::baker {

inline glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }
inline glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }
inline Vec3 vec3(const glm::dvec3& v) { return {float(v.x), float(v.y), float(v.z)}; }
inline Rgb rgb(const glm::dvec3& c) { return {float(c.x), float(c.y), float(c.z)}; }
using svit::luminanceOf;

}  // namespace svit::baker

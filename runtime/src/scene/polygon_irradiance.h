#pragma once
// The cosine-weighted solid angle a triangle subtends at a receiver point
// (irradiance per unit radiance): Lambert's polygon formula, with the
// triangle first clipped to the receiver's hemisphere. Exact, no
// sampling: what a masked area light gives a pixel before shadows
// (shaders/lit_static.frag's svitTriangleIrradiance is the same formula).

#include <glm/glm.hpp>

namespace svit {

/// Integral of max(0, n . w) over the directions w from `p` through the
/// triangle `a`, `b`, `c` (world metres; unit receiver normal `n`),
/// steradians: 0 when the triangle is behind the receiver, at most pi.
double triangleCosineSolidAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                                const glm::dvec3& p, const glm::dvec3& n);

}  // namespace svit

#include "polygon_irradiance.h"

#include <algorithm>
#include <cmath>

namespace svit {
namespace {

// Sutherland-Hodgman against the plane n . v >= 0: a triangle becomes at
// most a quadrilateral. Returns the corner count (0: wholly behind).
int clipToHemisphere(const glm::dvec3 (&in)[3], const glm::dvec3& n, glm::dvec3 (&out)[4]) {
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3& from = in[i];
    const glm::dvec3& to = in[(i + 1) % 3];
    const double h_from = glm::dot(n, from), h_to = glm::dot(n, to);
    if (h_from >= 0) out[count++] = from;
    if ((h_from >= 0) != (h_to >= 0))
      out[count++] = from + (to - from) * (h_from / (h_from - h_to));
  }
  return count;
}

}  // namespace

double triangleCosineSolidAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                                const glm::dvec3& p, const glm::dvec3& n) {
  const glm::dvec3 corners[3] = {a - p, b - p, c - p};
  glm::dvec3 polygon[4];
  const int count = clipToHemisphere(corners, n, polygon);
  if (count < 3) return 0.0;
  // Lambert: (1/2) sum over edges of the edge's angle x n . the unit
  // normal of the plane through p and the edge.
  double sum = 0;
  for (int i = 0; i < count; ++i) {
    const double li = glm::length(polygon[i]), lj = glm::length(polygon[(i + 1) % count]);
    if (!(li > 0) || !(lj > 0)) continue;
    const glm::dvec3 u = polygon[i] / li, v = polygon[(i + 1) % count] / lj;
    const glm::dvec3 cross = glm::cross(u, v);
    const double sine = glm::length(cross);
    if (!(sine > 1e-12)) continue;
    const double angle = std::atan2(sine, glm::dot(u, v));
    sum += angle * glm::dot(n, cross / sine);
  }
  return std::min(std::abs(0.5 * sum), 3.14159265358979323846);
}

}  // namespace svit

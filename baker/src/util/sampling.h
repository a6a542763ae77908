#pragma once
// Warps from the unit square to the directions and points the shooter needs.
// Each maps uniform numbers to the stated density exactly (Shirley & Chiu
// 1997 concentric disk for the cosine lobe, pbrt-v4 section A.5).

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "scene/numeric.h"

namespace svit::baker {

using svit::kPi;

/// Orthonormal basis (t, b, n) around unit `n` (Duff et al. 2017, branchless).
inline void basisAround(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::dvec3(c, sign + n.y * n.y * a, -n.y);
}

/// Uniform point on the unit disk (concentric map).
inline glm::dvec2 concentricDisk(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) return {0.0, 0.0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0) * (b / a);
  } else {
    r = b;
    phi = (kPi / 2.0) - (kPi / 4.0) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

/// Cosine-weighted direction around unit `n` (pdf cos(theta)/pi).
inline glm::dvec3 cosineHemisphere(const glm::dvec3& n, double u1, double u2) {
  const glm::dvec2 d = concentricDisk(u1, u2);
  const double z = std::sqrt(std::max(0.0, 1.0 - d.x * d.x - d.y * d.y));
  glm::dvec3 t, b;
  basisAround(n, t, b);
  return d.x * t + d.y * b + z * n;
}

/// Uniform direction on the sphere.
inline glm::dvec3 uniformSphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Direction around unit `axis` with cos(angle) = `cos_theta`, azimuth 2*pi*u.
inline glm::dvec3 directionAt(const glm::dvec3& axis, double cos_theta, double u) {
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * kPi * u;
  glm::dvec3 t, b;
  basisAround(axis, t, b);
  return sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * b + cos_theta * axis;
}

/// Uniform barycentrics (b1, b2) on a triangle (Osada et al. 2002).
inline glm::dvec2 uniformTriangle(double u1, double u2) {
  const double s = std::sqrt(u1);
  return {s * (1.0 - u2), s * u2};  // weights of corners 1 and 2
}

/// Solid angle of the spherical triangle with unit corner directions a, b,
/// c (Van Oosterom & Strackee 1983: accurate for small triangles too).
inline double sphericalTriangleArea(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double triple = std::abs(glm::dot(a, glm::cross(b, c)));
  return 2.0 * std::atan2(triple, 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a));
}

/// Uniform direction (pdf 1 / `area`) in the spherical triangle with unit
/// corner directions a, b, c of solid angle `area` (Arvo 1995, "Stratified
/// sampling of spherical triangles"): u1 picks the sub-triangle A B C' of
/// area u1 * area, u2 the point along the arc from B to C'. Stratified in
/// (u1, u2) as the unit square is.
inline glm::dvec3 sphericalTriangleDirection(const glm::dvec3& a, const glm::dvec3& b,
                                             const glm::dvec3& c, double area, double u1,
                                             double u2) {
  // Where the arc from `from` towards `to` leaves `from`, as a unit tangent.
  const auto tangent = [](const glm::dvec3& from, const glm::dvec3& to) {
    const glm::dvec3 t = to - glm::dot(to, from) * from;
    const double length = glm::length(t);
    return length > 0 ? t / length : t;
  };
  const double cos_alpha = std::clamp(glm::dot(tangent(a, b), tangent(a, c)), -1.0, 1.0);
  const double sin_alpha = std::sqrt(std::max(0.0, 1.0 - cos_alpha * cos_alpha));
  const double alpha = std::acos(cos_alpha);
  // C' on the arc A C such that A B C' has area u1 * area.
  const double sub_area = u1 * area;
  const double s = std::sin(sub_area - alpha), t = std::cos(sub_area - alpha);
  const double u = t - cos_alpha;
  const double v = s + sin_alpha * glm::dot(a, b);
  const double denominator = (v * s + u * t) * sin_alpha;
  const double q = denominator != 0
                       ? std::clamp(((v * t - u * s) * cos_alpha - v) / denominator, -1.0, 1.0)
                       : 1.0;
  const glm::dvec3 c_sub = q * a + std::sqrt(std::max(0.0, 1.0 - q * q)) * tangent(a, c);
  // The point on the arc B C' at the cosine that makes the density uniform.
  const double z = 1.0 - u2 * (1.0 - glm::dot(c_sub, b));
  return z * b + std::sqrt(std::max(0.0, 1.0 - z * z)) * tangent(b, c_sub);
}

}  // namespace svit::baker

// Index-map layouts and texel weights (thesis 5.2.4, "choice of the
// projection"): which cube faces cover a lobe, and how much of it each
// layout misses, summed numerically from the very texel weights the GPU
// reduction uses so the choice and the reduction cannot disagree.

#include "index_map_layouts.h"

#include <algorithm>
#include <cmath>

#include "scene/numeric.h"

namespace svit::gl {
namespace {

// Any unit vector perpendicular to unit `n`, a fixed function of n so a
// sample's frame only turns when its roll does.
glm::dvec3 perpendicular(const glm::dvec3& n) {
  const glm::dvec3 a = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

}  // namespace

FaceBasis cubeFaceBasis(int face) {
  static const glm::dvec3 kForward[kCubeFaceCount] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                                      {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  static const glm::dvec3 kUp[kCubeFaceCount] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1},
                                                 {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  FaceBasis b;
  b.forward = kForward[face];
  b.up = kUp[face];
  b.right = glm::cross(b.forward, b.up);
  return b;
}

LayoutFaces layoutFaces(MapLayout layout) {
  switch (layout) {
    case MapLayout::kSingle:
    case MapLayout::kParallel: return {1, {kPosZ}};
    case MapLayout::kTriple: return {3, {kPosX, kPosY, kPosZ}};
    case MapLayout::kHemicube: return {5, {kPosZ, kPosX, kNegX, kPosY, kNegY}};
    case MapLayout::kCube: return {6, {kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ}};
  }
  return {};
}

uint32_t layoutFaceMask(MapLayout layout) {
  const LayoutFaces faces = layoutFaces(layout);
  uint32_t mask = 0;
  for (int i = 0; i < faces.count; ++i) mask |= 1u << faces.faces[size_t(i)];
  return mask;
}

bool isHalfFace(MapLayout layout, int face) {
  return layout == MapLayout::kHemicube && face != kPosZ;
}

int firstRow(MapLayout layout, int face, int resolution) {
  return isHalfFace(layout, face) ? resolution / 2 : 0;
}

double faceArea(MapLayout layout) {
  switch (layout) {
    case MapLayout::kSingle:
    case MapLayout::kParallel: return 1;
    case MapLayout::kTriple:
    case MapLayout::kHemicube: return 3;
    case MapLayout::kCube: return 6;
  }
  return 0;
}

glm::dmat3 mapFrame(const Vec3& axis, float roll_rad) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(axis.x, axis.y, axis.z));
  const glm::dvec3 p = perpendicular(n);
  const glm::dvec3 q = glm::cross(n, p);
  const double c = std::cos(double(roll_rad)), s = std::sin(double(roll_rad));
  const glm::dvec3 t1 = c * p + s * q;
  const glm::dvec3 t2 = glm::cross(n, t1);  // t1 x t2 = n: right-handed
  return glm::dmat3(t1, t2, n);
}

glm::dmat3 worldFromCube(MapLayout layout, const glm::dmat3& map_frame) {
  if (layout != MapLayout::kTriple) return map_frame;
  // Cube coordinates with the corner on the axis: an orthonormal right-handed
  // basis (e1, e2, corner) of the cube maps onto (t1, t2, axis).
  const glm::dvec3 e1 = glm::dvec3(1, -1, 0) / std::sqrt(2.0);
  const glm::dvec3 e2 = glm::dvec3(1, 1, -2) / std::sqrt(6.0);
  const glm::dvec3 corner = glm::dvec3(1, 1, 1) / std::sqrt(3.0);
  const glm::dmat3 cube_basis(e1, e2, corner);
  return map_frame * glm::transpose(cube_basis);
}

glm::dvec3 cubeAxis(MapLayout layout) {
  return layout == MapLayout::kTriple ? glm::dvec3(1, 1, 1) / std::sqrt(3.0) : glm::dvec3(0, 0, 1);
}

double lobeProfile(Lobe lobe, double cos_inner, double cos_outer, double cos_theta) {
  switch (lobe) {
    case Lobe::kCosine: return std::max(cos_theta, 0.0);
    case Lobe::kIsotropic: return 1.0;
    case Lobe::kSpot: {
      if (cos_inner <= cos_outer) return cos_theta >= cos_outer ? 1.0 : 0.0;
      const double t = std::clamp((cos_theta - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
      return t * t;
    }
    case Lobe::kParallel: return 0.0;
  }
  return 0.0;
}

double lobeIntegral(Lobe lobe, double cos_inner, double cos_outer) {
  switch (lobe) {
    case Lobe::kCosine: return kPi;
    case Lobe::kIsotropic: return 4 * kPi;
    case Lobe::kSpot:
      // 2 pi * (integral of t(c)^2 dc): the full cap inside the inner cone
      // plus (ci - co) / 3 for t linear in c over [co, ci].
      if (cos_inner <= cos_outer) return 2 * kPi * (1 - cos_outer);
      return 2 * kPi * ((1 - cos_inner) + (cos_inner - cos_outer) / 3);
    case Lobe::kParallel: return 0.0;
  }
  return 0.0;
}

double texelCentre(int resolution, int i) { return (2.0 * i + 1.0) / resolution - 1.0; }

double texelSolidAngle(int resolution, double u, double v) {
  const double h = 2.0 / resolution;
  const double r2 = 1 + u * u + v * v;
  return h * h / (r2 * std::sqrt(r2));
}

LobeCoverage lobeCoverage(Lobe lobe, double cos_inner, double cos_outer, int resolution) {
  LobeCoverage out;
  if (lobe == Lobe::kParallel) {
    out.missed.fill(1.0);
    out.missed[size_t(MapLayout::kParallel)] = 0.0;
    out.normaliser_face_axis = out.normaliser_corner_axis = 1.0;
    return out;
  }
  // Per orientation and face: the whole face and its upper half.
  double full[2][kCubeFaceCount] = {}, upper[2][kCubeFaceCount] = {};
  const glm::dvec3 axes[2] = {cubeAxis(MapLayout::kCube), cubeAxis(MapLayout::kTriple)};
  const int first_upper = resolution / 2;
  for (int f = 0; f < kCubeFaceCount; ++f) {
    const FaceBasis b = cubeFaceBasis(f);
    for (int j = 0; j < resolution; ++j) {
      const double v = texelCentre(resolution, j);
      double row[2] = {0, 0};
      for (int i = 0; i < resolution; ++i) {
        const double u = texelCentre(resolution, i);
        const glm::dvec3 d = b.forward + u * b.right + v * b.up;
        const double inv_len = 1.0 / glm::length(d);
        const double omega = texelSolidAngle(resolution, u, v);
        for (int o = 0; o < 2; ++o) {
          row[o] += omega * lobeProfile(lobe, cos_inner, cos_outer, glm::dot(d, axes[o]) * inv_len);
        }
      }
      for (int o = 0; o < 2; ++o) {
        full[o][f] += row[o];
        if (j >= first_upper) upper[o][f] += row[o];
      }
    }
  }
  double total[2] = {0, 0};
  for (int o = 0; o < 2; ++o) {
    for (int f = 0; f < kCubeFaceCount; ++f) total[o] += full[o][f];
  }
  out.normaliser_face_axis = total[0];
  out.normaliser_corner_axis = total[1];
  auto missed = [&](int o, double covered) {
    return total[o] > 0 ? std::clamp(1.0 - covered / total[o], 0.0, 1.0) : 1.0;
  };
  out.missed[size_t(MapLayout::kSingle)] = missed(0, full[0][kPosZ]);
  out.missed[size_t(MapLayout::kTriple)] =
      missed(1, full[1][kPosX] + full[1][kPosY] + full[1][kPosZ]);
  out.missed[size_t(MapLayout::kHemicube)] = missed(
      0, full[0][kPosZ] + upper[0][kPosX] + upper[0][kNegX] + upper[0][kPosY] + upper[0][kNegY]);
  out.missed[size_t(MapLayout::kCube)] = missed(0, total[0]);
  out.missed[size_t(MapLayout::kParallel)] = 1.0;
  return out;
}

}  // namespace svit::gl

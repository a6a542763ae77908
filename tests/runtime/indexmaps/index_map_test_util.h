#pragma once
// Helpers for the index-map tests: scenes built in code, the conversion to
// the baker's BakeGeometry, and the oracle: Embree rays shot from a point
// sample with the same lobe, on a jittered (stratified) grid so 2^20 rays
// resolve 1% receivers to ~0.1% instead of Monte Carlo's ~1%.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "indexmaps/index_map_layouts.h"
#include "indexmaps/index_map_renderer.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/ray_caster.h"

namespace svit::test {

inline constexpr double kTestPi = std::numbers::pi;

inline Vec3 vec(const glm::dvec3& v) { return {float(v.x), float(v.y), float(v.z)}; }
inline glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }

/// Appends triangle (a, b, c) (CCW = front) with its receivers.
inline void addTriangle(gl::MapTriangles& t, const glm::dvec3& a, const glm::dvec3& b,
                        const glm::dvec3& c, uint32_t front, uint32_t back = gl::kNoReceiver) {
  t.positions.push_back(vec(a));
  t.positions.push_back(vec(b));
  t.positions.push_back(vec(c));
  t.front_receiver.push_back(front);
  t.back_receiver.push_back(back);
}

/// Appends quad origin + [0,1]^2 spanned by (du, dv), front side du x dv, as
/// n x n cells of two triangles each.
inline void addQuad(gl::MapTriangles& t, const glm::dvec3& origin, const glm::dvec3& du,
                    const glm::dvec3& dv, uint32_t front, uint32_t back = gl::kNoReceiver,
                    int n = 1) {
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 p00 = origin + du * (double(i) / n) + dv * (double(j) / n);
      const glm::dvec3 p10 = origin + du * (double(i + 1) / n) + dv * (double(j) / n);
      const glm::dvec3 p01 = origin + du * (double(i) / n) + dv * (double(j + 1) / n);
      const glm::dvec3 p11 = origin + du * (double(i + 1) / n) + dv * (double(j + 1) / n);
      addTriangle(t, p00, p10, p11, front, back);
      addTriangle(t, p00, p11, p01, front, back);
    }
  }
}

/// The six faces of the box [lo, hi], fronts facing inward (`inward`) or
/// outward; receiver `first + face` when `per_face`, else `first`.
inline void addBox(gl::MapTriangles& t, const glm::dvec3& lo, const glm::dvec3& hi, bool inward,
                   uint32_t first, bool per_face = false) {
  const glm::dvec3 e = hi - lo;
  const glm::dvec3 x(e.x, 0, 0), y(0, e.y, 0), z(0, 0, e.z);
  // (origin, du, dv) with du x dv pointing outward.
  const std::tuple<glm::dvec3, glm::dvec3, glm::dvec3> faces[6] = {
      {lo, z, y}, {lo + x, y, z}, {lo, x, z}, {lo + y, z, x}, {lo, y, x}, {lo + z, x, y}};
  for (int f = 0; f < 6; ++f) {
    auto [o, du, dv] = faces[f];
    const uint32_t r = per_face ? first + uint32_t(f) : first;
    if (inward) {
      addQuad(t, o, dv, du, r);
    } else {
      addQuad(t, o, du, dv, r);
    }
  }
}

/// A BakeGeometry (what the RayCaster takes) of the map triangles.
inline baker::BakeGeometry bakeGeometry(const gl::MapTriangles& t) {
  baker::BakeGeometry g;
  g.positions = t.positions;
  for (size_t i = 0; i < t.triangleCount(); ++i) {
    const glm::dvec3 a = dvec(t.positions[3 * i]), b = dvec(t.positions[3 * i + 1]),
                     c = dvec(t.positions[3 * i + 2]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    g.normals.push_back(vec(len > 0 ? n / len : glm::dvec3(0, 0, 1)));
    g.areas_m2.push_back(float(0.5 * len));
    g.albedo.push_back({0.5f, 0.5f, 0.5f});
    g.emission.push_back({});
    g.double_sided.push_back(t.back_receiver[i] != gl::kNoReceiver);
    g.instance.push_back(0);
    g.mesh_triangle.push_back(uint32_t(i));
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = t.positions[3 * i + size_t(k)];
      g.bounds.min = {std::min(g.bounds.min.x, p.x), std::min(g.bounds.min.y, p.y),
                      std::min(g.bounds.min.z, p.z)};
      g.bounds.max = {std::max(g.bounds.max.x, p.x), std::max(g.bounds.max.y, p.y),
                      std::max(g.bounds.max.z, p.z)};
    }
  }
  return g;
}

/// The renderer's near plane for `s` in a scene of diagonal `diagonal_m`
/// (index_map_renderer.cpp: max(1e-4 x diagonal, 1e-6 x max |coordinate|)).
inline double nearPlane(const gl::PointSample& s, double diagonal_m) {
  const double coordinate =
      std::max({std::abs(double(s.position.x)), std::abs(double(s.position.y)),
                std::abs(double(s.position.z)), 1.0});
  return std::max(1e-4 * diagonal_m, 1e-6 * coordinate);
}

inline double diagonal(const Aabb& b) {
  return std::hypot(double(b.max.x) - b.min.x, double(b.max.y) - b.min.y,
                    double(b.max.z) - b.min.z);
}

/// Counter-based uniform in [0, 1) (splitmix64), a pure function of its ids.
inline double hashUniform(uint64_t seed, uint64_t i) {
  uint64_t x = seed * 0x9e3779b97f4a7c15ull + i;
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  x ^= x >> 31;
  return double(x >> 11) * (1.0 / 9007199254740992.0);
}

/// Share of the sample's flux each receiver gets, by grid_n^2 rays on a
/// jittered grid over the lobe (cosine: Malley's disc; isotropic: uniform
/// sphere; spot: uniform over the outer cap, weighted by profile / integral;
/// parallel: the window). Rays start at the sample, t in [near, inf).
inline std::vector<double> rayShares(const baker::RayCaster& caster, const gl::MapTriangles& t,
                                     const gl::PointSample& s, uint32_t receivers, int grid_n,
                                     double near_m, uint64_t seed) {
  std::vector<double> shares(receivers, 0.0);
  const glm::dmat3 frame = gl::mapFrame(s.axis, 0.0f);
  const glm::dvec3 t1 = frame[0], t2 = frame[1], axis = frame[2];
  const double co = s.cos_outer, ci = s.cos_inner;
  const double cap_sr = 2 * kTestPi * (1 - co);
  const double integral = gl::lobeIntegral(s.lobe, ci, co);
  const size_t total = size_t(grid_n) * size_t(grid_n);
  constexpr size_t kChunk = 1 << 16;
  std::vector<baker::Ray> rays;
  std::vector<double> weights;
  std::vector<baker::RayHit> hits;
  for (size_t begin = 0; begin < total; begin += kChunk) {
    const size_t end = std::min(total, begin + kChunk);
    rays.clear();
    weights.clear();
    for (size_t k = begin; k < end; ++k) {
      const double u1 = (double(k % size_t(grid_n)) + hashUniform(seed, 2 * k)) / grid_n;
      const double u2 = (double(k / size_t(grid_n)) + hashUniform(seed, 2 * k + 1)) / grid_n;
      const double phi = 2 * kTestPi * u2;
      glm::dvec3 origin = dvec(s.position), dir = axis;
      double w = 1.0;
      switch (s.lobe) {
        case gl::Lobe::kCosine: {
          const double r = std::sqrt(u1);
          dir = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 +
                std::sqrt(std::max(0.0, 1 - u1)) * axis;
          break;
        }
        case gl::Lobe::kIsotropic: {
          const double z = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - z * z));
          dir = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + z * axis;
          break;
        }
        case gl::Lobe::kSpot: {
          const double z = 1 - u1 * (1 - co), r = std::sqrt(std::max(0.0, 1 - z * z));
          dir = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + z * axis;
          w = gl::lobeProfile(s.lobe, ci, co, z) * cap_sr / integral;
          break;
        }
        case gl::Lobe::kParallel:
          origin += double(s.half_extent_m) * ((2 * u1 - 1) * t1 + (2 * u2 - 1) * t2);
          break;
      }
      if (!(w > 0)) continue;
      baker::Ray ray;
      ray.origin = vec(origin);
      ray.direction = vec(dir);
      ray.t_near = float(near_m);
      rays.push_back(ray);
      weights.push_back(w);
    }
    hits.resize(rays.size());
    caster.intersect(rays, hits);
    for (size_t i = 0; i < rays.size(); ++i) {
      if (!hits[i].hit() || hits[i].triangle == s.own_triangle) continue;
      const uint32_t r =
          hits[i].front ? t.front_receiver[hits[i].triangle] : t.back_receiver[hits[i].triangle];
      if (r < receivers) shares[r] += weights[i];
    }
  }
  for (double& v : shares) v /= double(total);
  return shares;
}

/// Sum of a slot's row of shares.
inline double rowSum(const std::vector<float>& shares, size_t begin, size_t count) {
  double sum = 0;
  for (size_t i = begin; i < begin + count; ++i) sum += shares[i];
  return sum;
}

}  // namespace svit::test

#include "emitter_samples.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "sample_random.h"
#include "scene/glm_interop.h"
#include "scene/numeric.h"

namespace svit::gl {
namespace {

float roll(uint64_t seed, uint64_t stream, uint64_t index, bool jitter) {
  return jitter ? float(2 * kPi) * uniform01(seed, stream ^ 0x726f6c6cull, index) : 0.0f;
}

PointSample parallelSample(const glm::vec3& travel, const ParallelWindow& window, float weight,
                           float roll_rad) {
  PointSample s;
  // The window sits upwind, just outside the bounding sphere.
  s.position = fromGlm(toGlm(window.centre) - travel * (window.radius_m * 1.01f));
  s.axis = fromGlm(travel);
  s.lobe = Lobe::kParallel;
  s.half_extent_m = window.radius_m;
  s.weight = weight;
  s.roll_rad = roll_rad;
  return s;
}

// Any unit vector perpendicular to n.
glm::vec3 perpendicular(const glm::vec3& n) {
  const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

}  // namespace

double lightLobeSolidAngle(const Light& light) {
  if (light.type != LightType::kSpot) return 4 * kPi;
  // 2 pi * integral of t(c)^2 dc over [cos_outer, cos_inner], plus the full
  // cap inside the inner cone: t linear in c gives (ci - co) / 3.
  const double ci = std::cos(double(light.inner_cone_rad)),
               co = std::cos(double(light.outer_cone_rad));
  return 2 * kPi * ((1 - ci) + (ci - co) / 3);
}

std::vector<PointSample> lightSamples(const Light& light, int count, uint64_t seed, uint64_t stream,
                                      bool jitter_roll) {
  std::vector<PointSample> out;
  for (int i = 0; i < count; ++i) {
    PointSample s;
    s.position = light.position;
    s.axis = light.direction;
    if (light.type == LightType::kSpot) {
      s.lobe = Lobe::kSpot;
      s.cos_inner = std::cos(light.inner_cone_rad);
      s.cos_outer = std::cos(light.outer_cone_rad);
    } else {
      s.lobe = Lobe::kIsotropic;
      s.axis = {0, 1, 0};
    }
    s.weight = 1.0f / float(count);
    s.roll_rad = roll(seed, stream, uint64_t(i), jitter_roll);
    out.push_back(s);
  }
  return out;
}

std::vector<PointSample> sunSamples(const Sun& sun, const ParallelWindow& window, int count,
                                    uint64_t seed, bool jitter_roll) {
  const glm::vec3 to_sun = glm::normalize(toGlm(sun.direction_to_sun));
  const glm::vec3 u = perpendicular(to_sun), v = glm::cross(to_sun, u);
  std::vector<PointSample> out;
  for (int i = 0; i < count; ++i) {
    // Directions on the disk: a sunflower spiral (even area coverage).
    const float r =
        count > 1 ? sun.angular_radius_rad * std::sqrt((float(i) + 0.5f) / float(count)) : 0.0f;
    const float phi = float(i) * 2.39996323f;  // golden angle
    const glm::vec3 d =
        glm::normalize(to_sun + std::tan(r) * (std::cos(phi) * u + std::sin(phi) * v));
    out.push_back(parallelSample(-d, window, 1.0f / float(count),
                                 roll(seed, 0x73756eull, uint64_t(i), jitter_roll)));
  }
  return out;
}

std::vector<PointSample> skySamples(const Sky& sky, const ParallelWindow& window, int count,
                                    uint64_t seed, bool jitter_roll, Rgb& flux_out) {
  const bool ground = sky.model == SkyModel::kGradient && luminance(sky.ground_luminance) > 0;
  const int hemispheres = ground ? 2 : 1;
  // Strata equal in solid angle: rings of equal height in cos(theta) (Archimedes), sectors in phi.
  const int per_hemisphere = std::max(4, count / hemispheres);
  const int rings = std::max(1, int(std::lround(std::sqrt(per_hemisphere / 2.0))));
  const int sectors = std::max(2, per_hemisphere / rings);
  const double d_omega = 2 * kPi / double(rings * sectors);
  const double window_area = 4.0 * double(window.radius_m) * double(window.radius_m);
  std::vector<PointSample> out;
  std::vector<double> weights;
  glm::dvec3 flux(0.0);
  for (int h = 0; h < hemispheres; ++h) {
    for (int ring = 0; ring < rings; ++ring) {
      const double mu = (ring + 0.5) / rings;  // |cos theta| at the stratum's centre
      for (int sector = 0; sector < sectors; ++sector) {
        const double phi = 2 * kPi * (sector + 0.5 + 0.5 * (ring % 2)) / sectors;
        const double s = std::sqrt(1 - mu * mu);
        const glm::dvec3 towards_sky(s * std::cos(phi), h == 0 ? mu : -mu, s * std::sin(phi));
        glm::dvec3 l;
        if (h == 1) {
          l = glm::dvec3(sky.ground_luminance.r, sky.ground_luminance.g, sky.ground_luminance.b);
        } else if (sky.model == SkyModel::kGradient) {
          const glm::dvec3 zenith(sky.zenith_luminance.r, sky.zenith_luminance.g,
                                  sky.zenith_luminance.b);
          const glm::dvec3 horizon(sky.horizon_luminance.r, sky.horizon_luminance.g,
                                   sky.horizon_luminance.b);
          l = horizon + (zenith - horizon) * mu;  // as the baker's gradient
        } else {
          l = glm::dvec3(sky.zenith_luminance.r, sky.zenith_luminance.g, sky.zenith_luminance.b);
        }
        // Parallel light of radiance L over d_omega: irradiance L d_omega on
        // the window, flux L d_omega A.
        const glm::dvec3 f = l * d_omega * window_area;
        flux += f;
        weights.push_back(luminanceOf(f));
        out.push_back(parallelSample(-glm::vec3(towards_sky), window, 0.0f,
                                     roll(seed, 0x736b79ull, out.size(), jitter_roll)));
      }
    }
  }
  double total = 0;
  for (double w : weights) total += w;
  for (size_t i = 0; i < out.size(); ++i)
    out[i].weight = total > 0 ? float(weights[i] / total) : 0.0f;
  flux_out = {float(flux.x), float(flux.y), float(flux.z)};
  return out;
}

std::vector<PointSample> surfaceSamples(const MapTriangles& map, uint32_t triangle_base,
                                        const std::vector<uint32_t>& triangles,
                                        const std::vector<double>& density, int count,
                                        float offset_m, uint64_t seed, uint64_t stream,
                                        bool jitter_roll) {
  // Cumulative area of the triangles, in double for long lists.
  std::vector<double> cumulative;
  double total = 0;
  for (size_t k = 0; k < triangles.size(); ++k) {
    const uint32_t t = triangles[k];
    const glm::vec3 a = toGlm(map.positions[size_t(t) * 3]),
                    b = toGlm(map.positions[size_t(t) * 3 + 1]),
                    c = toGlm(map.positions[size_t(t) * 3 + 2]);
    total += 0.5 * double(glm::length(glm::cross(b - a, c - a))) *
             (density.empty() ? 1.0 : std::max(density[k], 0.0));
    cumulative.push_back(total);
  }
  std::vector<PointSample> out;
  if (!(total > 0) || count <= 0) return out;
  for (int i = 0; i < count; ++i) {
    // Stratified over the area: sample i picks from the i-th 1/count of it.
    const double target =
        total * (double(i) + double(uniform01(seed, stream, uint64_t(i) * 3))) / count;
    const size_t k =
        size_t(std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
    const uint32_t t = triangles[std::min(k, triangles.size() - 1)];
    const glm::vec3 a = toGlm(map.positions[size_t(t) * 3]),
                    b = toGlm(map.positions[size_t(t) * 3 + 1]),
                    c = toGlm(map.positions[size_t(t) * 3 + 2]);
    float u = uniform01(seed, stream, uint64_t(i) * 3 + 1),
          v = uniform01(seed, stream, uint64_t(i) * 3 + 2);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    PointSample s;
    s.position = fromGlm(a + u * (b - a) + v * (c - a) + n * offset_m);
    s.axis = fromGlm(n);
    s.lobe = Lobe::kCosine;
    s.weight = 1.0f / float(count);
    s.roll_rad = roll(seed, stream, uint64_t(i), jitter_roll);
    s.own_triangle = triangle_base + t;
    out.push_back(s);
  }
  return out;
}

}  // namespace svit::gl

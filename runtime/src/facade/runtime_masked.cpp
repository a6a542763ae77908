// The masked lights' direct light at a static surface point, as
// lit_static.frag shades it per pixel (Runtime::irradianceAt adds it):
// the bake's mask x the light's unshadowed irradiance x its dimmer x the
// dynamic objects' shadow, tested here by a ray where the shader reads
// the light's caster depth map (an area light: one ray per point sample,
// weighted as the shader weighs its samples' maps).

#include <algorithm>
#include <cmath>
#include <limits>

#define GLM_ENABLE_EXPERIMENTAL  // glm/gtx: intersectRayTriangle
#include <glm/gtx/intersect.hpp>

#include "runtime_impl.h"
#include "scene/glm_interop.h"

namespace svit {
namespace {

// Slab test of a segment against a box.
bool segmentMeetsBox(const glm::vec3& from, const glm::vec3& direction, float distance_m,
                     const Aabb& box) {
  float t0 = 0, t1 = distance_m;
  const glm::vec3 lo = toGlm(box.min), hi = toGlm(box.max);
  for (int a = 0; a < 3; ++a) {
    if (std::abs(direction[a]) < 1e-12f) {
      if (from[a] < lo[a] || from[a] > hi[a]) return false;
      continue;
    }
    float near_t = (lo[a] - from[a]) / direction[a], far_t = (hi[a] - from[a]) / direction[a];
    if (near_t > far_t) std::swap(near_t, far_t);
    t0 = std::max(t0, near_t);
    t1 = std::min(t1, far_t);
    if (t0 > t1) return false;
  }
  return true;
}

// The centre of the dynamic objects that can cast (the point an area
// light's sample count is chosen for, as the renderer does).
Vec3 castersCentre(const std::vector<rt::DynamicObject>& objects) {
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const rt::DynamicObject& object : objects) {
    if (!object.visible || object.removed || object.bounds.empty()) continue;
    lo = glm::min(lo, toGlm(object.bounds.min));
    hi = glm::max(hi, toGlm(object.bounds.max));
  }
  return fromGlm(lo.x <= hi.x ? 0.5f * (lo + hi) : glm::vec3(0.0f));
}

}  // namespace

double Runtime::Impl::areaVisibility(size_t k, const glm::vec3& from, const glm::vec3& n) const {
  const MaskedLightField& masked = level.masked;
  const std::vector<MaskedAreaSample> samples =
      masked.areaSamples(k, masked.areaSampleCount(k, castersCentre(objects)));
  double seen = 0, total = 0;
  for (const MaskedAreaSample& sample : samples) {
    const glm::vec3 v = toGlm(sample.point) - from;
    const float d2 = glm::dot(v, v);
    if (!(d2 > 0)) continue;
    const float d = std::sqrt(d2);
    const glm::vec3 l = v / d;
    const double w =
        std::max(glm::dot(n, l), 0.0f) * std::max(-glm::dot(toGlm(sample.normal), l), 0.0f) / d2;
    if (!(w > 0)) continue;
    total += w;
    if (!dynamicObjectBlocks(from, l, d)) seen += w;
  }
  return total > 0 ? seen / total : 1.0;
}

bool Runtime::Impl::dynamicObjectBlocks(const glm::vec3& from, const glm::vec3& direction,
                                        float distance_m) const {
  for (const rt::DynamicObject& object : objects) {
    if (!object.visible || object.removed || object.bounds.empty()) continue;
    if (!segmentMeetsBox(from, direction, distance_m, object.bounds)) continue;
    const std::vector<Vec3>& p = object.world_positions;
    for (size_t t = 0; t + 2 < p.size(); t += 3) {
      glm::vec2 barycentric;
      float distance = 0;
      // Both windings: backs cast shadows too (the caster maps cull nothing).
      const bool hit = glm::intersectRayTriangle(from, direction, toGlm(p[t]), toGlm(p[t + 1]),
                                                 toGlm(p[t + 2]), barycentric, distance) ||
                       glm::intersectRayTriangle(from, direction, toGlm(p[t]), toGlm(p[t + 2]),
                                                 toGlm(p[t + 1]), barycentric, distance);
      if (hit && distance > 0 && distance < distance_m) return true;
    }
  }
  return false;
}

glm::dvec3 Runtime::Impl::maskedDirectAt(const SurfaceHit& hit) const {
  const MaskedLightField& masked = level.masked;
  glm::dvec3 sum(0.0);
  const glm::vec3 n = toGlm(level.surfaces.normal(hit.triangle)) * (hit.side == 0 ? 1.0f : -1.0f);
  // Off the surface by a hair of the level's size, as the shader's normal offset.
  const glm::vec3 from = toGlm(hit.point) + n * (level.sample_offset_m * 10.0f);
  for (size_t k = 0; k < masked.lightCount(); ++k) {
    const Rgb e = masked.unshadowed(k, hit.point, fromGlm(n));
    if (e.r <= 0 && e.g <= 0 && e.b <= 0) continue;
    const float v = masked.visibility(k, hit.page, hit.uv);
    if (!(v > 0)) continue;
    const double scale = light_scale.emitterScale(masked.emitter(k));
    if (!(scale > 0)) continue;
    double through = 1;
    if (masked.isArea(k)) {
      through = areaVisibility(k, from, n);
    } else {
      const float distance = std::min(masked.distanceToLight(k, hit.point), 1e30f);
      if (dynamicObjectBlocks(from, toGlm(masked.towardLight(k, hit.point)), distance)) continue;
    }
    sum += glm::dvec3(e.r, e.g, e.b) * double(v) * scale * through;
  }
  return sum;
}

}  // namespace svit

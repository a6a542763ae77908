// The oracle RayCaster: every ray against every triangle with the
// Moeller-Trumbore test (Moeller & Trumbore, "Fast, Minimum Storage
// Ray/Triangle Intersection", JGT 1997) evaluated in double, so its answers
// are as exact as the float32 inputs allow. No acceleration structure, so
// nothing to get wrong: tests compare Embree against it (docs/style.md §8).

#include <algorithm>
#include <cmath>

#include "ray_rules.h"
#include "scene/svit_check.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

struct DVec3 {
  double x, y, z;
};
DVec3 toDouble(const Vec3& v) { return {v.x, v.y, v.z}; }
DVec3 operator-(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DVec3 cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

class BruteForceRayCaster final : public RayCaster {
 public:
  explicit BruteForceRayCaster(const BakeGeometry& geometry) : geometry_(geometry) {}

  void intersect(std::span<const Ray> rays, std::span<RayHit> hits) const override {
    SVIT_CHECK(rays.size() == hits.size(), "BruteForceRayCaster::intersect: %zu rays but %zu hits",
               rays.size(), hits.size());
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = closestHit(rays[i]);
  }

  const char* name() const override { return "brute-force"; }

 private:
  RayHit closestHit(const Ray& ray) const {
    RayHit best;
    float t_near = 0.0f, t_far = 0.0f;
    if (!usableSegment(ray, &t_near, &t_far)) return best;
    const DVec3 origin = toDouble(ray.origin);
    const DVec3 direction = toDouble(ray.direction);
    double best_t = double(t_far);
    // Sizes as flattenStaticGeometry makes them; the minimum keeps a
    // malformed geometry from reading out of bounds.
    const size_t triangles = std::min(
        {geometry_.triangleCount(), geometry_.positions.size() / 3, geometry_.normals.size()});
    for (size_t t = 0; t < triangles; ++t) {
      const DVec3 c0 = toDouble(geometry_.corner(t, 0));
      const DVec3 edge1 = toDouble(geometry_.corner(t, 1)) - c0;
      const DVec3 edge2 = toDouble(geometry_.corner(t, 2)) - c0;
      const DVec3 p = cross(direction, edge2);
      const double det = dot(edge1, p);
      // Exactly parallel (or a degenerate triangle): no single hit point.
      // No epsilon: double keeps tiny determinants of float inputs meaningful.
      if (det == 0.0 || !std::isfinite(det)) continue;
      const double inv_det = 1.0 / det;
      const DVec3 s = origin - c0;
      const double u = dot(s, p) * inv_det;
      // Written as !(inside) so NaN (from NaN corners) counts as outside.
      if (!(u >= 0.0 && u <= 1.0)) continue;
      const DVec3 q = cross(s, edge1);
      const double v = dot(direction, q) * inv_det;
      if (!(v >= 0.0 && u + v <= 1.0)) continue;
      const double hit_t = dot(edge2, q) * inv_det;
      // Strictly closer only, so on an exact tie the lower index (met
      // first) wins: deterministic, unlike a BVH's traversal order.
      if (!(hit_t >= double(t_near) && (hit_t < best_t || (!best.hit() && hit_t <= best_t))))
        continue;
      best_t = hit_t;
      best.triangle = uint32_t(t);
      best.t = float(hit_t);
      best.u = float(u);
      best.v = float(v);
    }
    if (best.hit()) best.front = arrivesOnFront(ray.direction, geometry_.normals[best.triangle]);
    return best;
  }

  const BakeGeometry& geometry_;
};

}  // namespace

std::unique_ptr<RayCaster> makeBruteForceCaster(const BakeGeometry& geometry) {
  return std::make_unique<BruteForceRayCaster>(geometry);
}

}  // namespace svit::baker

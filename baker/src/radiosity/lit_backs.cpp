#include "lit_backs.h"

#include <algorithm>
#include <array>
#include <chrono>

#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

enum class BackState : uint8_t { kUnknown, kLit, kDark };

/// What the lights of the level offer a back: a sky that escaping rays
/// see above the horizon (+y) and, where it has a ground, below it;
/// directions towards directional lights and the sun; lamp positions.
struct LightTargets {
  bool sky_above = false, sky_below = false;
  std::vector<glm::dvec3> towards;  ///< unit, against each directional light's travel
  std::vector<glm::dvec3> lamps;
};

LightTargets lightTargets(const std::vector<LightSource>& lights) {
  LightTargets out;
  for (const LightSource& light : lights) {
    if (!(light.flux_y > 0)) continue;
    switch (light.kind) {
      case LightKind::kSky:
        out.sky_above = out.sky_above || light.upper_share > 0;
        out.sky_below = out.sky_below || light.upper_share < 1;
        break;
      case LightKind::kDirectional: out.towards.push_back(-light.direction); break;
      case LightKind::kPoint:
      case LightKind::kSpot: out.lamps.push_back(light.position); break;
    }
  }
  return out;
}

/// Four points inside triangle t: its centroid and the centroids of the
/// corner thirds, so a back that is lit along one edge only is still seen.
std::array<glm::dvec3, 4> lookoutPoints(const BakeGeometry& geometry, size_t t) {
  const glm::dvec3 a = dvec(geometry.corner(t, 0)), b = dvec(geometry.corner(t, 1)),
                   c = dvec(geometry.corner(t, 2));
  const glm::dvec3 centroid = (a + b + c) / 3.0;
  return {centroid, (4.0 * a + b + c) / 6.0, (a + 4.0 * b + c) / 6.0, (a + b + 4.0 * c) / 6.0};
}

/// One back's look around: lit, or not yet, with the double-sided backs
/// its rays met (lit if one of them turns out lit).
struct Lookout {
  bool lit = false;
  std::vector<uint32_t> backs_seen;
  size_t rays = 0;
};

class BackLookout {
 public:
  BackLookout(const BakeGeometry& geometry, const RayCaster& caster, const LightReach& reach,
              const LightTargets& targets)
      : geometry_(geometry), caster_(caster), reach_(reach), targets_(targets) {}

  Lookout look(size_t t) const {
    Lookout out;
    const glm::dvec3 n = -dvec(geometry_.normals[t]);
    const std::array<glm::dvec3, 4> points = lookoutPoints(geometry_, t);
    const float magnitude = cornerMagnitude(geometry_, t);
    std::array<Vec3, 4> origins;
    for (int k = 0; k < 4; ++k) origins[k] = offsetRayOrigin(vec3(points[k]), vec3(n), magnitude);
    Rng rng(mix64(0x6c69744261636b73ull ^ uint64_t(t)));
    for (int half = 0; half < 2 && !out.lit; ++half) lookAround(origins, n, rng, out);
    if (!out.lit) lookAtLights(origins, n, out);
    std::sort(out.backs_seen.begin(), out.backs_seen.end());
    out.backs_seen.erase(std::unique(out.backs_seen.begin(), out.backs_seen.end()),
                         out.backs_seen.end());
    return out;
  }

 private:
  // Half the hemisphere rays, spread over the four points.
  void lookAround(const std::array<Vec3, 4>& origins, const glm::dvec3& n, Rng& rng,
                  Lookout& out) const {
    constexpr int kRays = kLitBackRays / 2;
    std::array<Ray, kRays> rays;
    std::array<RayHit, kRays> hits;
    for (int i = 0; i < kRays; ++i) {
      rays[i].origin = origins[i % 4];
      const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
      rays[i].direction = vec3(cosineHemisphere(n, u1, u2));
    }
    caster_.intersect(rays, hits);
    out.rays += kRays;
    for (int i = 0; i < kRays && !out.lit; ++i) {
      const RayHit& h = hits[i];
      if (!h.hit()) {
        out.lit = rays[i].direction.y > 0 ? targets_.sky_above : targets_.sky_below;
      } else if (h.front) {
        out.lit = frontReached(rays[i], h);
      } else if (geometry_.double_sided[h.triangle]) {
        out.backs_seen.push_back(h.triangle);
      }
    }
  }

  // A front side lights a back that sees it unless the front itself lies in
  // space the flood never reached (a crate's inside seen from its walls).
  bool frontReached(const Ray& ray, const RayHit& h) const {
    const glm::dvec3 p = dvec(ray.origin) + dvec(ray.direction) * double(h.t);
    return reach_.reaches(p, dvec(geometry_.normals[h.triangle]));
  }

  // Shadow rays towards the sun, directional lights and lamps in front.
  void lookAtLights(const std::array<Vec3, 4>& origins, const glm::dvec3& n, Lookout& out) const {
    std::vector<Ray> rays;
    for (const Vec3& o : origins) {
      for (const glm::dvec3& d : targets_.towards) {
        if (glm::dot(d, n) > 0) rays.push_back({o, vec3(d)});
      }
      for (const glm::dvec3& lamp : targets_.lamps) {
        const glm::dvec3 d = lamp - dvec(o);
        if (glm::dot(d, n) > 0) rays.push_back({o, vec3(d), 0.0f, 0.9999f});
      }
    }
    std::vector<RayHit> hits(rays.size());
    caster_.intersect(rays, hits);
    out.rays += rays.size();
    out.lit = std::any_of(hits.begin(), hits.end(), [](const RayHit& h) { return !h.hit(); });
  }

  const BakeGeometry& geometry_;
  const RayCaster& caster_;
  const LightReach& reach_;
  const LightTargets& targets_;
};

bool sealedBack(const BakeGeometry& geometry, const LightReach& reach, size_t t) {
  const glm::dvec3 n = -dvec(geometry.normals[t]);
  for (const glm::dvec3& p : lookoutPoints(geometry, t)) {
    if (reach.verdict(p, n) != LightReachVerdict::kUnreached) return false;
  }
  return true;
}

// Backs that saw only other backs are lit once one of those is: rounds
// until nothing changes; what is left is dark.
int settleSeenBacks(const std::vector<Lookout>& lookouts, std::vector<BackState>& state) {
  int rounds = 0;
  for (bool changed = true; changed; ++rounds) {
    changed = false;
    for (size_t t = 0; t < state.size(); ++t) {
      if (state[t] != BackState::kUnknown) continue;
      for (uint32_t seen : lookouts[t].backs_seen) {
        if (state[seen] != BackState::kLit) continue;
        state[t] = BackState::kLit;
        changed = true;
        break;
      }
    }
  }
  for (BackState& s : state) {
    if (s == BackState::kUnknown) s = BackState::kDark;
  }
  return rounds;
}

}  // namespace

LitBacks findLitBacks(const BakeGeometry& geometry, const RayCaster& caster,
                      const std::vector<LightSource>& lights, const LightReach& reach,
                      int threads) {
  const auto start = std::chrono::steady_clock::now();
  const size_t count = geometry.triangleCount();
  const LightTargets targets = lightTargets(lights);
  const BackLookout lookout(geometry, caster, reach, targets);
  std::vector<BackState> state(count, BackState::kDark);
  std::vector<Lookout> lookouts(count);
  std::vector<uint8_t> sealed(count, 0);
  parallelFor(count, 256, resolveThreads(threads), [&](size_t begin, size_t end) {
    for (size_t t = begin; t < end; ++t) {
      if (!geometry.double_sided[t]) continue;
      if (sealedBack(geometry, reach, t)) {
        sealed[t] = 1;
        continue;
      }
      lookouts[t] = lookout.look(t);
      state[t] = lookouts[t].lit ? BackState::kLit : BackState::kUnknown;
    }
  });
  LitBacks out;
  out.stats.rounds = settleSeenBacks(lookouts, state);
  out.lit.assign(count, 0);
  for (size_t t = 0; t < count; ++t) {
    if (!geometry.double_sided[t]) continue;
    ++out.stats.double_sided;
    out.stats.sealed += sealed[t];
    out.stats.rays += lookouts[t].rays;
    out.lit[t] = state[t] == BackState::kLit ? 1 : 0;
    out.stats.lit += out.lit[t];
  }
  out.stats.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace svit::baker

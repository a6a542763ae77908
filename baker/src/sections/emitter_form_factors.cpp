// Per-emitter baseline form factors (docs/architecture/runtime-lighting.md
// "Sector-free importance caching", thesis 5.10): which patches each static
// emitter lights and with what share of its flux. Monte Carlo like the
// shooter (thesis 4.2): every ray of an emitter carries the same luminous
// flux, so the share a patch receives is (rays whose first hit lies on it) /
// (rays shot). Lights sample the solver's own emission distributions
// (light_sources.h).

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "radiosity/light_sources.h"
#include "runtime_sections_internal.h"
#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

// Stream tag so these rays never share a stream with the solver's or the
// probes' (random.h keys are tuples of ids).
constexpr uint64_t kFormFactorStream = 0x666f726d66616374ull;  // "formfact"
// Rays cast per parallel work item; fixed, so results do not depend on threads.
constexpr size_t kChunkRays = 2048;
// Rays held in memory per group of emitters (4 bytes each).
constexpr size_t kGroupRays = size_t(1) << 20;

// One emitter to shoot from.
struct Source {
  BakeEmitter::Kind kind = BakeEmitter::Kind::kLight;
  uint32_t index = 0;
  glm::dvec3 flux{0.0};
  LightSource light;               // lights, sun, sky
  std::vector<uint32_t> elements;  // patch: its emitting elements
  std::vector<double> cdf;         // patch: cumulative emitted luminous flux
};

// The baked light sources of `scene`, one call per source so each keeps its
// Scene::lights index (makeLightSources drops dynamic and dark lights).
Expected<std::vector<Source>> lightSources(const Scene& scene, const BakeGeometry& geometry) {
  std::vector<Source> out;
  auto add = [&](const Scene& one, BakeEmitter::Kind kind, uint32_t index) -> Status {
    Expected<std::vector<LightSource>> made = makeLightSources(one, geometry);
    if (!made.ok()) return made.status();
    for (const LightSource& light : *made) {
      Source s;
      s.kind = kind;
      s.index = index;
      s.flux = light.flux_rgb;
      s.light = light;
      out.push_back(std::move(s));
    }
    return Status();
  };
  Scene one;
  one.source_path = scene.source_path;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    if (scene.lights[i].dynamic) continue;
    one.lights = {scene.lights[i]};
    if (Status s = add(one, BakeEmitter::Kind::kLight, uint32_t(i)); !s.ok()) return s;
  }
  one.lights.clear();
  one.sun = scene.sun;
  if (Status s = add(one, BakeEmitter::Kind::kSun, 0); !s.ok()) return s;
  one.sun = Sun();
  one.sky = scene.sky;
  if (Status s = add(one, BakeEmitter::Kind::kSky, 0); !s.ok()) return s;
  return out;
}

// Emitting patches, with a table to pick an element by emitted luminous flux.
std::vector<Source> patchSources(const BakeGeometry& geometry, const PatchSet& patches) {
  std::vector<Source> out;
  for (size_t p = 0; p < patches.patches.size(); ++p) {
    const BakePatch& patch = patches.patches[p];
    if (!(luminance(patch.emission) > 0)) continue;
    Source s;
    s.kind = BakeEmitter::Kind::kPatch;
    s.index = uint32_t(p);
    // The patch's own exitance (the tree's, which follows emissive textures)
    // times its area; elements are picked by their mean luminance.
    s.flux =
        glm::dvec3(patch.emission.r, patch.emission.g, patch.emission.b) * double(patch.area_m2);
    double total = 0;
    for (uint32_t i = 0; i < patch.element_count; ++i) {
      const uint32_t e = patches.patch_elements[patch.first_element + i];
      const Rgb& l = geometry.emission[e / 2];
      const glm::dvec3 flux = glm::dvec3(l.r, l.g, l.b) * (kPi * double(geometry.areas_m2[e / 2]));
      if (!(luminanceOf(flux) > 0)) continue;
      total += luminanceOf(flux);
      s.elements.push_back(e);
      s.cdf.push_back(total);
    }
    if (s.elements.empty()) continue;
    out.push_back(std::move(s));
  }
  return out;
}

// One ray of a patch emitter: an element by emitted flux, a uniform point on
// it, a cosine-distributed direction about the side's normal.
Ray patchRay(const BakeGeometry& geometry, const Source& s, Rng& rng) {
  const double pick = rng.uniformDouble() * s.cdf.back();
  const size_t i = size_t(std::upper_bound(s.cdf.begin(), s.cdf.end(), pick) - s.cdf.begin());
  const uint32_t e = s.elements[std::min(i, s.elements.size() - 1)];
  const uint32_t t = e / 2;
  const glm::dvec3 n = dvec(geometry.normals[t]) * (e % 2 == 0 ? 1.0 : -1.0);
  const glm::dvec2 b = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
  const glm::dvec3 p = (1.0 - b.x - b.y) * dvec(geometry.corner(t, 0)) +
                       b.x * dvec(geometry.corner(t, 1)) + b.y * dvec(geometry.corner(t, 2));
  Ray ray;
  ray.origin = offsetRayOrigin(vec3(p), vec3(n), cornerMagnitude(geometry, t));
  ray.direction = vec3(cosineHemisphere(n, rng.uniformDouble(), rng.uniformDouble()));
  return ray;
}

}  // namespace

Expected<std::vector<BakeEmitter>> buildEmitterFormFactors(const Scene& scene,
                                                           const BakeGeometry& geometry,
                                                           const RayCaster& caster,
                                                           const PatchSet& patches, uint32_t rays,
                                                           uint64_t seed, int threads,
                                                           const std::atomic<bool>* cancel) {
  Expected<std::vector<Source>> sources = lightSources(scene, geometry);
  if (!sources.ok()) return sources.status();
  for (Source& s : patchSources(geometry, patches)) sources->push_back(std::move(s));

  std::vector<BakeEmitter> out;
  out.reserve(sources->size());
  const size_t per_group = std::max<size_t>(1, kGroupRays / std::max<uint32_t>(1, rays));
  std::vector<int32_t> ray_patch;
  std::vector<uint32_t> sorted;
  for (size_t first = 0; first < sources->size(); first += per_group) {
    if (cancel && cancel->load())
      return Status(StatusCode::kCancelled, "runtime sections: form factors cancelled");
    const size_t last = std::min(sources->size(), first + per_group);
    const size_t count = (last - first) * rays;
    ray_patch.assign(count, -1);
    parallelFor(count, kChunkRays, threads, [&](size_t begin, size_t end) {
      if (cancel && cancel->load()) return;
      std::vector<Ray> batch(end - begin);
      std::vector<RayHit> hits(end - begin);
      for (size_t j = begin; j < end; ++j) {
        const size_t emitter = first + j / rays;
        const Source& s = (*sources)[emitter];
        Rng rng(hashIds(seed, kFormFactorStream, emitter, j % rays));
        if (s.kind == BakeEmitter::Kind::kPatch) {
          batch[j - begin] = patchRay(geometry, s, rng);
        } else {
          const LightRay lr = s.light.sample(rng);
          batch[j - begin].origin = vec3(lr.origin);
          batch[j - begin].direction = vec3(lr.direction);
        }
      }
      caster.intersect(batch, hits);
      for (size_t j = begin; j < end; ++j) {
        const RayHit& h = hits[j - begin];
        if (h.hit())
          ray_patch[j] = patches.element_patch[size_t(h.triangle) * 2 + (h.front ? 0 : 1)];
      }
    });
    if (cancel && cancel->load())
      return Status(StatusCode::kCancelled, "runtime sections: form factors cancelled");
    for (size_t emitter = first; emitter < last; ++emitter) {
      const Source& s = (*sources)[emitter];
      BakeEmitter e;
      e.kind = s.kind;
      e.index = s.index;
      e.flux = rgb(s.flux);
      // Run lengths of the sorted hit patches: ascending patches, and
      // integer counts, so no summation order is involved.
      sorted.clear();
      for (size_t j = (emitter - first) * rays; j < (emitter - first + 1) * rays; ++j) {
        if (ray_patch[j] >= 0) sorted.push_back(uint32_t(ray_patch[j]));
      }
      std::sort(sorted.begin(), sorted.end());
      for (size_t j = 0; j < sorted.size();) {
        size_t k = j;
        while (k < sorted.size() && sorted[k] == sorted[j]) ++k;
        e.patches.push_back(sorted[j]);
        e.factors.push_back(float(double(k - j) / double(rays)));
        j = k;
      }
      out.push_back(std::move(e));
    }
  }
  return out;
}

}  // namespace svit::baker

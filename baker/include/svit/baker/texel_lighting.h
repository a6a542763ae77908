#pragma once
// Irradiance per lightmap texel: direct light by shadow rays to light
// samples, and indirect light (and the sky) by a final gather against the
// interpolated radiosity solution, so the lightmap keeps texel detail while
// the solver stays coarse (docs/architecture/baker-lightmaps.md "Lightmaps").

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

/// Baked lights whose direct light shadow masks carry instead of the
/// lightmap (shadow_masks.h): the lighting passes leave them out.
struct MaskedLights {
  std::vector<uint32_t> lights;  ///< Scene::lights indices, static punctual or directional
  bool sun = false;
  /// Scene::instances whose emissive triangles are masked area lights: the
  /// lighting passes leave those triangles' direct light out (their
  /// bounce stays in the solution the gather reads).
  std::vector<uint32_t> emissive_instances;
  /// The masked area lights (after the lights and the sun): per area, its
  /// emitting elements (triangle * 2 + side) and its bake patch. Filled
  /// from the patches once they exist (shadow_masks.h); the passes need
  /// only emissive_instances.
  std::vector<std::vector<uint32_t>> area_elements;
  std::vector<uint32_t> area_patches;
  size_t count() const { return lights.size() + (sun ? 1 : 0) + area_elements.size(); }
  bool masksInstance(uint32_t instance) const;
};

struct TexelLightingSettings {
  uint64_t seed = 1;
  int threads = 0;                   ///< 0 = all cores; results do not depend on it
  uint32_t area_light_samples = 16;  ///< shadow rays per texel to emissive surfaces
  uint32_t sun_samples = 8;          ///< shadow rays per texel across the sun's disk
  /// point/spot lights evaluated per texel; more are sampled by importance
  uint32_t max_point_lights = 16;
  uint32_t gather_rays = 64;  ///< final-gather rays per texel (indirect light and sky)
  /// the solution the gather reads: a bake's passes read the solver's halves
  /// in turn (radiosity.h's SolutionHalf)
  SolutionHalf solution = SolutionHalf::kWhole;
  /// left out of the direct light (their masks hold it)
  MaskedLights masked;
};

/// Direct and indirect irradiance of one texel, lux per channel.
struct TexelIrradiance {
  Rgb direct;
  Rgb indirect;  ///< includes the sky
};

/// Lights every texel of `texels`. `solver` must hold a solution for the same
/// geometry. `progress(done, total)` is called from the calling thread
/// between chunks; returning false (or `cancel`) stops with kCancelled.
Expected<std::vector<TexelIrradiance>> lightTexels(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
    const RadiositySolver& solver, const TexelSet& texels, const TexelLightingSettings& settings,
    const std::atomic<bool>* cancel = nullptr,
    const std::function<bool(size_t, size_t)>& progress = {});

/// The shadow and gather rays each texel of `texels` casts in a pass of
/// `settings` (built, not cast: fast), what a sharded bake balances its
/// shards by. Deterministic.
std::vector<uint32_t> texelRayCounts(const Scene& scene, const BakeGeometry& geometry,
                                     const RayCaster& caster, const RadiositySolver& solver,
                                     const TexelSet& texels, const TexelLightingSettings& settings);

/// Lights the texels whose indices into `texels.samples` `samples` lists, in
/// that order, each exactly as lightTexels lights it (a texel's random
/// stream is its index), so shards of a bake light their texels bit for bit
/// as the whole bake does. kInvalidInput for an index out of range.
Expected<std::vector<TexelIrradiance>> lightTexelList(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
    const RadiositySolver& solver, const TexelSet& texels, const std::vector<uint32_t>& samples,
    const TexelLightingSettings& settings, const std::atomic<bool>* cancel = nullptr,
    const std::function<bool(size_t, size_t)>& progress = {});

/// Per texel, each masked light's visibility from the static level: the
/// unshadowed-irradiance-weighted share of its shadow rays (one to a point
/// or spot light, `settings.sun_samples` over the sun's disk,
/// `settings.area_light_samples` over an area light's elements) that reach
/// it, 0 where the light does not reach the texel at all (behind, outside
/// the cone). Laid out texel-major: [texel * masked.count() + light], the
/// Scene::lights in `masked.lights` order, then the sun, then the areas.
/// Deterministic.
Expected<std::vector<float>> maskVisibility(const Scene& scene, const BakeGeometry& geometry,
                                            const RayCaster& caster, const TexelSet& texels,
                                            const TexelLightingSettings& settings,
                                            const std::atomic<bool>* cancel = nullptr);

}  // namespace svit::baker

#pragma once
// The stages of the runtime sections (runtime_sections.h), one file each:
// patches and their cluster trees (patch_builder.cpp), per-emitter baseline
// form factors (emitter_form_factors.cpp), LOD proxies (proxy_builder.cpp)
// and the SH probe grid (probe_grid.cpp). Internal: runtime_sections.cpp
// validates the settings and calls them in order; tests and benchmarks may
// call them one by one.

#include <atomic>
#include <cstdint>
#include <vector>

#include "svit/bake_file.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

/// Patches of the static geometry and the cluster trees above them.
struct PatchSet {
  std::vector<BakePatch> patches;
  std::vector<uint32_t> patch_elements;  ///< triangle * 2 + side, ascending within a patch
  std::vector<BakeClusterNode> clusters;
  /// Per element (triangle * 2 + side): its patch, or -1 where the side does
  /// not exist (the back of a single-sided triangle).
  std::vector<int32_t> element_patch;
};

/// Walks each object's cluster tree (solver.tree()) top-down and makes a
/// node a patch when its area is at most `max_area_m2` and every element
/// (triangle side) below it has its normal within `max_normal_rad` of the
/// node's area-weighted mean normal; a lone element is always a patch.
/// Patches are numbered in depth-first order (child 0 first), clusters in
/// pre-order. Radiosity is the solver's per-side mean, area-weighted.
/// `solver` must have been built over `geometry`. Serial; deterministic.
PatchSet buildPatches(const BakeGeometry& geometry, const RadiositySolver& solver,
                      double max_area_m2, double max_normal_rad);

/// Baseline form factors of every static emitter: static lights in scene
/// order (kLight, index = Scene::lights index), the sun, the sky, then every
/// patch with emission (kPatch, ascending). Each shoots `rays` rays from its
/// own emission distribution (LightSource::sample for lights; uniform points
/// weighted by emitted flux and cosine directions for patches); a factor is
/// the share of the rays (equal luminous flux each) whose first hit lies on
/// a patch. Rays lost to the void or to the black back of single-sided
/// surfaces count for no patch, so factors sum to <= 1. Bit-identical for
/// any `threads`. Errors: a light's flux is not finite; kCancelled.
Expected<std::vector<BakeEmitter>> buildEmitterFormFactors(const Scene& scene,
                                                           const BakeGeometry& geometry,
                                                           const RayCaster& caster,
                                                           const PatchSet& patches, uint32_t rays,
                                                           uint64_t seed, int threads,
                                                           const std::atomic<bool>* cancel);

/// Simplifies every static object (instance) on its own to about `ratio`
/// of its faces (objects of <= 4 faces stay as they are) and maps each proxy
/// face to the patch of the nearest original triangle side facing within 90
/// degrees of it (any side when none does; ties to the first side in
/// triangle order), by Embree closest-point queries over a BVH of each
/// object's sides: O(proxy faces x log object faces). Simplification is
/// serial; the mapping runs on `threads` workers, bit-identical for any count.
/// Errors: kCancelled, kInternal (Embree).
Expected<BakeProxyMesh> buildProxy(const BakeGeometry& geometry, const PatchSet& patches,
                                   double ratio, int threads, const std::atomic<bool>* cancel);

/// Probes per grid axis at most.
inline constexpr uint32_t kMaxProbesPerAxis = 64;
/// Rays gathered per probe over the sphere (16 x 16 jittered strata).
inline constexpr uint32_t kProbeRays = 256;
/// Points sampled per probe on the emissive surfaces (levels that have any).
inline constexpr uint32_t kProbeEmitterSamples = 64;

/// Cell-centred probe grid over the static bounds, `spacing_m` apart (per
/// axis widened so no axis has more than kMaxProbesPerAxis probes). Each
/// probe projects the radiance it sees (hit: the solver's interpolated
/// radiosity / pi of the side hit; miss: the sky) onto L1 SH, from
/// kProbeRays sphere directions and, for emission, also kProbeEmitterSamples
/// points on emissive triangles (chosen by luminance x area), the two
/// combined by multiple importance sampling (balance heuristic), so a small
/// bright lamp is not left to the few sphere rays that happen to hit it. Storage per
/// probe: coefficients Y00, Y1-1, Y10, Y11 (basis 0.282095 and 0.488603 *
/// (y, z, x)), each as r, g, b: radiance SH, so irradiance about unit normal
/// n is E(n) = pi * c0 * Y00 + 2pi/3 * sum_m c1m * Y1m(n). A probe whose
/// rays mostly hit the black back of single-sided surfaces (inside
/// geometry) gets the mean of its valid neighbours (3x3x3 block), or zero.
/// Calls solver.prepareQueries(). Bit-identical for any `threads`.
/// Errors: kCancelled.
Expected<BakeProbeGrid> buildProbeGrid(const Scene& scene, const BakeGeometry& geometry,
                                       const RayCaster& caster, const RadiositySolver& solver,
                                       double spacing_m, uint64_t seed, int threads,
                                       const std::atomic<bool>* cancel);

}  // namespace svit::baker

#pragma once
// The bake's runtime sections: patches (cluster-tree nodes of bounded area
// and similar normal) with their static radiosity, cluster trees over them,
// per-emitter baseline form factors, LOD proxies of the static geometry
// (fast-simplification) mapped back to patches, and an L1 SH probe grid for
// dynamic objects. Built only for levels with dynamic objects or runtime
// lights (docs/architecture/runtime-facade.md "Pay for what is used").

#include <atomic>
#include <cstdint>

#include "svit/bake_file.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

struct RuntimeSectionSettings {
  double patch_max_area_m2 = 0;                      ///< 0: 1/256 of the static surface area
  double patch_max_normal_rad = 0.5235987755982988;  ///< 30 degrees
  double proxy_ratio = 0.25;         ///< proxy faces / static faces (fast-simplification target)
  double probe_spacing_m = 0;        ///< 0: bounds diagonal / 32
  uint32_t form_factor_rays = 4096;  ///< per emitter, for its baseline form factors
  uint64_t seed = 1;
  int threads = 0;
};

/// True when the level needs runtime sections: a dynamic instance or a
/// dynamic (runtime) light.
bool levelNeedsRuntimeSections(const Scene& scene);

/// Fills data.patches, patch_elements, clusters, emitters, proxy and probes
/// from the solved radiosity (`solver` over `geometry`, `caster` tracing
/// `geometry`), and sets data.has_runtime_sections. Other fields of `data`
/// are left alone.
/// - Patches: numbered depth-first over the objects' cluster trees; every
///   element (triangle side) lies in exactly one; clusters in pre-order, one
///   tree per static object, leaves naming patches.
/// - Emitters: static lights in scene order (kLight, index = Scene::lights
///   index), then the sun (kSun), the sky (kSky), then every emitting patch
///   (kPatch, ascending); `flux` is what the solver shoots (sun and sky:
///   the flux through the disk enclosing the scene, light_sources.h);
///   `factors` are luminous shares of it from `form_factor_rays` rays (rays
///   lost to the void or to black backs count for none: they sum to <= 1).
/// - Proxy: each static object simplified to ~proxy_ratio of its faces,
///   each face mapped to the patch of the nearest original side facing it.
/// - Probes: cell-centred grid over the static bounds (at most 64 per axis).
///   `sh` holds radiance SH, per probe Y00, Y1-1, Y10, Y11 (basis 0.282095,
///   0.488603 * (y, z, x)), each r, g, b: the integral of radiance x Y over
///   the sphere (cd/m2 x sr). The runtime convolves with the
///   clamped cosine: E(n) = pi * c0 * Y00 + 2pi/3 * sum_m c1m * Y1m(n) (lux).
///   Gathered from surfaces and sky only (no direct light of punctual
///   lights or the sun). Probes inside geometry take their neighbours' mean.
/// Deterministic for a seed: bit-identical for any `settings.threads`.
/// Errors (data unchanged): a setting out of range (message names it and
/// its value), a solver over other geometry, a light's flux not finite;
/// kCancelled when `cancel` is set. Thread-safe: no; uses
/// `settings.threads` workers (0 = all cores) inside.
Status buildRuntimeSections(const Scene& scene, const BakeGeometry& geometry,
                            const RayCaster& caster, const RadiositySolver& solver,
                            const RuntimeSectionSettings& settings, BakeData& data,
                            const std::atomic<bool>* cancel = nullptr);

}  // namespace svit::baker

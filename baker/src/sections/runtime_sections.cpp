// The bake's runtime sections (runtime_sections.h): validates the settings,
// derives the defaults from the level, and runs the stages of
// runtime_sections_internal.h in order. Outputs are written only once every
// stage has succeeded, so an error or a cancel leaves `data` as it was.

#include "svit/baker/runtime_sections.h"

#include <cmath>
#include <string>

#include <glm/glm.hpp>

#include "radiosity/element_tree.h"
#include "runtime_sections_internal.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

Status badSetting(const std::string& name, double value, const char* expected) {
  return Status(StatusCode::kInvalidInput, "runtime sections: " + name + " = " +
                                               std::to_string(value) + ": expected " + expected);
}

Status cancelled() { return Status(StatusCode::kCancelled, "runtime sections: cancelled"); }

}  // namespace

bool levelNeedsRuntimeSections(const Scene& scene) {
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic) return true;
  }
  for (const Light& light : scene.lights) {
    if (light.dynamic) return true;
  }
  return false;
}

Status buildRuntimeSections(const Scene& scene, const BakeGeometry& geometry,
                            const RayCaster& caster, const RadiositySolver& solver,
                            const RuntimeSectionSettings& settings, BakeData& data,
                            const std::atomic<bool>* cancel) {
  const RuntimeSectionSettings& s = settings;
  if (!std::isfinite(s.patch_max_area_m2) || s.patch_max_area_m2 < 0) {
    return badSetting("patch_max_area_m2", s.patch_max_area_m2, "finite and >= 0 (0: default)");
  }
  if (!(s.patch_max_normal_rad > 0 && s.patch_max_normal_rad <= kPi)) {
    return badSetting("patch_max_normal_rad", s.patch_max_normal_rad, "in (0, pi]");
  }
  if (!(s.proxy_ratio > 0 && s.proxy_ratio <= 1))
    return badSetting("proxy_ratio", s.proxy_ratio, "in (0, 1]");
  if (!std::isfinite(s.probe_spacing_m) || s.probe_spacing_m < 0) {
    return badSetting("probe_spacing_m", s.probe_spacing_m, "finite and >= 0 (0: default)");
  }
  if (s.form_factor_rays == 0) return badSetting("form_factor_rays", 0, ">= 1");
  if (&solver.tree().geometry() != &geometry) {
    return Status(StatusCode::kInvalidInput,
                  "runtime sections: the solver was built over other geometry");
  }
  const int threads = s.threads;
  if (cancel && cancel->load()) return cancelled();

  // Defaults from the level: 1/256 of the static area (every element side)
  // per patch, 32 probes along the bounds' diagonal.
  double static_area_m2 = 0;
  for (int root : solver.tree().objectRoots()) static_area_m2 += solver.tree().node(root).area_m2;
  const double max_area_m2 = s.patch_max_area_m2 > 0 ? s.patch_max_area_m2 : static_area_m2 / 256.0;
  const Vec3& lo = geometry.bounds.min;
  const Vec3& hi = geometry.bounds.max;
  const double diagonal_m = glm::length(glm::dvec3(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z));
  double spacing_m = s.probe_spacing_m > 0 ? s.probe_spacing_m : diagonal_m / 32.0;
  if (!(spacing_m > 0)) spacing_m = 1.0;  // a single point of geometry: one probe, any spacing

  PatchSet patches = buildPatches(geometry, solver, max_area_m2, s.patch_max_normal_rad);
  if (cancel && cancel->load()) return cancelled();
  Expected<std::vector<BakeEmitter>> emitters = buildEmitterFormFactors(
      scene, geometry, caster, patches, s.form_factor_rays, s.seed, threads, cancel);
  if (!emitters.ok()) return emitters.status();
  Expected<BakeProxyMesh> proxy = buildProxy(geometry, patches, s.proxy_ratio, threads, cancel);
  if (!proxy.ok()) return proxy.status();
  Expected<BakeProbeGrid> probes =
      buildProbeGrid(scene, geometry, caster, solver, spacing_m, s.seed, threads, cancel);
  if (!probes.ok()) return probes.status();

  data.has_runtime_sections = true;
  data.patches = std::move(patches.patches);
  data.patch_elements = std::move(patches.patch_elements);
  data.clusters = std::move(patches.clusters);
  data.emitters = std::move(emitters).value();
  data.proxy = std::move(proxy).value();
  data.probes = std::move(probes).value();
  return Status();
}

}  // namespace svit::baker

// Progressive Monte Carlo shooting (thesis 4.2-4.3): every batch shoots the
// unshot flux of lights, emitters and receiving nodes with rays of equal
// luminous flux, allocated by importance (stratified over the shooters'
// cumulative flux). After a batch, dense uneven hits subdivide their
// receivers, sparse hits propagate up to clusters, and the rest is deposited
// where it rests. A pass ends when little flux is left; the remainder is
// compensated as ambient light (thesis 5.5). Passes repeat with more rays
// and are averaged; their spread is the error estimate. One batch's stages
// are in radiosity_batch.cpp.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "radiosity_state.h"
#include "scene/glm_interop.h"
#include "scene/texture_sampling.h"
#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

using Clock = std::chrono::steady_clock;

// Emission of original triangle `t` over a sub-triangle, from the material's
// emissive texture (for splitting textured emitters).
EmissionOver makeEmissionOver(const Scene& scene, const BakeGeometry& geometry) {
  return [&scene, &geometry](uint32_t t, const float(&bary)[3][2]) -> glm::dvec3 {
    const Instance& instance = scene.instances[geometry.instance[t]];
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const uint32_t mt = geometry.mesh_triangle[t];
    const Material& material = scene.materials[mesh.triangle_material[mt]];
    const Rgb& factor = material.emissive_luminance;
    const TextureRef& ref = material.emissive_texture;
    const std::vector<Vec2>& uvs = ref.texcoord == 1 ? mesh.uv1 : mesh.uv0;
    if (ref.texture < 0 || uvs.empty()) return {factor.r, factor.g, factor.b};
    Vec2 corner_uv[3];
    for (int k = 0; k < 3; ++k) {
      // Sub-triangle corner in the original triangle's UVs.
      const Vec2 a = uvs[mesh.indices[mt * 3]], b = uvs[mesh.indices[mt * 3 + 1]],
                 c = uvs[mesh.indices[mt * 3 + 2]];
      const float u = bary[k][0], v = bary[k][1];
      corner_uv[k] = transformUv(
          ref, {a.x + u * (b.x - a.x) + v * (c.x - a.x), a.y + u * (b.y - a.y) + v * (c.y - a.y)});
    }
    const Rgb mean = meanOverTriangle(scene.textures[size_t(ref.texture)], corner_uv[0],
                                      corner_uv[1], corner_uv[2], true);
    return {factor.r * mean.r, factor.g * mean.g, factor.b * mean.b};
  };
}

// Triangle t named as the file does: mesh, primitive, triangle, material.
std::string triangleLabel(const Scene& scene, const BakeGeometry& geometry, size_t t) {
  std::string where = scene.source_path + ": triangle " + std::to_string(t);
  if (geometry.instance[t] < scene.instances.size()) {
    const Mesh& mesh = scene.meshes[size_t(scene.instances[geometry.instance[t]].mesh)];
    const uint32_t mt = geometry.mesh_triangle[t];
    where = scene.source_path + ": mesh '" + mesh.name + "'";
    if (mt < mesh.triangle_source.size()) {
      where += " primitive " + std::to_string(mesh.triangle_source[mt].primitive) + " triangle " +
               std::to_string(mesh.triangle_source[mt].triangle);
    }
    if (mt < mesh.triangle_material.size() && mesh.triangle_material[mt] < scene.materials.size()) {
      where += " (material '" + scene.materials[mesh.triangle_material[mt]].name + "')";
    }
  }
  return where;
}

// Settings in range, and every triangle's albedo in [0, 1] and emission
// finite and >= 0; errors name the element as the file does.
Status checkSolverInputs(const Scene& scene, const BakeGeometry& geometry,
                         const RadiositySettings& settings) {
  if (!(settings.subdiv > 0) || !(settings.min_perimeter_m >= 0) || settings.first_pass_rays == 0 ||
      !(settings.pass_growth >= 1.0) || settings.max_batch_rays == 0 ||
      !(settings.pass_end_rays >= 1.0) || !(settings.emitter_split_ratio > 1.0) ||
      settings.min_hits_per_element == 0 || settings.threads < 0 ||
      !(settings.leak_guard_max_voxel_m >= 0)) {
    return Status(StatusCode::kInvalidInput,
                  "radiosity settings: out of range (subdiv > 0, min_perimeter_m >= 0, "
                  "first_pass_rays > 0, pass_growth >= 1, max_batch_rays > 0, "
                  "pass_end_rays >= 1, emitter_split_ratio > 1, "
                  "min_hits_per_element > 0, threads >= 0, leak_guard_max_voxel_m >= 0)");
  }
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const Rgb& a = geometry.albedo[t];
    const Rgb& e = geometry.emission[t];
    const bool albedo_ok = a.r >= 0 && a.r <= 1 && a.g >= 0 && a.g <= 1 && a.b >= 0 && a.b <= 1;
    const bool emission_ok = std::isfinite(e.r) && std::isfinite(e.g) && std::isfinite(e.b) &&
                             e.r >= 0 && e.g >= 0 && e.b >= 0;
    if (albedo_ok && emission_ok) continue;
    char values[160];
    if (!emission_ok) {
      std::snprintf(values, sizeof values,
                    "emitted luminance (%g, %g, %g) cd/m2 must be finite and >= 0", double(e.r),
                    double(e.g), double(e.b));
    } else {
      std::snprintf(values, sizeof values, "albedo (%g, %g, %g) must be in [0, 1]", double(a.r),
                    double(a.g), double(a.b));
    }
    return Status(StatusCode::kInvalidInput, triangleLabel(scene, geometry, t) + ": " + values);
  }
  return Status();
}

}  // namespace

RadiositySolver::RadiositySolver() : state_(std::make_unique<State>()) {}
RadiositySolver::~RadiositySolver() = default;

Expected<std::unique_ptr<RadiositySolver>> RadiositySolver::create(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
    const RadiositySettings& settings) {
  if (Status s = checkSolverInputs(scene, geometry, settings); !s.ok()) return s;
  std::unique_ptr<RadiositySolver> solver(new RadiositySolver());
  State& s = *solver->state_;
  s.scene = &scene;
  s.geometry = &geometry;
  s.caster = &caster;
  s.settings = settings;
  s.threads = resolveThreads(settings.threads);
  TreeSettings tree_settings;
  const double diagonal = glm::length(dvec(geometry.bounds.max) - dvec(geometry.bounds.min));
  tree_settings.min_perimeter_m =
      settings.min_perimeter_m > 0 ? settings.min_perimeter_m : 0.02 * diagonal;
  s.settings.min_perimeter_m = tree_settings.min_perimeter_m;
  tree_settings.emitter_split_ratio = settings.emitter_split_ratio;
  s.tree =
      std::make_unique<ElementTree>(geometry, tree_settings, makeEmissionOver(scene, geometry));
  Expected<std::vector<LightSource>> lights = makeLightSources(scene, geometry);
  if (!lights.ok()) return lights.status();
  s.lights = std::move(lights).value();
  s.reach = LightReach::build(geometry, s.lights, settings.leak_guard_max_voxel_m);

  for (const LightSource& light : s.lights) s.emitted_y += light.flux_y;
  glm::dvec3 reflectance(0.0);
  for (int root : s.tree->objectRoots()) {
    const TreeNode& n = s.tree->node(root);
    if (luminanceOf(n.emitted_flux) > 0) {
      s.emitting_roots.push_back(root);
      s.emitted_y += luminanceOf(n.emitted_flux);
    }
    reflectance += n.reflectance_area;
    s.total_area_m2 += n.area_m2;
  }
  s.mean_albedo = s.total_area_m2 > 0 ? reflectance / s.total_area_m2 : glm::dvec3(0.0);
  s.element_s1.assign(geometry.triangleCount() * 2, 0.0);
  s.element_s2.assign(geometry.triangleCount() * 2, 0.0);
  s.stats.elements = 0;
  for (size_t t = 0; t < geometry.triangleCount(); ++t)
    s.stats.elements += geometry.double_sided[t] ? 2 : 1;
  s.growNodeArrays();
  return solver;
}

void RadiositySolver::State::growNodeArrays() {
  const size_t n = tree->nodes().size();
  e_pass.resize(n, glm::dvec3(0.0));
  e_unshot.resize(n, glm::dvec3(0.0));
  e_sum.resize(n, glm::dvec3(0.0));
  e_sum_odd.resize(n, glm::dvec3(0.0));
}

void RadiositySolver::State::startPass() {
  std::fill(e_pass.begin(), e_pass.end(), glm::dvec3(0.0));
  std::fill(e_unshot.begin(), e_unshot.end(), glm::dvec3(0.0));
  pending.clear();
  light_unshot.assign(lights.size(), 1.0);
  emission_unshot.assign(emitting_roots.size(), 1.0);
  pass_rays = double(settings.first_pass_rays) * std::pow(settings.pass_growth, double(pass));
  ray_flux_y = emitted_y / pass_rays;
  shot_pass_y = 0;
  batch = 0;
  started = true;
  ++version;
}

double RadiositySolver::State::unshotY() const {
  double u = 0;
  for (size_t i = 0; i < lights.size(); ++i) u += lights[i].flux_y * light_unshot[i];
  for (size_t i = 0; i < emitting_roots.size(); ++i) {
    u += luminanceOf(tree->node(emitting_roots[i]).emitted_flux) * emission_unshot[i];
  }
  for (int n : pending) u += luminanceOf(tree->node(n).reflectance_area * e_unshot[size_t(n)]);
  return u;
}

glm::dvec3 RadiositySolver::State::currentAmbient() const {
  // Unshot flux U would reach surfaces as U*c, reflect rho*c of it and so
  // on: U*c / (1 - rho*c) in all, spread over every surface (thesis 5.5).
  // c, the share of surface rays that hit the scene, keeps open scenes
  // (sun and sky leaving through windows) from being over-compensated.
  glm::dvec3 unshot(0.0);
  for (size_t i = 0; i < lights.size(); ++i) unshot += lights[i].flux_rgb * light_unshot[i];
  for (size_t i = 0; i < emitting_roots.size(); ++i)
    unshot += tree->node(emitting_roots[i]).emitted_flux * emission_unshot[i];
  for (int n : pending) unshot += tree->node(n).reflectance_area * e_unshot[size_t(n)];
  const double captured = surface_rays > 0 ? double(surface_hits) / double(surface_rays) : 1.0;
  glm::dvec3 ambient(0.0);
  for (int c = 0; c < 3; ++c) {
    // Albedo 1 in a closed scene has no finite answer; 1e-3 caps the
    // amplification at 1000 rather than dividing by zero.
    const double denominator = std::max(1e-3, 1.0 - mean_albedo[c] * captured);
    ambient[c] = total_area_m2 > 0 ? unshot[c] * captured / (total_area_m2 * denominator) : 0.0;
  }
  return ambient;
}

void RadiositySolver::State::endPass() {
  const glm::dvec3 ambient = currentAmbient();
  const double weight = pass_rays;
  for (size_t n = 0; n < e_sum.size(); ++n) e_sum[n] += weight * e_pass[n];
  ambient_sum += weight * ambient;
  weight_sum += weight;
  if (pass % 2 == 1) {
    for (size_t n = 0; n < e_sum_odd.size(); ++n) e_sum_odd[n] += weight * e_pass[n];
    ambient_sum_odd += weight * ambient;
    weight_sum_odd += weight;
  }
  const std::vector<glm::dvec3> means = elementMeans(e_pass, ambient);
  for (size_t e = 0; e < means.size(); ++e) {
    const double x = luminanceOf(means[e]);
    element_s1[e] += weight * x;
    element_s2[e] += weight * x * x;
  }
  ++stats.passes_completed;
  ++pass;
  startPass();
}

Status RadiositySolver::improve(const StopRule& stop) {
  State& s = *state_;
  const auto call_start = Clock::now();
  const double elapsed_before = s.stats.seconds;
  if (!s.started) {
    s.startPass();
    s.recordPoint(0.0);
  }
  // Where the last estimate was taken at a pass end (or nothing has been shot
  // yet): the only points targets_at_pass_ends looks at.
  bool pass_just_ended = s.stats.rays == 0;
  while (true) {
    const double call_s = std::chrono::duration<double>(Clock::now() - call_start).count();
    s.stats.seconds = elapsed_before + call_s;
    const double unshot = s.unshotY();
    SolverProgress progress{
        s.stats.seconds, s.stats.passes_completed, s.stats.rays, s.last_estimate,
        s.shot_pass_y + unshot > 0 ? s.shot_pass_y / (s.shot_pass_y + unshot) : 1.0};
    // Points between pass ends at most every 0.25 s, and rarer when each
    // costs more (O(nodes): about 20x its own cost apart).
    if (s.stats.seconds - s.last_point_s >= std::max(0.25, 20.0 * s.last_point_cost_s))
      s.recordPoint(s.stats.seconds);
    if (stop.cancel && stop.cancel->load())
      return Status(StatusCode::kCancelled, "radiosity: cancelled");
    if (stop.progress && !stop.progress(progress))
      return Status(StatusCode::kCancelled, "radiosity: cancelled");
    if (s.emitted_y <= 0) break;  // nothing emits: the answer is black, exactly
    if (call_s >= stop.max_seconds || s.stats.passes_completed >= stop.max_passes ||
        s.stats.rays >= stop.max_rays)
      break;
    if (!stop.targets_at_pass_ends || pass_just_ended) {
      if (s.stats.passes_completed >= 2 && s.last_estimate <= stop.target_est_rel_error) break;
      if (progress.shot_fraction >= stop.target_shot_fraction) break;
    }
    const uint32_t passes = s.stats.passes_completed;
    s.runBatch();
    pass_just_ended = s.stats.passes_completed != passes;
    if (pass_just_ended)
      s.recordPoint(elapsed_before +
                    std::chrono::duration<double>(Clock::now() - call_start).count());
  }
  s.stats.seconds =
      elapsed_before + std::chrono::duration<double>(Clock::now() - call_start).count();
  s.recordPoint(s.stats.seconds);
  return Status();
}

}  // namespace svit::baker

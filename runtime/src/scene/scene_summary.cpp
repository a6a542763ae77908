#include "svit/scene_summary.h"

#include <cmath>
#include <cstdio>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "glm_interop.h"
#include "numeric.h"

namespace svit {

SceneSummary summarize(const Scene& scene) {
  SceneSummary summary;
  summary.meshes = scene.meshes.size();
  summary.materials = scene.materials.size();
  summary.textures = scene.textures.size();
  summary.instances = scene.instances.size();
  double flux_rgb[3] = {0, 0, 0};
  for (const Instance& instance : scene.instances) {
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const glm::mat4 world = toGlm(instance.world_from_object);
    const size_t triangles = mesh.triangleCount();
    (instance.dynamic ? summary.dynamic_triangles : summary.static_triangles) += triangles;
    if (instance.dynamic) ++summary.dynamic_instances;
    for (size_t t = 0; t < triangles; ++t) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 w =
            transformPoint(world, toGlm(mesh.positions[mesh.indices[t * 3 + size_t(k)]]));
        p[k] = glm::dvec3(w);
        summary.bounds.min = {std::min(summary.bounds.min.x, w.x),
                              std::min(summary.bounds.min.y, w.y),
                              std::min(summary.bounds.min.z, w.z)};
        summary.bounds.max = {std::max(summary.bounds.max.x, w.x),
                              std::max(summary.bounds.max.y, w.y),
                              std::max(summary.bounds.max.z, w.z)};
      }
      const Rgb& e = mesh.triangle_emission[t];
      if (e.r > 0 || e.g > 0 || e.b > 0) {
        ++summary.emissive_triangles;
        const double area = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        // Lambertian emitter: exitance pi*L per emitting side.
        const double sides = scene.materials[mesh.triangle_material[t]].double_sided ? 2.0 : 1.0;
        const double k = kPi * area * sides;
        flux_rgb[0] += k * e.r;
        flux_rgb[1] += k * e.g;
        flux_rgb[2] += k * e.b;
        summary.emitted_flux_lm += k * double(luminance(e));
      }
    }
  }
  summary.emitted_flux_rgb = {float(flux_rgb[0]), float(flux_rgb[1]), float(flux_rgb[2])};
  for (const Light& light : scene.lights) {
    switch (light.type) {
      case LightType::kPoint: ++summary.point_lights; break;
      case LightType::kSpot: ++summary.spot_lights; break;
      case LightType::kDirectional: ++summary.directional_lights; break;
    }
    if (light.dynamic) ++summary.dynamic_lights;
  }
  summary.has_sun = scene.sun.enabled;
  summary.has_sky = scene.sky.model != SkyModel::kNone;
  summary.animations = scene.animations.size();
  for (const Animation& a : scene.animations) summary.animation_tracks += a.tracks.size();
  summary.object_paths = scene.object_paths.size();
  summary.camera_paths = scene.camera_paths.size();
  for (const SceneCamera& camera : scene.cameras) summary.cameras.push_back(camera.name);
  summary.warnings = scene.warnings;
  return summary;
}

namespace {

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

}  // namespace

std::string summaryToText(const std::string& level_path, const SceneSummary& s) {
  std::string out = "level       " + level_path + "\n";
  out += "triangles   " + std::to_string(s.static_triangles + s.dynamic_triangles) + " (" +
         std::to_string(s.static_triangles) + " static, " + std::to_string(s.dynamic_triangles) +
         " dynamic)\n";
  out += "instances   " + std::to_string(s.instances) + " (" + std::to_string(s.dynamic_instances) +
         " dynamic) of " + std::to_string(s.meshes) + " meshes\n";
  out += "materials   " + std::to_string(s.materials) + ", " + std::to_string(s.textures) +
         " textures decoded\n";
  out += "emitters    " + std::to_string(s.emissive_triangles) + " emissive triangles, " +
         format("%.6g lm (RGB %.6g, ", s.emitted_flux_lm, s.emitted_flux_rgb.r) +
         format("%.6g, %.6g)\n", s.emitted_flux_rgb.g, s.emitted_flux_rgb.b);
  out += "lights      " + std::to_string(s.point_lights) + " point, " +
         std::to_string(s.spot_lights) + " spot, " + std::to_string(s.directional_lights) +
         " directional (" + std::to_string(s.dynamic_lights) + " dynamic); sun " +
         (s.has_sun ? "yes" : "no") + ", sky " + (s.has_sky ? "yes" : "no") + "\n";
  out += "animation   " + std::to_string(s.animations) + " animations, " +
         std::to_string(s.animation_tracks) + " tracks; " + std::to_string(s.object_paths) +
         " object paths, " + std::to_string(s.camera_paths) + " camera paths\n";
  out += "cameras     " + std::to_string(s.cameras.size());
  for (size_t i = 0; i < s.cameras.size(); ++i) out += (i ? ", '" : ": '") + s.cameras[i] + "'";
  out += "\n";
  if (s.bounds.empty()) {
    out += "bounds      empty\n";
  } else {
    out += "bounds      " +
           format("min (%.4g, %.4g, %.4g)", s.bounds.min.x, s.bounds.min.y, s.bounds.min.z) +
           format(" max (%.4g, %.4g, %.4g) m\n", s.bounds.max.x, s.bounds.max.y, s.bounds.max.z);
  }
  out += "warnings    " + std::to_string(s.warnings.size()) + "\n";
  for (const std::string& w : s.warnings) out += "  " + w + "\n";
  return out;
}

std::string summaryToJson(const std::string& level_path, const SceneSummary& s) {
  nlohmann::ordered_json j;
  j["level"] = level_path;
  j["triangles"] = {{"static", s.static_triangles}, {"dynamic", s.dynamic_triangles}};
  j["instances"] = {{"total", s.instances}, {"dynamic", s.dynamic_instances}};
  j["meshes"] = s.meshes;
  j["materials"] = s.materials;
  j["textures"] = s.textures;
  j["emitters"] = {
      {"emissive_triangles", s.emissive_triangles},
      {"flux_lm", s.emitted_flux_lm},
      {"flux_rgb", {s.emitted_flux_rgb.r, s.emitted_flux_rgb.g, s.emitted_flux_rgb.b}}};
  j["lights"] = {
      {"point", s.point_lights},     {"spot", s.spot_lights}, {"directional", s.directional_lights},
      {"dynamic", s.dynamic_lights}, {"sun", s.has_sun},      {"sky", s.has_sky}};
  j["animations"] = {{"animations", s.animations},
                     {"tracks", s.animation_tracks},
                     {"object_paths", s.object_paths},
                     {"camera_paths", s.camera_paths}};
  j["cameras"] = s.cameras;
  if (s.bounds.empty()) {
    j["bounds_m"] = nullptr;
  } else {
    j["bounds_m"] = {{"min", {s.bounds.min.x, s.bounds.min.y, s.bounds.min.z}},
                     {"max", {s.bounds.max.x, s.bounds.max.y, s.bounds.max.z}}};
  }
  j["warnings"] = s.warnings;
  // Names, paths and warnings come from files and need not be UTF-8 (a
  // Linux path, a percent-decoded URI): write U+FFFD for bad bytes rather
  // than throw out of a noexcept-by-contract API (found by fuzz_gltf).
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace svit

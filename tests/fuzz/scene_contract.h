#pragma once
// The promises a successful load makes (svit/scene.h, svit/level.h), checked
// element by element: the oracle of the import fuzz targets
// (fuzz_level_import.cpp) and of tests/runtime/scene/fuzz_regressions_test.cpp, so
// the fuzzers find wrong results, not only crashes. Header-only.

#include <cmath>
#include <cstdio>
#include <string>

#include "svit/scene.h"

namespace svit::fuzz {

inline bool finite(const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool finiteNonNegative(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 &&
         c.b >= 0;
}
// Emission and light colour may be +Inf as floats: the loader multiplies two
// finite doubles (emissiveFactor x emissiveStrength, colour x intensity) and
// leaves the overflow to the baker's boundary (docs/stability.md,
// tests/stability/stability_input_test.cpp). NaN or negative never.
inline bool nonNegative(const Rgb& c) { return c.r >= 0 && c.g >= 0 && c.b >= 0; }
inline bool finite(const Mat4& m) {
  for (float v : m.m) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}
inline bool inRange(int index, size_t size) { return index >= 0 && size_t(index) < size; }

/// Empty when `scene` keeps the contract of svit/scene.h and svit/level.h for
/// a successful load; otherwise the first broken promise.
inline std::string sceneContractViolation(const Scene& scene) {
  for (size_t t = 0; t < scene.textures.size(); ++t) {
    const Texture& x = scene.textures[t];
    const std::string w = "texture " + std::to_string(t);
    if (x.width <= 0 || x.height <= 0 || x.channels < 1 || x.channels > 4)
      return w + ": bad size or channels";
    if (x.texels.size() != size_t(x.width) * size_t(x.height) * size_t(x.channels))
      return w + ": texel count";
  }
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    const std::string w = "material " + std::to_string(i);
    for (const TextureRef* ref : {&m.base_color_texture, &m.emissive_texture}) {
      if (ref->texture != -1 && !inRange(ref->texture, scene.textures.size()))
        return w + ": texture index";
      if (ref->texcoord != 0 && ref->texcoord != 1) return w + ": texcoord set";
    }
    if (!finiteNonNegative(m.base_color) || !nonNegative(m.emissive_luminance))
      return w + ": colour";
  }
  for (size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& mesh = scene.meshes[i];
    const std::string w = "mesh " + std::to_string(i);
    const size_t vertices = mesh.positions.size(), triangles = mesh.triangleCount();
    if (mesh.normals.size() != vertices) return w + ": normals and positions differ in count";
    if (!mesh.uv0.empty() && mesh.uv0.size() != vertices) return w + ": uv0 count";
    if (!mesh.uv1.empty() && mesh.uv1.size() != vertices) return w + ": uv1 count";
    if (mesh.indices.size() % 3 != 0) return w + ": index count not a multiple of 3";
    if (mesh.triangle_material.size() != triangles || mesh.triangle_albedo.size() != triangles ||
        mesh.triangle_emission.size() != triangles || mesh.triangle_source.size() != triangles) {
      return w + ": per-triangle arrays differ from the triangle count";
    }
    for (uint32_t index : mesh.indices) {
      if (index >= vertices)
        return w + ": index " + std::to_string(index) + " >= " + std::to_string(vertices);
    }
    for (size_t v = 0; v < vertices; ++v) {
      const Vec3& n = mesh.normals[v];
      const double length = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
      // Unit length: a float normalisation leaves a few ulp; 1e-3 is generous.
      if (!finite(mesh.positions[v]) || !finite(n) || !(std::abs(length - 1.0) < 1e-3)) {
        const Vec3& p = mesh.positions[v];
        char values[200];
        std::snprintf(values, sizeof values,
                      "position (%g, %g, %g) or normal (%g, %g, %g) not finite, or normal not unit",
                      double(p.x), double(p.y), double(p.z), double(n.x), double(n.y), double(n.z));
        return w + " vertex " + std::to_string(v) + ": " + values;
      }
      if ((!mesh.uv0.empty() && !finite(mesh.uv0[v])) ||
          (!mesh.uv1.empty() && !finite(mesh.uv1[v]))) {
        return w + " vertex " + std::to_string(v) + ": uv not finite";
      }
    }
    for (size_t t = 0; t < triangles; ++t) {
      if (mesh.triangle_material[t] >= scene.materials.size())
        return w + ": triangle material index";
      if (!finiteNonNegative(mesh.triangle_albedo[t]) || !nonNegative(mesh.triangle_emission[t])) {
        return w + " triangle " + std::to_string(t) +
               ": albedo not finite and >= 0, or emission < 0 or NaN";
      }
    }
  }
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    const Node& n = scene.nodes[i];
    const std::string w = "node " + std::to_string(i);
    if (n.parent != -1 && !inRange(n.parent, scene.nodes.size())) return w + ": parent index";
    for (int child : n.children) {
      if (!inRange(child, scene.nodes.size())) return w + ": child index";
    }
    if (n.mesh != -1 && !inRange(n.mesh, scene.meshes.size())) return w + ": mesh index";
  }
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    const std::string w = "instance " + std::to_string(i);
    if (!inRange(instance.node, scene.nodes.size()) ||
        !inRange(instance.mesh, scene.meshes.size())) {
      return w + ": node or mesh index";
    }
    if (!finite(instance.world_from_object)) return w + ": world transform not finite";
  }
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    const std::string w = "light " + std::to_string(i);
    if (!std::isfinite(l.intensity) || l.intensity < 0 || !nonNegative(l.color))
      return w + ": intensity or colour";
    if (!std::isfinite(l.range_m) || l.range_m < 0) return w + ": range";
    if (!finite(l.position) || !finite(l.direction))
      return w + ": position or direction not finite";
    if (l.type == LightType::kSpot &&
        !(l.inner_cone_rad >= 0 && l.inner_cone_rad < l.outer_cone_rad &&
          l.outer_cone_rad <= 1.5707964f)) {
      return w + ": spot cone";
    }
    if (l.node != -1 && !inRange(l.node, scene.nodes.size())) return w + ": node index";
  }
  if (scene.sun.enabled &&
      (!finite(scene.sun.direction_to_sun) || !std::isfinite(scene.sun.illuminance_lux) ||
       scene.sun.illuminance_lux < 0 || !finiteNonNegative(scene.sun.color))) {
    return "sun: not finite";
  }
  if (!finiteNonNegative(scene.sky.zenith_luminance) ||
      !finiteNonNegative(scene.sky.horizon_luminance) ||
      !finiteNonNegative(scene.sky.ground_luminance)) {
    return "sky: not finite and >= 0";
  }
  for (size_t a = 0; a < scene.animations.size(); ++a) {
    for (const AnimationTrack& track : scene.animations[a].tracks) {
      const std::string w = "animation " + std::to_string(a);
      if (!inRange(track.node, scene.nodes.size())) return w + ": track node index";
      for (size_t k = 0; k < track.times_s.size(); ++k) {
        if (!std::isfinite(track.times_s[k]) ||
            (k > 0 && !(track.times_s[k] > track.times_s[k - 1]))) {
          return w + ": times not finite and ascending";
        }
      }
      for (float v : track.values) {
        if (!std::isfinite(v)) return w + ": value not finite";
      }
    }
  }
  for (size_t p = 0; p < scene.object_paths.size(); ++p) {
    const ObjectPath& path = scene.object_paths[p];
    const std::string w = "object path " + std::to_string(p);
    if (!inRange(path.node, scene.nodes.size())) return w + ": node index";
    if (path.animation != -1 && !inRange(path.animation, scene.animations.size()))
      return w + ": animation index";
  }
  return "";
}

}  // namespace svit::fuzz

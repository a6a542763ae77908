#pragma once
// Loading levels: a .gltf/.glb, or a level .json that names a glTF and adds
// sun, sky, lights, dynamic nodes, object paths and camera paths.

#include <string>

#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

struct LoadOptions {
  /// Decode base-colour and emissive textures (needed for per-triangle albedo
  /// and lightmaps). false: factors alone, faster for tools that only count.
  bool load_textures = true;
};

/// Loads a level from `path` (.gltf, .glb or .json, chosen by extension).
/// Errors name the file and element: unreadable or truncated files, bad
/// JSON, out-of-range indices, accessors or buffer views out of bounds,
/// NaN/Inf data, bad light parameters, unknown node names, unsupported
/// required extensions, a scene with no triangles. Degenerate triangles,
/// missing textures, points and lines are skipped and listed in
/// Scene::warnings. Thread-safe: yes (no shared state).
Expected<Scene> loadLevel(const std::string& path, const LoadOptions& options = {});

/// A sun or a sky given outside a level file (svit-bake --sun/--sky): the
/// JSON text of level.json's "sun" or "sky" object, checked as strictly
/// (docs/level-format.md). Errors (kInvalidInput) start with `origin` and
/// name the field: "--sun: sun.illuminance_lux: is required".
Expected<Sun> parseSunJson(const std::string& text, const std::string& origin);
Expected<Sky> parseSkyJson(const std::string& text, const std::string& origin);

/// Loads a bare glTF 2.0 file (.gltf or .glb).
Expected<Scene> loadGltf(const std::string& path, const LoadOptions& options = {});

/// Writes the scene's meshes, materials (factors and textures), nodes and
/// lights and cameras as a .gltf with an embedded buffer, dynamic marks as
/// extras.svit.dynamic. Writes `path`.tmp then renames, so a failure leaves
/// any previous file intact. Sun, sky and paths belong to level.json and are
/// not written.
Status writeGltf(const Scene& scene, const std::string& path);

}  // namespace svit

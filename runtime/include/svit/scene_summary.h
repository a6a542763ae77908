#pragma once
// What svit-info prints: counts, emitters, bounds and warnings of a level.

#include <cstddef>
#include <string>
#include <vector>

#include "svit/scene.h"

namespace svit {

struct SceneSummary {
  size_t static_triangles = 0;   ///< with instances placed
  size_t dynamic_triangles = 0;  ///< with instances placed
  size_t instances = 0;
  size_t dynamic_instances = 0;
  size_t meshes = 0;
  size_t materials = 0;
  size_t textures = 0;
  size_t emissive_triangles = 0;  ///< placed triangles with non-zero emission
  double emitted_flux_lm = 0;     ///< luminous flux of emissive triangles: sum of pi*Y*area*sides
  Rgb emitted_flux_rgb{0, 0, 0};  ///< the same per linear RGB channel
  size_t point_lights = 0;
  size_t spot_lights = 0;
  size_t directional_lights = 0;
  size_t dynamic_lights = 0;
  bool has_sun = false;
  bool has_sky = false;
  size_t animations = 0;
  size_t animation_tracks = 0;
  size_t object_paths = 0;
  size_t camera_paths = 0;
  std::vector<std::string> cameras;  ///< names of the glTF's viewpoints (Scene::cameras)
  Aabb bounds;                       ///< world bounds of all placed triangles, metres
  std::vector<std::string> warnings;
};

/// Counts and measures the scene. Pure; thread-safe.
SceneSummary summarize(const Scene& scene);

/// Multi-line human-readable summary (what `svit-info` prints).
std::string summaryToText(const std::string& level_path, const SceneSummary& summary);

/// The same as a JSON object (what `svit-info --json` prints).
std::string summaryToJson(const std::string& level_path, const SceneSummary& summary);

}  // namespace svit

#pragma once
// What the runtime reads from the level and its bake once, at creation:
// the scene and bake, the baked surfaces and lightmap pages, the runtime
// patches over the static surfaces and the triangles their maps draw. Never
// changed by update().

#include <cstdint>
#include <string>
#include <vector>

#include "indexmaps/emitter_samples.h"
#include "indexmaps/index_map_culling.h"
#include "indexmaps/index_map_renderer.h"
#include "receivers/runtime_patches.h"
#include "svit/baked_surfaces.h"
#include "svit/lightmap_image.h"
#include "svit/masked_lights.h"
#include "svit/runtime.h"

namespace svit::gl {

struct StaticLevel {
  Scene scene;
  BakeData bake;
  std::string bake_dir;
  BakedSurfaces surfaces;
  std::vector<LightmapImage> pages;
  /// The bake's masked lights (their direct light is not in `pages`);
  /// bake.masks keeps their list, the field their texels.
  MaskedLightField masked;

  /// Receivers of the static level; groups (what shoots) are bake patches.
  RuntimePatches patches;
  uint32_t static_receivers = 0;
  uint32_t static_groups = 0;
  MapTriangles static_map;
  /// per runtime patch: its static map triangles
  std::vector<std::vector<uint32_t>> patch_map_triangles;
  /// Per whole block of kShareBlockReceivers static patches: the box of
  /// their bounds (reaches() tests a block before its patches).
  std::vector<Aabb> static_block_bounds;
  /// The level's bounding sphere: the sun's and sky's samples cover it.
  ParallelWindow window{};
  /// Samples sit this far off their surface so the map's near plane clears it.
  float sample_offset_m = 1e-4f;
};

/// Reads the bake's surfaces and pages and, when the bake has runtime
/// sections, builds about settings.target_patches runtime patches over the
/// static surfaces. Errors name `bake_dir`: unreadable pages, a level with
/// dynamic content baked without runtime sections, bad sections.
Expected<StaticLevel> buildStaticLevel(const Scene& scene, const BakeData& bake,
                                       const std::string& bake_dir,
                                       const RuntimeSettings& settings);

}  // namespace svit::gl

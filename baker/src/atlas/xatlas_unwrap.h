#pragma once
// The xatlas path of buildLightmapAtlas: static instances charted in
// parallel groups, then packed together into the pages.

#include <cstddef>
#include <vector>

#include "atlas_instances.h"
#include "svit/baker/lightmap_atlas.h"

namespace svit::baker {

/// Triangles per charting group. xatlas charts each instance on its own, so
/// groups only batch instances for the workers: 16k triangles gives a level of
/// a quarter million triangles about 16 groups to balance, while each atlas's
/// fixed costs stay small. Fixed, never derived from the thread count: the
/// groups, and so the atlas, are the same on every machine. A range is never
/// split here: one above this is a group of its own.
constexpr size_t kXatlasGroupTriangles = 16384;

/// Charts every range of `ranges` (an instance or a piece of one, each
/// separately, world positions at
/// settings.texels_per_m) and packs all charts into pages of at most
/// settings.max_page_size with settings.padding_texels. Uses
/// settings.threads workers; the result does not depend on their number.
/// Errors: kUnsupported naming the triangle xatlas leaves out (below its
/// zero-area threshold), kInternal where xatlas's output disagrees with its
/// input.
Expected<LightmapAtlas> buildWithXatlas(const Scene& scene, const BakeGeometry& geometry,
                                        const std::vector<InstanceRange>& ranges,
                                        const AtlasSettings& settings);

}  // namespace svit::baker

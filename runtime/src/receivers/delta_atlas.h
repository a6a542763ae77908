#pragma once
// The runtime's displayed deltas as textures in lightmap space: per atlas
// page, an RGBA float image at half the page's resolution (alpha: the
// factor on the lightmap minus 1, runtime_light_scale.cpp), rasterised from
// the runtime patches' sub-triangles with their welded-vertex values
// (linear across each sub-triangle, so the per-patch deltas are smooth on
// screen), plus a one-texel gutter so bilinear filtering never reads an
// empty texel. A shader adds texture(delta, lightmap_uv) to the lightmap.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "runtime_patches.h"

namespace svit::gl {

struct DeltaPage {
  int width = 0, height = 0;
  std::vector<float> rgba;  ///< row-major, 4 floats per texel, row 0 = v in [0, 1/height)
};

/// Rasterises `vertex_values` (per welded vertex, lux) and the x of
/// `scale_minus_one` (per welded vertex; empty: 0 everywhere) over the sub-triangles into pages
/// of half the lightmap pages' sizes (at least 1 texel).
std::vector<DeltaPage> rasteriseDeltas(const RuntimePatches& patches,
                                       const std::vector<glm::dvec3>& vertex_values,
                                       const std::vector<glm::dvec3>& scale_minus_one,
                                       const std::vector<std::pair<int, int>>& page_sizes);

}  // namespace svit::gl

#pragma once
// The texels around a texel that the lightmap filter may mix with it: in
// the (2r + 1)^2 window on its page, on the same chart and facing the same
// side. Internal.

#include <cstddef>
#include <cstdint>

#include "svit/baker/lightmap_atlas.h"

namespace svit::baker {

/// Calls visit(j, dx, dy, cos) for every covered texel j in the window of
/// radius `r` around sample `i` whose chart is i's and whose normal makes a
/// positive cosine `cos` with i's (i itself included, at 0, 0, 1).
template <typename Visit>
void forEachChartNeighbour(const LightmapAtlas& atlas, const TexelSet& texels, size_t i, int r,
                           Visit&& visit) {
  const TexelSample& s = texels.samples[i];
  const uint32_t chart = atlas.triangle_chart[s.face];
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const int x = int(s.x) + dx, y = int(s.y) + dy;
      if (x < 0 || y < 0 || x >= texels.page_width || y >= texels.page_height) continue;
      const int32_t j = texels.sampleAt(s.page, uint32_t(x), uint32_t(y));
      if (j < 0) continue;
      const TexelSample& o = texels.samples[size_t(j)];
      if (atlas.triangle_chart[o.face] != chart) continue;
      const double c = s.normal.x * o.normal.x + s.normal.y * o.normal.y + s.normal.z * o.normal.z;
      if (c <= 0) continue;
      visit(size_t(j), dx, dy, c);
    }
  }
}

}  // namespace svit::baker

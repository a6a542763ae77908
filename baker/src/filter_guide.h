#pragma once
// The lightmap filter's guide (lightmap_pages.h, FilterGuide) from a bake's
// lighting passes: each texel's mean indirect luminance, and the standard
// error of that mean from the even passes' mean against the odd passes'
// (so a sharded bake's merge, which keeps only those sums, has it too).
// Internal.

#include <memory>

#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "texel_accumulator.h"

namespace svit::baker {

/// Null with fewer than two passes: no spread to tell noise by. One texel's
/// two halves give its variance from a single difference, so the squared
/// differences are averaged over the filter's own window (radius `radius`,
/// same chart and side) before the square root.
std::shared_ptr<const FilterGuide> filterGuide(const LightmapAtlas& atlas, const TexelSet& texels,
                                               const TexelAccumulator& accumulator, int radius);

}  // namespace svit::baker

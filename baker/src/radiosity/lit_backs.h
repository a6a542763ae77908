#pragma once
// Which double-sided triangles' backs light can reach, so that only those
// get lightmap texels of their own (docs/architecture/baker-lightmaps.md
// "Backs"). Exporters write `doubleSided: true` on every material; a wall
// of a closed room, or of the Cornell box, then has a back that faces the
// void outside, and a lightmap for it would double the texels and halve
// the passes a budget affords for texels no one can see lit.
//
// The voxel flood (light_reach.h) cannot tell: the outside of an open box
// is connected free space, yet no light goes there and comes back. So each
// back looks out with rays from points inside the triangle: it is lit
// where a ray escapes into a sky, where a lamp or the sun is in sight, or
// where a ray meets a side that is itself lit (a front in reached space,
// or a back already found lit, to a fixed point). A back whose every ray
// escapes into the void, or meets only unlit backs, is dark: black, and no
// baked light ever changes that. A back in a gap narrower than the rays'
// spacing may be called dark though light trickles in: that error is at
// most the light through the gap, and the report counts the dark backs.

#include <cstdint>
#include <vector>

#include "light_reach.h"
#include "light_sources.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {

struct LitBacks {
  std::vector<uint8_t> lit;  ///< per triangle: 1 = double-sided and its back is lit
  LitBacksStats stats;
};

/// Rays per back, cast in two halves (the second only where the first found
/// no light): from 4 points inside the triangle, cosine-distributed.
inline constexpr int kLitBackRays = 64;

/// The lit backs of `geometry`'s double-sided triangles. Deterministic for
/// any thread count.
LitBacks findLitBacks(const BakeGeometry& geometry, const RayCaster& caster,
                      const std::vector<LightSource>& lights, const LightReach& reach, int threads);

}  // namespace svit::baker

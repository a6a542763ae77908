#pragma once
// Shadow masks (thesis 5.3 steps 9-10, docs/architecture/baker-lightmaps.md
// "Shadow masks"): for a level with dynamic objects, the static visibility of
// each significant baked light (point, spot, directional, the sun) per
// lightmap texel, so the runtime can shade that light's direct light per
// pixel and multiply in the dynamic objects' shadow from its own depth map.
// The lighting passes leave those lights' direct light out of the lightmap
// (TexelLightingSettings::masked); their bounce stays in it.

#include <atomic>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/ray_caster.h"
#include "svit/baker/texel_lighting.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

/// At most this many lights get a mask; the rest keep the lightmap and the
/// runtime's patch path (listed in report.json).
inline constexpr size_t kMaxMaskedLights = 32;
/// An emissive instance with at most this many emitting triangle sides is
/// a lamp, masked as area lights (one per patch of it); more make a
/// glowing surface, which keeps the lightmap and the patch deltas.
inline constexpr size_t kMaxAreaLightSides = 16;

/// A baked light the bake does not mask, and why.
struct UnmaskedLight {
  std::string light;  ///< its name ("sun" for the sun)
  std::string reason;
};

struct MaskChoice {
  MaskedLights masked;
  std::vector<UnmaskedLight> unmasked;
  /// Why nothing is masked ("the level has no dynamic objects"); empty
  /// when some light is.
  std::string none_reason;
};

/// The lights to mask: every static light with intensity, the sun and the
/// lamps (static instances with 1..kMaxAreaLightSides emissive triangle
/// sides), for a level with dynamic instances and `enabled`
/// (BakeOptions::shadow_masks). Within kMaxMaskedLights the sun comes
/// first, then the lamps in instance order (a slot per emissive side),
/// then directional lights and punctual lights by luminous intensity x
/// cone solid angle. Deterministic. The lamps' area lights are filled in
/// by addAreaLights once the patches exist.
MaskChoice chooseMaskedLights(const Scene& scene, const BakeGeometry& geometry, bool enabled);

/// One masked area light per patch that holds emissive elements of
/// `masked.emissive_instances` (BakeData::patches and patch_elements):
/// fills masked.area_elements and area_patches, in patch order.
void addAreaLights(const BakeGeometry& geometry, const std::vector<BakePatch>& patches,
                   const std::vector<uint32_t>& patch_elements, MaskedLights& masked);

struct ShadowMaskSettings {
  uint64_t seed = 1;
  int threads = 0;
  uint32_t sun_samples = 16;  ///< rays over the sun's disk per texel
  PageSettings pages;         ///< dilation and seams as the lightmap's (its filter is not used)
};

/// Traces and packs the masks of `masked` into `masks` (BakeShadowMasks
/// describes the layout): visibility per texel, dilated and seamed per
/// light like the lightmap, quantised to 8 bits; lights whose masks
/// overlap (both above zero at a texel) get different channels, greedily in
/// `masked` order. `emitters`: the bake's, to name each light's emitter.
/// Errors: a masked light with no bake emitter, cancellation.
Expected<BakeShadowMasks> buildShadowMasks(const Scene& scene, const BakeGeometry& geometry,
                                           const RayCaster& caster, const LightmapAtlas& atlas,
                                           const TexelSet& texels, const MaskedLights& masked,
                                           const std::vector<BakeEmitter>& emitters,
                                           const ShadowMaskSettings& settings,
                                           const std::atomic<bool>* cancel = nullptr);

/// Texels of `page` whose channel value names `light` (reached by it).
size_t maskTexelsOf(const BakeShadowMasks& masks, size_t light, size_t page);

}  // namespace svit::baker

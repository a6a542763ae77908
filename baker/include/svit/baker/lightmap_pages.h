#pragma once
// From lit texels to lightmap pages a GPU samples: an optional edge-aware
// filter of the indirect light that never crosses charts, seam stitching so
// texels on both sides of a UV seam agree, and dilation into the padding so
// bilinear filtering never reads an empty texel.

#include <memory>
#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/texel_lighting.h"
#include "svit/lightmap_image.h"

namespace svit::baker {

/// What tells the edge-aware filter noise from light: per texel (TexelSet
/// order), the luminance of a mean of its indirect light and that mean's
/// standard error, lux (filtered_passes.h makes one of each half of a
/// bake's passes, to filter the other half).
struct FilterGuide {
  std::vector<float> luminance, sigma;
};

struct PageSettings {
  int dilation_texels = 2;         ///< rings of empty texels filled around every chart
  bool edge_aware_filter = false;  ///< smooth gather noise in the indirect light
  int filter_radius_texels = 2;
  double filter_normal_power = 16;  ///< weight cos(normal angle)^power
  /// The filter mixes a neighbour in by exp(-d^2 / (2 k^2 (s_i^2 + s_j^2)))
  /// for guide luminances that differ by d and standard errors s: noise
  /// (d within a few s) is smoothed, a real edge of the indirect light (a
  /// contact shadow, the sky's edge under a roof) is left sharp. k is this.
  double filter_noise_sigmas = 2;
  /// Without a guide the filter is off: nothing tells noise from an edge.
  /// The weights depend on the guide and the geometry only, so the filter
  /// is linear in the light it filters (the split-half estimate needs that).
  std::shared_ptr<const FilterGuide> guide;
  int seam_iterations = 4;
  int threads = 0;  ///< the filter's workers, 0: all cores; the result does not depend on it
};

struct LightmapPages {
  std::vector<LightmapImage> images;  ///< irradiance, lux
  /// per page texel: 1 covered, 2 dilated, 3 buried (black), 0 empty
  std::vector<std::vector<uint8_t>> valid;
};

/// The indirect light of `lighting` (TexelSet order) as the pages hold it:
/// smoothed within charts where `settings` asks for the filter and gives a
/// guide, else as it is. Linear in `lighting` for a given guide.
std::vector<Rgb> filterIndirect(const LightmapAtlas& atlas, const TexelSet& texels,
                                const std::vector<TexelIrradiance>& lighting,
                                const PageSettings& settings);

LightmapPages buildLightmapPages(const BakeGeometry& geometry, const LightmapAtlas& atlas,
                                 const TexelSet& texels,
                                 const std::vector<TexelIrradiance>& lighting,
                                 const PageSettings& settings);

/// Pairs of (page, uv) on both sides of each UV seam, sampled along shared
/// edges; what seam stitching makes agree, exposed for tests.
struct SeamPoint {
  uint32_t page_a, page_b;
  Vec2 uv_a, uv_b;
};
std::vector<SeamPoint> findSeamPoints(const BakeGeometry& geometry, const LightmapAtlas& atlas);

}  // namespace svit::baker

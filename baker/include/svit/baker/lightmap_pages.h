#pragma once
// From lit texels to lightmap pages a GPU samples: an optional edge-aware
// filter of the indirect light that never crosses charts, seam stitching so
// texels on both sides of a UV seam agree, and dilation into the padding so
// bilinear filtering never reads an empty texel.

#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/texel_lighting.h"
#include "svit/lightmap_image.h"

namespace svit::baker {

struct PageSettings {
  int dilation_texels = 2;         ///< rings of empty texels filled around every chart
  bool edge_aware_filter = false;  ///< smooth gather noise in the indirect light
  int filter_radius_texels = 2;
  double filter_normal_power = 16;  ///< weight cos(normal angle)^power
  int seam_iterations = 4;
};

struct LightmapPages {
  std::vector<LightmapImage> images;  ///< irradiance, lux
  /// per page texel: 1 covered, 2 dilated, 3 buried (black), 0 empty
  std::vector<std::vector<uint8_t>> valid;
};

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

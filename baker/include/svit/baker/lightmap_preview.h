#pragma once
// An 8-bit sRGB PNG view of lightmap pages, for people: exposure set so the
// 99th percentile of texel luminance maps to white, Reinhard-free clamp.

#include <string>
#include <vector>

#include "svit/lightmap_image.h"
#include "svit/status.h"

namespace svit::baker {

/// Writes the pages side by side into one PNG (via `path`.tmp and a rename).
/// `exposure` > 0 multiplies luminance before the sRGB curve; 0 = automatic.
Status writeLightmapPreviewPng(const std::vector<LightmapImage>& pages, const std::string& path,
                               double exposure = 0);

}  // namespace svit::baker

#pragma once
// A lightmap atlas page in memory and on disk (fp32 OpenEXR, RGB): what the
// baker writes and what svit-probe and the runtime read. Sampling matches a
// GL sampler: bilinear, texel centres at (i + 0.5) / size, clamp to edge.

#include <cstdint>
#include <string>
#include <vector>

#include "svit/math_types.h"
#include "svit/status.h"

namespace svit {

struct LightmapImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  ///< row-major, 3 floats per texel, row 0 = v in [0, 1/height)
  /// The EXR's standard "comments" attribute (a page says there why it is
  /// black, for one); empty: none written, or none in the file.
  std::string comments;

  Rgb texel(int x, int y) const {
    const float* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
    return {p[0], p[1], p[2]};
  }
  /// Bilinear lookup at page coordinates `uv` in [0, 1] (u right, v down the rows).
  Rgb sampleBilinear(Vec2 uv) const;
};

/// Page `page` of `pages` sampled at `uv`; 0 where `page` is none of them
/// (the back no baked light reaches, BakeBackUv's kUnlitBackPage).
inline Rgb samplePage(const std::vector<LightmapImage>& pages, uint32_t page, Vec2 uv) {
  return page < pages.size() ? pages[page].sampleBilinear(uv) : Rgb{0, 0, 0};
}

/// Writes an fp32 RGB EXR (with a "comments" attribute when `comments` is
/// set) via `path`.tmp and a rename. Errors: non-finite
/// texels (naming the first), I/O failure.
Status writeLightmapExr(const LightmapImage& image, const std::string& path);

/// Reads an EXR written by writeLightmapExr: any single-part scanline EXR
/// with R, G and B channels of half or float (other channels ignored),
/// uncompressed, RLE or ZIP. Errors name the file: not found, not an EXR,
/// tiled/deep/multi-part, subsampled or PIZ/other compression
/// (kUnsupported), no R, G or B channel, a data window empty or
/// over 16384 texels a side or larger than the file could hold compressed,
/// corrupt pixel data, a texel that is not finite. Thread-safe: yes.
Expected<LightmapImage> readLightmapExr(const std::string& path);

}  // namespace svit

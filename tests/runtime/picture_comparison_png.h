#pragma once
// A side-by-side picture of the metric's inputs (tests/runtime/picture_metric.h):
// the shown frame, the reference, and their luminance difference in false
// colour (red where the shown frame is brighter, blue where darker, full at
// `difference_scale` of the reference's mean), one PNG, for people to look at.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "picture_metric.h"
#include "render/scene_renderer_target.h"

namespace svit::test {

// Radiance to display sRGB as svit_shading.frag's svitDisplay does it.
inline uint8_t displayByte(float radiance, float exposure) {
  const float x = std::max(radiance, 0.0f) * exposure;
  const float curve =
      std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
  const float srgb =
      curve <= 0.0031308f ? 12.92f * curve : 1.055f * std::pow(curve, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(255.0f * srgb));
}

inline Status writeComparisonPng(const std::string& path, const LinearFrame& shown,
                                 const LinearFrame& reference, float exposure,
                                 double difference_scale = 0.25) {
  const int w = shown.width, h = shown.height;
  const double mean = comparePictures(reference, reference).static_reference_mean;
  std::vector<uint8_t> rgb(size_t(w) * 3 * size_t(h) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      uint8_t* row = &rgb[(size_t(y) * size_t(w) * 3) * 3];
      for (int c = 0; c < 3; ++c) {
        row[size_t(x) * 3 + size_t(c)] = displayByte(shown.rgb[i * 3 + size_t(c)], exposure);
        row[(size_t(w) + size_t(x)) * 3 + size_t(c)] =
            displayByte(reference.rgb[i * 3 + size_t(c)], exposure);
      }
      const double d = rec709Luminance(&shown.rgb[i * 3]) - rec709Luminance(&reference.rgb[i * 3]);
      const double s = std::min(1.0, std::abs(d) / std::max(difference_scale * mean, 1e-30));
      const uint8_t v = uint8_t(std::lround(255.0 * std::sqrt(s)));
      uint8_t* out = &row[(size_t(2 * w) + size_t(x)) * 3];
      out[0] = d > 0 ? v : 0;
      out[1] = 0;
      out[2] = d < 0 ? v : 0;
    }
  }
  return gl::writeRgbPng(path, w * 3, h, rgb);
}

}  // namespace svit::test

#include "svit/baker/lightmap_preview.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include <stb_image_write.h>

namespace svit::baker {
namespace {

uint8_t toSrgb8(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return uint8_t(std::lround(encoded * 255.0));
}

}  // namespace

Status writeLightmapPreviewPng(const std::vector<LightmapImage>& pages, const std::string& path,
                               double exposure) {
  if (pages.empty()) return Status(StatusCode::kInvalidInput, path + ": no lightmap pages to show");
  int width = 0, height = 0;
  for (const LightmapImage& page : pages) {
    width += page.width;
    height = std::max(height, page.height);
  }
  if (!(exposure > 0)) {
    std::vector<float> luminances;
    for (const LightmapImage& page : pages) {
      for (size_t i = 0; i + 2 < page.rgb.size(); i += 3) {
        const float y = luminance(Rgb{page.rgb[i], page.rgb[i + 1], page.rgb[i + 2]});
        if (y > 0) luminances.push_back(y);
      }
    }
    if (luminances.empty()) {
      exposure = 1;
    } else {
      const size_t k = size_t(double(luminances.size() - 1) * 0.99);
      std::nth_element(luminances.begin(), luminances.begin() + long(k), luminances.end());
      exposure = 1.0 / std::max(1e-30, double(luminances[k]));
    }
  }
  std::vector<uint8_t> pixels(size_t(width) * size_t(height) * 3, 0);
  int x0 = 0;
  for (const LightmapImage& page : pages) {
    for (int y = 0; y < page.height; ++y) {
      for (int x = 0; x < page.width; ++x) {
        const Rgb c = page.texel(x, y);
        uint8_t* p = &pixels[(size_t(y) * size_t(width) + size_t(x0 + x)) * 3];
        p[0] = toSrgb8(c.r * exposure);
        p[1] = toSrgb8(c.g * exposure);
        p[2] = toSrgb8(c.b * exposure);
      }
    }
    x0 += page.width;
  }
  const std::string temporary = path + ".tmp";
  if (!stbi_write_png(temporary.c_str(), width, height, 3, pixels.data(), width * 3)) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    return Status(StatusCode::kIoError, path + ": cannot write PNG");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) return Status(StatusCode::kIoError, path + ": cannot rename " + temporary);
  return Status();
}

}  // namespace svit::baker

#include "svit/lightmap_image.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <tinyexr.h>

namespace svit {

Rgb LightmapImage::sampleBilinear(Vec2 uv) const {
  if (width <= 0 || height <= 0) return {0, 0, 0};
  const float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int x0 = std::clamp(int(fx), 0, width - 1), x1 = std::clamp(int(fx) + 1, 0, width - 1);
  const int y0 = std::clamp(int(fy), 0, height - 1), y1 = std::clamp(int(fy) + 1, 0, height - 1);
  const Rgb a = texel(x0, y0), b = texel(x1, y0), c = texel(x0, y1), d = texel(x1, y1);
  auto mix = [&](float p, float q, float r, float s) {
    return (p * (1 - tx) + q * tx) * (1 - ty) + (r * (1 - tx) + s * tx) * ty;
  };
  return {mix(a.r, b.r, c.r, d.r), mix(a.g, b.g, c.g, d.g), mix(a.b, b.b, c.b, d.b)};
}

Status writeLightmapExr(const LightmapImage& image, const std::string& path) {
  const size_t texels = size_t(image.width) * size_t(image.height);
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != texels * 3) {
    return Status(StatusCode::kInvalidInput, path + ": lightmap image has inconsistent size");
  }
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    if (!std::isfinite(image.rgb[i])) {
      return Status(StatusCode::kInvalidInput, path + ": texel (" + std::to_string((i / 3) % size_t(image.width)) +
                                                   ", " + std::to_string((i / 3) / size_t(image.width)) +
                                                   ") is not finite");
    }
  }
  // EXR stores channels as planes, conventionally sorted by name: B, G, R.
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c) planes[c].resize(texels);
  for (size_t i = 0; i < texels; ++i) {
    planes[0][i] = image.rgb[i * 3 + 2];
    planes[1][i] = image.rgb[i * 3 + 1];
    planes[2][i] = image.rgb[i * 3 + 0];
  }
  float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
  EXRHeader header;
  InitEXRHeader(&header);
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = 3;
  exr.images = reinterpret_cast<unsigned char**>(plane_pointers);
  exr.width = image.width;
  exr.height = image.height;
  header.num_channels = 3;
  EXRChannelInfo channels[3];
  std::memset(channels, 0, sizeof channels);
  std::strcpy(channels[0].name, "B");
  std::strcpy(channels[1].name, "G");
  std::strcpy(channels[2].name, "R");
  header.channels = channels;
  int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  int requested[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  header.pixel_types = pixel_types;
  // fp32, not half: direct sunlight (1e5 lux) overflows half's 65504.
  header.requested_pixel_types = requested;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  const std::string temporary = path + ".tmp";
  const char* error = nullptr;
  const int result = SaveEXRImageToFile(&exr, &header, temporary.c_str(), &error);
  if (result != TINYEXR_SUCCESS) {
    const std::string message = error ? error : "unknown error";
    FreeEXRErrorMessage(error);
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    return Status(StatusCode::kIoError, path + ": cannot write EXR: " + message);
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    return Status(StatusCode::kIoError, path + ": cannot rename " + temporary);
  }
  return Status();
}

Expected<LightmapImage> readLightmapExr(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Status(StatusCode::kNotFound, path + ": file not found");
  float* rgba = nullptr;
  int width = 0, height = 0;
  const char* error = nullptr;
  const int result = LoadEXR(&rgba, &width, &height, path.c_str(), &error);
  if (result != TINYEXR_SUCCESS) {
    const std::string message = error ? error : "unknown error";
    FreeEXRErrorMessage(error);
    return Status(StatusCode::kInvalidInput, path + ": not a readable EXR: " + message);
  }
  LightmapImage image;
  image.width = width;
  image.height = height;
  image.rgb.resize(size_t(width) * size_t(height) * 3);
  for (size_t i = 0; i < size_t(width) * size_t(height); ++i) {
    for (int c = 0; c < 3; ++c) image.rgb[i * 3 + size_t(c)] = rgba[i * 4 + size_t(c)];
  }
  std::free(rgba);
  return image;
}

}  // namespace svit

#include "texture_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace svit {
namespace {

const std::array<float, 256>& srgbTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

int wrapIndex(int i, int n, WrapMode mode) {
  switch (mode) {
    case WrapMode::kClampToEdge: return std::clamp(i, 0, n - 1);
    case WrapMode::kMirroredRepeat: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case WrapMode::kRepeat:
    default: {
      int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

Vec4 fetch(const Texture& texture, int x, int y, bool srgb) {
  const size_t base = (size_t(y) * size_t(texture.width) + size_t(x)) * size_t(texture.channels);
  const uint8_t* p = texture.texels.data() + base;
  auto colour = [&](uint8_t v) { return srgb ? srgbTable()[v] : v / 255.0f; };
  switch (texture.channels) {
    case 1: {
      const float g = colour(p[0]);
      return {g, g, g, 1.0f};
    }
    case 2: {
      const float g = colour(p[0]);
      return {g, g, g, p[1] / 255.0f};
    }
    case 3: return {colour(p[0]), colour(p[1]), colour(p[2]), 1.0f};
    default: return {colour(p[0]), colour(p[1]), colour(p[2]), p[3] / 255.0f};
  }
}

}  // namespace

float srgbToLinear(uint8_t encoded) { return srgbTable()[encoded]; }

Vec2 transformUv(const TextureRef& ref, Vec2 uv) {
  const float su = uv.x * ref.scale.x, sv = uv.y * ref.scale.y;
  const float c = std::cos(ref.rotation_rad), s = std::sin(ref.rotation_rad);
  // KHR_texture_transform: rotation is counter-clockwise in UV space.
  return {ref.offset.x + c * su + s * sv, ref.offset.y - s * su + c * sv};
}

Vec4 sampleBilinear(const Texture& texture, Vec2 uv, bool srgb) {
  if (texture.width <= 0 || texture.height <= 0 || texture.channels <= 0) return {1, 1, 1, 1};
  const float x = uv.x * float(texture.width) - 0.5f;
  const float y = uv.y * float(texture.height) - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return fetch(texture, 0, 0, srgb);
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  // Reduce large coordinates before converting to int (UVs far outside [0,1]).
  const auto reduce = [](float f, int n) { return int(std::fmod(double(f), 2.0 * n)); };
  const int x0 = reduce(fx, texture.width), y0 = reduce(fy, texture.height);
  const int xa = wrapIndex(x0, texture.width, texture.wrap_s);
  const int xb = wrapIndex(x0 + 1, texture.width, texture.wrap_s);
  const int ya = wrapIndex(y0, texture.height, texture.wrap_t);
  const int yb = wrapIndex(y0 + 1, texture.height, texture.wrap_t);
  const Vec4 c00 = fetch(texture, xa, ya, srgb), c10 = fetch(texture, xb, ya, srgb);
  const Vec4 c01 = fetch(texture, xa, yb, srgb), c11 = fetch(texture, xb, yb, srgb);
  auto lerp2 = [&](float a, float b, float c, float d) {
    return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
  };
  return {lerp2(c00.x, c10.x, c01.x, c11.x), lerp2(c00.y, c10.y, c01.y, c11.y),
          lerp2(c00.z, c10.z, c01.z, c11.z), lerp2(c00.w, c10.w, c01.w, c11.w)};
}

Rgb meanOverTriangle(const Texture& texture, Vec2 a, Vec2 b, Vec2 c, bool srgb) {
  // Footprint in texels decides the subdivision: about one sample per texel,
  // at most 16*16 = 256 (enough for a mean; the lightmapper samples per texel).
  const double area_uv =
      0.5 * std::abs(double(b.x - a.x) * (c.y - a.y) - double(c.x - a.x) * (b.y - a.y));
  const double area_texels = area_uv * texture.width * texture.height;
  const int k = std::isfinite(area_texels)
                    ? std::clamp(int(std::ceil(std::sqrt(std::max(area_texels, 1.0)))), 1, 16)
                    : 1;
  // Split the triangle into k*k congruent sub-triangles (k-1 upward rows of
  // grid cells) and sample each centroid: uniform and deterministic.
  double sum[3] = {0, 0, 0};
  int samples = 0;
  const float inv = 1.0f / float(k);
  auto point = [&](float u, float v) {  // barycentric (u along b-a, v along c-a)
    return Vec2{a.x + u * (b.x - a.x) + v * (c.x - a.x), a.y + u * (b.y - a.y) + v * (c.y - a.y)};
  };
  auto add = [&](float u, float v) {
    const Vec4 s = sampleBilinear(texture, point(u, v), srgb);
    sum[0] += s.x;
    sum[1] += s.y;
    sum[2] += s.z;
    ++samples;
  };
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j + i < k; ++j) {
      add((float(i) + 1.0f / 3.0f) * inv, (float(j) + 1.0f / 3.0f) * inv);  // upward
      if (i + j + 1 < k) add((float(i) + 2.0f / 3.0f) * inv, (float(j) + 2.0f / 3.0f) * inv);
    }
  }
  return {float(sum[0] / samples), float(sum[1] / samples), float(sum[2] / samples)};
}

}  // namespace svit

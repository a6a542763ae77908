#pragma once
// Sampling svit::Texture in linear colour: sRGB decode, glTF wrap modes,
// bilinear filtering, KHR_texture_transform, and the mean over a triangle's
// UV footprint (the per-triangle albedo the radiosity solver uses).

#include "svit/scene.h"

namespace svit {

/// sRGB-encoded 8-bit value to linear [0,1] (IEC 61966-2-1 curve, exact per value).
float srgbToLinear(uint8_t encoded);

/// Applies a TextureRef's KHR_texture_transform to a UV.
Vec2 transformUv(const TextureRef& ref, Vec2 uv);

/// Bilinear sample at `uv` (glTF convention: v = 0 is the first row), with the
/// texture's wrap modes. Colour channels decoded from sRGB when `srgb`; alpha
/// always linear. Missing channels: grey replicates, alpha 1.
Vec4 sampleBilinear(const Texture& texture, Vec2 uv, bool srgb);

/// Mean linear colour over the triangle with UVs `a`, `b`, `c` (already
/// transformed), estimated at centroids of a uniform subdivision of the
/// triangle into k*k parts, k growing with the texel footprint up to 16.
/// Deterministic.
Rgb meanOverTriangle(const Texture& texture, Vec2 a, Vec2 b, Vec2 c, bool srgb);

}  // namespace svit

#include <gtest/gtest.h>

#include "scene/texture_sampling.h"

namespace svit {
namespace {

Texture checker2x2() {
  Texture t;
  t.width = 2;
  t.height = 2;
  t.channels = 3;
  // sRGB 255 and 0: linear 1 and 0.
  t.texels = {255, 255, 255, 0, 0, 0, 0, 0, 0, 255, 255, 255};
  return t;
}

TEST(TextureSampling, SrgbDecodeMatchesTheStandardCurve) {
  EXPECT_FLOAT_EQ(srgbToLinear(0), 0.0f);
  EXPECT_FLOAT_EQ(srgbToLinear(255), 1.0f);
  // sRGB 0.5 (128/255 = 0.50196) -> linear 0.21586 (IEC 61966-2-1).
  EXPECT_NEAR(srgbToLinear(128), 0.21586f, 1e-4f);
}

TEST(TextureSampling, TexelCentresReturnTexels) {
  const Texture t = checker2x2();
  EXPECT_FLOAT_EQ(sampleBilinear(t, {0.25f, 0.25f}, true).x, 1.0f);
  EXPECT_FLOAT_EQ(sampleBilinear(t, {0.75f, 0.25f}, true).x, 0.0f);
  EXPECT_FLOAT_EQ(sampleBilinear(t, {0.75f, 0.75f}, true).x, 1.0f);
}

TEST(TextureSampling, RepeatWrapsAndClampHolds) {
  Texture t = checker2x2();
  EXPECT_FLOAT_EQ(sampleBilinear(t, {1.25f, 0.25f}, true).x, 1.0f);
  EXPECT_FLOAT_EQ(sampleBilinear(t, {-0.75f, 0.25f}, true).x, 1.0f);
  t.wrap_s = WrapMode::kClampToEdge;
  EXPECT_FLOAT_EQ(sampleBilinear(t, {5.0f, 0.25f}, true).x, 0.0f);
}

TEST(TextureSampling, MeanOverWholeCheckerIsHalf) {
  const Texture t = checker2x2();
  // The two triangles tile one period of the texture, so their mean is the
  // texture mean, 0.5; 4 stratified samples each leave about 2% error.
  const Rgb a = meanOverTriangle(t, {0, 0}, {1, 0}, {0, 1}, true);
  const Rgb b = meanOverTriangle(t, {1, 0}, {1, 1}, {0, 1}, true);
  EXPECT_NEAR(0.5f * (a.r + b.r), 0.5f, 0.02f);
}

TEST(TextureSampling, TransformAppliesScaleThenOffset) {
  TextureRef ref;
  ref.scale = {2, 3};
  ref.offset = {0.5f, 0.25f};
  const Vec2 uv = transformUv(ref, {1, 1});
  EXPECT_FLOAT_EQ(uv.x, 2.5f);
  EXPECT_FLOAT_EQ(uv.y, 3.25f);
}

}  // namespace
}  // namespace svit

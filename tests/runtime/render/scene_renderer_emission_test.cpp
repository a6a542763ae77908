// A lamp switched off looks off: SceneRenderer::setBakedEmitterScale scales
// the emission drawn on the patches of a kPatch bake emitter (the Cornell
// ceiling lamp), in the runtime and patch-delta views, while kBakedOnly
// keeps the bake as baked; bad arguments are refused and change nothing.
// Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

std::vector<uint32_t> patchEmitters(const BakeData& bake) {
  std::vector<uint32_t> out;
  for (uint32_t e = 0; e < bake.emitters.size(); ++e) {
    if (bake.emitters[e].kind == BakeEmitter::Kind::kPatch) out.push_back(e);
  }
  return out;
}

struct LampFrame {
  Pixel lamp, ceiling, back_wall;  // ceiling: beside the lamp
  std::vector<uint8_t> rgb;
};

LampFrame renderLamp(SceneRenderer& renderer, const BakedLevel& level, ShadingView view) {
  const Camera camera = cameraOf(level.scene);
  EXPECT_TRUE(renderer.render(camera, view).ok());
  LampFrame frame;
  frame.rgb = renderer.readPixels();
  const int w = renderer.width(), h = renderer.height();
  // The lamp quad is small on screen: a 5 x 5 box at its centre.
  const glm::ivec2 lamp = project(camera, w, h, nodeCentre(level.scene, "light"));
  const glm::ivec2 back = project(camera, w, h, nodeCentre(level.scene, "backwall"));
  // The lamp is 0.47 m wide: 0.45 m to its side is bare ceiling.
  const glm::ivec2 ceiling =
      project(camera, w, h, nodeCentre(level.scene, "light") + glm::vec3(0.45f, 0, 0));
  frame.lamp = boxMean(frame.rgb, w, h, lamp.x, lamp.y, 2);
  frame.ceiling = boxMean(frame.rgb, w, h, ceiling.x, ceiling.y, 2);
  frame.back_wall = boxMean(frame.rgb, w, h, back.x, back.y);
  return frame;
}

TEST(SceneRendererEmission, LampGoesDarkWhenItsBakeEmittersAreOff) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  const std::vector<uint32_t> lamp_emitters = patchEmitters(level.bake);
  ASSERT_FALSE(lamp_emitters.empty()) << "the Cornell bake has no emissive patch";
  SceneRendererSettings settings;  // 640 x 360
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  SceneRenderer& r = **renderer;

  const LampFrame on = renderLamp(r, level, ShadingView::kRuntime);
  EXPECT_GT(on.lamp.luminance(), 200.0) << "the lamp is not the brightest thing when on";

  for (uint32_t e : lamp_emitters) ASSERT_TRUE(r.setBakedEmitterScale(e, 0.0f).ok());
  const LampFrame off = renderLamp(r, level, ShadingView::kRuntime);
  std::printf(
      "lamp on %.1f, off %.1f; ceiling beside it %.1f; back wall %.1f (8-bit display luminance)\n",
      on.lamp.luminance(), off.lamp.luminance(), off.ceiling.luminance(),
      off.back_wall.luminance());
  ASSERT_TRUE(r.writePng(pngPath("svit_scene_renderer_lamp_off.png")).ok());
  // Off, the lamp only reflects what reaches it from below, as the ceiling
  // beside it does (without a runtime the lightmaps keep the lamp's light):
  // about as bright as that ceiling (the lamp's albedo and the lightmap's
  // texels differ a little: 25%), where on it saturates the display.
  EXPECT_GT(on.lamp.luminance(), on.ceiling.luminance() + 60.0);
  EXPECT_NEAR(off.lamp.luminance(), off.ceiling.luminance(), 0.25 * off.ceiling.luminance());
  EXPECT_LT(off.lamp.luminance(), off.back_wall.luminance());
  // Only the lamp changed: the back wall is drawn as before.
  EXPECT_NEAR(off.back_wall.luminance(), on.back_wall.luminance(), 0.5);

  // Half way: between off and on.
  for (uint32_t e : lamp_emitters) ASSERT_TRUE(r.setBakedEmitterScale(e, 0.5f).ok());
  const LampFrame half = renderLamp(r, level, ShadingView::kRuntime);
  EXPECT_GT(half.lamp.luminance(), off.lamp.luminance() + 10.0);
  EXPECT_LE(half.lamp.luminance(), on.lamp.luminance());

  // The patch-delta view draws the dimmed lamp under its false colour too.
  for (uint32_t e : lamp_emitters) ASSERT_TRUE(r.setBakedEmitterScale(e, 0.0f).ok());
  const LampFrame delta_off = renderLamp(r, level, ShadingView::kPatchDelta);
  for (uint32_t e : lamp_emitters) ASSERT_TRUE(r.setBakedEmitterScale(e, 1.0f).ok());
  const LampFrame delta_on = renderLamp(r, level, ShadingView::kPatchDelta);
  EXPECT_NEAR(delta_off.lamp.luminance(), delta_off.ceiling.luminance(),
              0.25 * delta_off.ceiling.luminance());
  EXPECT_GT(delta_on.lamp.luminance(), delta_on.ceiling.luminance() + 20.0);

  // Back to 1: the frame is the first one again, bit for bit.
  const LampFrame again = renderLamp(r, level, ShadingView::kRuntime);
  EXPECT_EQ(maxChannelDifference(again.rgb, on.rgb), 0);
}

TEST(SceneRendererEmission, BakedOnlyViewShowsTheLampAsBaked) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;
  settings.width = 320, settings.height = 180;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  SceneRenderer& r = **renderer;
  const LampFrame before = renderLamp(r, level, ShadingView::kBakedOnly);
  for (uint32_t e : patchEmitters(level.bake)) ASSERT_TRUE(r.setBakedEmitterScale(e, 0.0f).ok());
  const LampFrame after = renderLamp(r, level, ShadingView::kBakedOnly);
  EXPECT_EQ(maxChannelDifference(before.rgb, after.rgb), 0);
}

TEST(SceneRendererEmission, BadScalesAreRefusedAndChangeNothing) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;
  settings.width = 320, settings.height = 180;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  SceneRenderer& r = **renderer;
  const LampFrame before = renderLamp(r, level, ShadingView::kRuntime);
  const uint32_t count = uint32_t(level.bake.emitters.size());
  const uint32_t lamp = patchEmitters(level.bake).at(0);

  Status s = r.setBakedEmitterScale(count, 0.0f);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("no baked emitter " + std::to_string(count)), std::string::npos)
      << s.message();
  for (float bad : {-1.0f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
    s = r.setBakedEmitterScale(lamp, bad);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << bad;
    EXPECT_NE(s.message().find("scale " +
                               (std::isnan(bad) ? std::string("nan")
                                : bad < 0       ? "-1"
                                                : "inf") +
                               " must lie in [0, 1e+06]"),
              std::string::npos)
        << s.message();
  }
  const LampFrame after = renderLamp(r, level, ShadingView::kRuntime);
  EXPECT_EQ(maxChannelDifference(before.rgb, after.rgb), 0);
}

}  // namespace
}  // namespace svit

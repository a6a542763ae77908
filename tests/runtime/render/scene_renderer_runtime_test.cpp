// SceneRenderer with svit::Runtime: the runtime view at rest equals the
// baked view, a runtime light adds light and renders its shadow map once,
// the Cornell box's moving box is drawn and lit. Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

// Runtime lights switched off change nothing: the runtime view is the
// baked view (same shader path, zero deltas, no light) to the last bit of
// rounding; a light switched on brightens the frame near it and renders
// its shadow map once, not again while nothing moves.
TEST(SceneRendererRuntime, RuntimeViewAtRestEqualsBakedOnlyAndARuntimeLightAddsLight) {
  const BakedLevel& level = bakedLevel(cornellWithRuntimeLights());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(runtime.ok()) << runtime.status().message();
  const LightId light = (*runtime)->lightForSceneLight(0), spot = (*runtime)->lightForSceneLight(1);
  ASSERT_NE(light, kInvalidId);
  ASSERT_NE(spot, kInvalidId);
  ASSERT_TRUE((*runtime)->setLightEnabled(light, false).ok());
  ASSERT_TRUE((*runtime)->setLightEnabled(spot, false).ok());
  (*runtime)->update();
  SceneRendererSettings settings;
  settings.width = 320, settings.height = 180;
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(), settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Camera camera = cornellFrontCamera();
  ASSERT_TRUE((*renderer)->render(camera, ShadingView::kBakedOnly).ok());
  const std::vector<uint8_t> baked = (*renderer)->readPixels();
  ASSERT_TRUE((*renderer)->render(camera, ShadingView::kRuntime).ok());
  const std::vector<uint8_t> at_rest = (*renderer)->readPixels();
  EXPECT_LE(maxChannelDifference(baked, at_rest), 1);

  ASSERT_TRUE((*runtime)->setLightEnabled(light, true).ok());
  (*runtime)->update();
  Expected<RenderStats> first = (*renderer)->render(camera, ShadingView::kRuntime);
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_EQ(first->shadow_maps_rendered, 1u);
  ASSERT_TRUE((*renderer)->writePng(pngPath("svit_scene_renderer_cornell_runtime_light.png")).ok());
  const std::vector<uint8_t> lit = (*renderer)->readPixels();
  Expected<RenderStats> second = (*renderer)->render(camera, ShadingView::kRuntime);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->shadow_maps_rendered, 0u) << "nothing moved: the shadow map stays";
  // The back wall facing the lamp (0.33, 1.2, 0.38) is brighter.
  const glm::ivec2 p =
      project(camera, settings.width, settings.height, glm::vec3(0.33f, 1.2f, -1.0f));
  const Pixel before = boxMean(baked, settings.width, settings.height, p.x, p.y);
  const Pixel after = boxMean(lit, settings.width, settings.height, p.x, p.y);
  EXPECT_GT(after.luminance(), before.luminance() + 10.0);
}

// The Cornell level with its moving box: the runtime's deltas show in the
// runtime view (the box's shadow on the floor), the box is lit, and a
// frame where nothing moved renders no shadow map.
TEST(SceneRendererRuntime, CornellWithTheDynamicBox) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(runtime.ok()) << runtime.status().message();
  (*runtime)->update();
  SceneRendererSettings settings;
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(), settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Camera camera = cameraOf(level.scene);
  for (ShadingView view :
       {ShadingView::kBakedOnly, ShadingView::kRuntime, ShadingView::kPatchDelta}) {
    Expected<RenderStats> stats = (*renderer)->render(camera, view);
    ASSERT_TRUE(stats.ok()) << stats.status().message();
    const char* name = view == ShadingView::kBakedOnly ? "baked"
                       : view == ShadingView::kRuntime ? "runtime"
                                                       : "delta";
    const std::string png =
        pngPath(std::string("svit_scene_renderer_cornell_dynamic_") + name + ".png");
    ASSERT_TRUE((*renderer)->writePng(png).ok());
    std::printf("%s: %.2f ms, %u draw calls -> %s\n", name, stats->shading_ms, stats->draw_calls,
                png.c_str());
  }
  // The tall box in the runtime view is lit (not black) where it faces the camera.
  ASSERT_TRUE((*renderer)->render(camera, ShadingView::kRuntime).ok());
  const std::vector<uint8_t> rgb = (*renderer)->readPixels();
  const glm::ivec2 p =
      project(camera, settings.width, settings.height, nodeCentre(level.scene, "tallBox"));
  EXPECT_GT(boxMean(rgb, settings.width, settings.height, p.x, p.y).luminance(), 30.0);
}

}  // namespace
}  // namespace svit

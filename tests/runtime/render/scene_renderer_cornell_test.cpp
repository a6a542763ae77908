// What a frame of the baked Cornell box looks like: red left wall, green
// right wall, grey-white back wall, the lamp brightest, not black; the
// patch-delta view without a runtime shows no delta. The frame is written
// to the temp directory for a person to look at. Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

TEST(SceneRendererCornell, BakedOnlyLooksLikeTheCornellBox) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;  // 640 x 360
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Camera camera = cameraOf(level.scene);
  std::vector<double> ms;
  for (int frame = 0; frame < 5; ++frame) {
    Expected<RenderStats> stats = (*renderer)->render(camera, ShadingView::kBakedOnly);
    ASSERT_TRUE(stats.ok()) << stats.status().message();
    ms.push_back(stats->shading_ms);
  }
  std::sort(ms.begin(), ms.end());
  std::printf("Cornell kBakedOnly %dx%d: %.2f ms per frame (median of 5, llvmpipe)\n",
              settings.width, settings.height, ms[2]);
  const std::string png = pngPath("svit_scene_renderer_cornell_baked.png");
  ASSERT_TRUE((*renderer)->writePng(png).ok());
  std::printf("frame: %s\n", png.c_str());

  const int w = (*renderer)->width(), h = (*renderer)->height();
  const std::vector<uint8_t> rgb = (*renderer)->readPixels();
  ASSERT_EQ(rgb.size(), size_t(w) * size_t(h) * 3);
  // Not black, not blown out. The camera sees past the box's open front on
  // both sides (about 35% of the width, black: nothing is there).
  double mean = 0;
  size_t dark = 0;
  for (size_t i = 0; i < rgb.size(); i += 3) {
    const double y = 0.2126 * rgb[i] + 0.7152 * rgb[i + 1] + 0.0722 * rgb[i + 2];
    mean += y;
    dark += y < 8 ? 1 : 0;
  }
  mean /= double(rgb.size() / 3);
  EXPECT_GT(mean, 40.0);
  EXPECT_LT(mean, 220.0);
  EXPECT_LT(double(dark) / double(rgb.size() / 3), 0.40);

  auto at = [&](const std::string& node, glm::vec3 nudge = glm::vec3(0)) {
    const glm::ivec2 p = project(camera, w, h, nodeCentre(level.scene, node) + nudge);
    return boxMean(rgb, w, h, p.x, p.y);
  };
  const Pixel left = at("leftWall"), right = at("rightwall"), back = at("backwall"),
              floor = at("floor");
  const Pixel lamp = at("light");
  EXPECT_GT(left.r, 1.5 * left.g) << "left wall not red";
  EXPECT_GT(left.r, 1.5 * left.b) << "left wall not red";
  EXPECT_GT(right.g, 1.3 * right.r) << "right wall not green";
  EXPECT_GT(right.g, 1.3 * right.b) << "right wall not green";
  EXPECT_NEAR(back.r, back.g, 0.25 * back.g) << "back wall not grey-white";
  for (const Pixel& other : {left, right, back, floor})
    EXPECT_GT(lamp.luminance(), other.luminance());
  EXPECT_GT(lamp.luminance(), 200.0);
}

TEST(SceneRendererCornell, PatchDeltaViewWithoutRuntimeShowsNoDelta) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;
  settings.width = 160, settings.height = 90;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  ASSERT_TRUE((*renderer)->render(cornellFrontCamera(), ShadingView::kPatchDelta).ok());
  const std::vector<uint8_t> rgb = (*renderer)->readPixels();
  // Zero delta = the dimmed grey of the frame: no pixel takes a hue.
  for (size_t i = 0; i < rgb.size(); i += 3) {
    ASSERT_LE(
        std::max({rgb[i], rgb[i + 1], rgb[i + 2]}) - std::min({rgb[i], rgb[i + 1], rgb[i + 2]}), 1)
        << "pixel " << i / 3;
  }
}

}  // namespace
}  // namespace svit

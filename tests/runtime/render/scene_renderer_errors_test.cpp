// SceneRenderer errors: no GL context, a missing lightmap page, a bake of
// other geometry, a back lightmap of a one-sided triangle, settings out of
// range, PNG output without a frame or to a path that cannot be written.
// Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

TEST(SceneRenderer, CreateWithoutContextIsAnError) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr);
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(renderer.status().message().find("no current OpenGL context"), std::string::npos)
      << renderer.status().message();
}

TEST(SceneRenderer, MissingLightmapPageNamesTheFile) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  const fs::path dir = fs::temp_directory_path() /
                       ("svit_scene_renderer_missing_page_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(level.dir + "/bake.svit", dir / "bake.svit", fs::copy_options::overwrite_existing);
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, level.bake, dir.string(), nullptr);
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.status().code(), StatusCode::kNotFound);
  EXPECT_NE(renderer.status().message().find(level.bake.pages.at(0).file), std::string::npos)
      << renderer.status().message();
  fs::remove_all(dir);
}

TEST(SceneRenderer, BakeOfOtherGeometryIsAnError) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  BakeData bake = level.bake;
  bake.triangle_uvs.pop_back();
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, bake, level.dir, nullptr);
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(renderer.status().message().find("static triangles"), std::string::npos)
      << renderer.status().message();
  EXPECT_NE(renderer.status().message().find("bake.svit"), std::string::npos)
      << renderer.status().message();
}

TEST(SceneRenderer, BackLightmapOfAOneSidedTriangleIsAnError) {
  const BakedLevel& level = bakedLevel(cornellLevel());  // no double-sided triangle
  BakeData bake = level.bake;
  ASSERT_TRUE(bake.back_uvs.empty());
  bake.back_uvs.push_back({5, 0, {{0.1f, 0.1f}, {0.2f, 0.1f}, {0.1f, 0.2f}}});
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, bake, level.dir, nullptr);
  ASSERT_FALSE(renderer.ok());
  EXPECT_EQ(renderer.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(renderer.status().message().find("bake triangle 5: has a back lightmap"),
            std::string::npos)
      << renderer.status().message();
}

TEST(SceneRenderer, SettingsOutOfRangeAreNamed) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;
  settings.shadow_taps = 0;
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_FALSE(renderer.ok());
  EXPECT_NE(renderer.status().message().find("shadow_taps"), std::string::npos)
      << renderer.status().message();
}

TEST(SceneRenderer, WritePngBeforeAnyFrameOrToABadPathIsAnError) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  SceneRendererSettings settings;
  settings.width = 64, settings.height = 36;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  EXPECT_FALSE((*renderer)->writePng(pngPath("svit_never_written.png")).ok());
  EXPECT_TRUE((*renderer)->readPixels().empty());
  ASSERT_TRUE((*renderer)->render(cornellFrontCamera(), ShadingView::kBakedOnly).ok());
  const std::string bad = "/nonexistent-dir/frame.png";
  Status status = (*renderer)->writePng(bad);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find(bad), std::string::npos) << status.message();
}

}  // namespace
}  // namespace svit

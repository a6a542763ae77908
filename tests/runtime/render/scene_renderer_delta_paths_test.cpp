// The two ways a host shades the runtime's static deltas draw the same
// picture: the per-pixel lookup of runtime-patch deltas
// (svit_runtime_delta.frag, ShadingResources::vertex_deltas) and the
// lightmap-space delta pages (ShadingResources::delta_textures), on the
// Cornell box, whose runtime patches cut its bake patches into pieces (the
// per-vertex path this replaced indexed runtime-patch deltas by bake patch
// and drew blotches). Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "runtime/cornell_probes.h"
#include "runtime/gl_test_context.h"
#include "runtime/picture_comparison_png.h"
#include "runtime/picture_metric.h"
#include "scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

test::LinearFrame settledRuntimePicture(const BakedLevel& level, bool delta_textures,
                                        ShadingView view) {
  RuntimeSettings settings;
  settings.delta_textures = delta_textures;
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  EXPECT_TRUE(runtime.ok()) << runtime.status().message();
  if (!runtime.ok()) return {};
  // The tall box where the level's path takes it at 3 s (25 cm, 30 degrees):
  // its shadow and reflected light on the floor and walls.
  const Mat4 moved = test::placeAt({0.25f, 0, 0.1f}, {0, 0.2588190f, 0, 0.9659258f});
  EXPECT_TRUE((*runtime)->setObjectTransform((*runtime)->objects().at(0), moved).ok());
  (*runtime)->update(0);
  EXPECT_EQ((*runtime)->shadingResources().delta_textures.empty(), !delta_textures);
  SceneRendererSettings rs;
  rs.width = 320;
  rs.height = 180;
  rs.auto_exposure = false;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(), rs);
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return {};
  EXPECT_TRUE((*renderer)->render(cornellFrontCamera(), view).ok());
  return test::readLinearFrame(**renderer);
}

TEST(SceneRendererDeltaPaths, PerPixelLookupAndLightmapSpacePagesDrawTheSamePicture) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  ASSERT_FALSE(level.bake.patches.empty());
  const test::LinearFrame per_pixel = settledRuntimePicture(level, false, ShadingView::kRuntime);
  const test::LinearFrame pages = settledRuntimePicture(level, true, ShadingView::kRuntime);
  const test::LinearFrame baked = settledRuntimePicture(level, false, ShadingView::kBakedOnly);
  const test::PictureError paths = test::comparePictures(per_pixel, pages);
  const test::PictureError delta = test::comparePictures(per_pixel, baked);
  std::printf(
      "per-pixel against lightmap-space pages: %.4f of the mean; the deltas themselves: %.4f\n",
      paths.static_rel_rms, delta.static_rel_rms);
  EXPECT_TRUE(test::writeComparisonPng(pngPath("svit_delta_paths.png"), per_pixel, pages, 1).ok());
  ASSERT_GT(paths.static_pixels, 10000u);
  // The deltas are large (a moved box's shadow and light), and the two
  // paths agree to a small part of them: the pages are at half the
  // lightmap's resolution, bilinear, so chart edges differ a little.
  EXPECT_GT(delta.static_rel_rms, 0.05);
  EXPECT_LT(paths.static_rel_rms, 0.1 * delta.static_rel_rms);
}

}  // namespace
}  // namespace svit

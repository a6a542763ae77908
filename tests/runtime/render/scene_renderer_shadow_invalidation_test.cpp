// Shadow maps re-rendered only for the lights that see where a dynamic
// object moved from or to (LightShadowMaps' occlusion test), and a frame
// that skipped a map equals one from a renderer that rendered them all.
// Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

// A frame from a renderer made now, which renders every map.
std::vector<uint8_t> freshFrame(const BakedLevel& level, const Runtime& runtime,
                                const SceneRendererSettings& settings, const Camera& camera) {
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, &runtime, settings);
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return {};
  Expected<RenderStats> stats = (*renderer)->render(camera, ShadingView::kRuntime);
  EXPECT_TRUE(stats.ok());
  EXPECT_EQ(stats->shadow_maps_rendered, 2u);
  return (*renderer)->readPixels();
}

TEST(SceneRendererShadowInvalidation, OnlyLightsThatSeeTheMoveRenderAgain) {
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  // Without shadow masks: the ceiling lamp's caster maps (one per point
  // sample, all seeing every move) would hide the runtime lights' counts.
  TestBake unmasked;
  unmasked.shadow_masks = false;
  const BakedLevel& level = bakedLevel(cornellWithRuntimeLights("tallBox"), unmasked);
  ASSERT_TRUE(level.bake.has_runtime_sections);
  auto created = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  const ObjectId box = runtime.objectForNode(level.scene.findNode("tallBox"));
  ASSERT_NE(box, kInvalidId);
  const Mat4 rest = runtime.objectInfo(box)->world_from_object;

  SceneRendererSettings settings;
  settings.width = 160, settings.height = 90;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, &runtime, settings);
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Camera camera = cornellFrontCamera();
  auto frame = [&] {
    Expected<RenderStats> stats = (*renderer)->render(camera, ShadingView::kRuntime);
    EXPECT_TRUE(stats.ok());
    return stats.ok() ? stats->shadow_maps_rendered : 99u;
  };
  EXPECT_EQ(frame(), 2u) << "first frame: the lamp's cube and the spot's face";
  EXPECT_EQ(frame(), 0u) << "nothing moved";

  // 5 cm to the left: the lamp sees the box, the spot's cone does not.
  Mat4 moved = rest;
  moved.m[12] -= 0.05f;
  ASSERT_TRUE(runtime.setObjectTransform(box, moved).ok());
  EXPECT_EQ(frame(), 1u) << "only the lamp's map sees the move";
  EXPECT_EQ((*renderer)->readPixels(), freshFrame(level, runtime, settings, camera))
      << "the kept spot map is the one a full re-render makes";

  // Into the spot's cone at the back right: both maps must follow.
  Mat4 into_cone = rest;
  into_cone.m[12] += 0.75f, into_cone.m[13] += 0.4f, into_cone.m[14] -= 0.35f;
  ASSERT_TRUE(runtime.setObjectTransform(box, into_cone).ok());
  EXPECT_EQ(frame(), 2u) << "the box entered the spot's view";
  EXPECT_EQ((*renderer)->readPixels(), freshFrame(level, runtime, settings, camera));
  // And out again: the spot's map sees where it was.
  ASSERT_TRUE(runtime.setObjectTransform(box, moved).ok());
  EXPECT_EQ(frame(), 2u);
  EXPECT_EQ((*renderer)->readPixels(), freshFrame(level, runtime, settings, camera));
}

}  // namespace
}  // namespace svit

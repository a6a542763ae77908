// Per-pixel runtime lights with depth shadow maps, on the level's own
// runtime lights (no svit::Runtime: the renderer shades them where the
// level puts them): a point light's cube map shadows the floor behind the
// short box, a narrow spot (one face) lights inside its cone only, maps are
// rendered once and kept while nothing moves. Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

struct Frames {
  std::vector<uint8_t> baked, lit;
  int width = 0, height = 0;
  Camera camera;
  // Luminance the runtime lights add at world point p (8-bit display units).
  double gain(const glm::vec3& p) const {
    const glm::ivec2 q = project(camera, width, height, p);
    return boxMean(lit, width, height, q.x, q.y, 2).luminance() -
           boxMean(baked, width, height, q.x, q.y, 2).luminance();
  }
};

Frames renderBothViews(const Camera& camera, const std::string& png_name, RenderStats* first,
                       RenderStats* second) {
  const BakedLevel& level = bakedLevel(cornellWithRuntimeLights());
  Frames frames;
  frames.camera = camera;
  test::GlTestContext context;
  EXPECT_TRUE(context.ok());
  if (!context.ok()) return frames;
  SceneRendererSettings settings;
  settings.width = 320, settings.height = 180;
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, settings);
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return frames;
  frames.width = settings.width, frames.height = settings.height;
  EXPECT_TRUE((*renderer)->render(camera, ShadingView::kBakedOnly).ok());
  frames.baked = (*renderer)->readPixels();
  Expected<RenderStats> a = (*renderer)->render(camera, ShadingView::kRuntime);
  Expected<RenderStats> b = (*renderer)->render(camera, ShadingView::kRuntime);
  EXPECT_TRUE(a.ok() && b.ok());
  if (a.ok()) *first = *a;
  if (b.ok()) *second = *b;
  frames.lit = (*renderer)->readPixels();
  EXPECT_TRUE((*renderer)->writePng(pngPath(png_name)).ok());
  return frames;
}

TEST(SceneRendererLights, PointLightShadowsTheFloorBehindTheShortBox) {
  Camera camera;  // above the open front, looking down at the short box
  camera.position = {0, 1.6f, 2.6f};
  camera.look_at = {0, 0.3f, 0};
  camera.yfov_rad = 0.8f;
  RenderStats first, second;
  const Frames f = renderBothViews(camera, "svit_scene_renderer_point_shadow.png", &first, &second);
  ASSERT_FALSE(f.lit.empty());
  EXPECT_EQ(first.shadow_maps_rendered, 2u);  // the point's cube and the spot's face
  EXPECT_EQ(second.shadow_maps_rendered, 0u) << "nothing moved: the maps stay";
  // The lamp hangs 0.6 m above the short box's top (y 0.6) at its centre.
  // Floor 0.44 m in front of the centre: the box's edge (<= 0.38 m out)
  // hides the lamp (the ray passes the edge below 0.2 m).
  const double shadowed = f.gain({0.33f, 0.0f, 0.82f});
  // Floor 1 m to the side, clear of both boxes: the ray passes the edge at
  // ~0.74 m, above the box.
  const double lit = f.gain({-0.67f, 0.0f, 0.38f});
  EXPECT_LT(shadowed, 3.0);
  EXPECT_GT(lit, 10.0);
}

TEST(SceneRendererLights, SpotLightsInsideItsConeOnly) {
  RenderStats first, second;
  const Frames f =
      renderBothViews(cornellFrontCamera(), "svit_scene_renderer_spot.png", &first, &second);
  ASSERT_FALSE(f.lit.empty());
  // The spot (5 cd, 1.04 m from the back wall) gives ~4.6 lux inside its
  // cone; the point lamp adds < 1 lux on both points below.
  const double inside = f.gain({0.5f, 1.5f, -1.03f});
  const double outside = f.gain({-0.5f, 1.5f, -1.03f});
  EXPECT_GT(inside, outside + 20.0);
}

}  // namespace
}  // namespace svit

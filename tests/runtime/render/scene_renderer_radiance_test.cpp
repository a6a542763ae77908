// SceneRenderer's linear radiance (attachment 1 of the offscreen target):
// svitDisplay() of it, done again here in C++, is the frame's 8-bit pixels;
// it does not depend on the exposure; a HUD drawn after render() leaves it
// alone; a frame into the default framebuffer keeps the previous one; and
// writeExr() round-trips through tinyexr's LoadEXR. Label `gl` (xvfb-run).

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "runtime/gl_test_context.h"
#include "scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers

constexpr int kWidth = 160, kHeight = 90;

// shaders/svit_shading.frag's svitDisplay(), in the same order of
// operations: exposure, the Narkowicz (2015) ACES fit, the sRGB curve.
double srgbEncode(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

double display(float radiance, float exposure) {
  const double x = std::max(double(radiance), 0.0) * double(exposure);
  const double curve =
      std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  return srgbEncode(curve);
}

SceneRendererSettings fixedExposure(float exposure) {
  SceneRendererSettings settings;
  settings.width = kWidth, settings.height = kHeight;
  settings.exposure = exposure;
  settings.auto_exposure = false;
  return settings;
}

struct Frame {
  std::vector<uint8_t> pixels;
  std::vector<float> radiance;
};

Frame renderFrame(SceneRenderer& renderer, const Camera& camera, ShadingView view) {
  Expected<RenderStats> stats = renderer.render(camera, view);
  EXPECT_TRUE(stats.ok()) << stats.status().message();
  return {renderer.readPixels(), renderer.readRadiance()};
}

// The worst |255 display(radiance) - pixel| over every channel, and how
// many channels lie strictly inside (0, 255) (so the check is not of black
// or saturated pixels only).
struct DisplayMatch {
  double worst = 0;
  size_t mid_tones = 0;
};

DisplayMatch matchDisplay(const Frame& frame, float exposure) {
  DisplayMatch out;
  for (size_t i = 0; i < frame.pixels.size(); ++i) {
    const double expected = 255.0 * display(frame.radiance[i], exposure);
    out.worst = std::max(out.worst, std::abs(expected - double(frame.pixels[i])));
    if (frame.pixels[i] > 0 && frame.pixels[i] < 255) ++out.mid_tones;
  }
  return out;
}

// The static pass (lit_static.frag) and the moving box (lit_dynamic.frag,
// drawn with the runtime), in the baked and the runtime view, at two
// exposures: every channel of every pixel is svitDisplay of the radiance.
// Tolerance: the UNORM8 store rounds (0.5 of a step) and the GPU's pow/
// division differ from double by far less than one more step: 1.5 steps.
TEST(SceneRendererRadiance, DisplayOfTheRadianceIsThePixels) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(runtime.ok()) << runtime.status().message();
  (*runtime)->update();
  for (float exposure : {1.0f, 4.0f}) {
    auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(),
                                          fixedExposure(exposure));
    ASSERT_TRUE(renderer.ok()) << renderer.status().message();
    for (ShadingView view : {ShadingView::kBakedOnly, ShadingView::kRuntime}) {
      const Frame frame = renderFrame(**renderer, cameraOf(level.scene), view);
      ASSERT_EQ(frame.pixels.size(), size_t(kWidth) * kHeight * 3);
      ASSERT_EQ(frame.radiance.size(), frame.pixels.size());
      const DisplayMatch match = matchDisplay(frame, exposure);
      std::printf(
          "exposure %g, view %d: worst %.3f of an 8-bit step, %zu of %zu channels mid-tone\n",
          exposure, int(view), match.worst, match.mid_tones, frame.pixels.size());
      EXPECT_LE(match.worst, 1.5) << "exposure " << exposure << ", view " << int(view);
      EXPECT_GT(match.mid_tones, frame.pixels.size() / 2)
          << "exposure " << exposure << ": mostly black or saturated";
    }
  }
}

// The patch-delta view stores its false colour itself as "radiance"
// (scene_renderer.h): the pixels are it, rounded to 8 bits (0.5 of a step,
// plus float slack).
TEST(SceneRendererRadiance, PatchDeltaViewStoresItsFalseColour) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(runtime.ok()) << runtime.status().message();
  (*runtime)->update();
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(),
                                        fixedExposure(1.0f));
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Frame frame = renderFrame(**renderer, cameraOf(level.scene), ShadingView::kPatchDelta);
  ASSERT_EQ(frame.radiance.size(), frame.pixels.size());
  double worst = 0;
  for (size_t i = 0; i < frame.pixels.size(); ++i) {
    worst = std::max(worst, std::abs(255.0 * double(frame.radiance[i]) - double(frame.pixels[i])));
  }
  EXPECT_LE(worst, 0.51);
}

// Exposure is a display setting: the float radiance is the same to the
// bit at exposure 1 and 4 (the same shader, only u_exposure differs),
// while most 8-bit pixels that are not black change.
TEST(SceneRendererRadiance, RadianceDoesNotDependOnExposure) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  auto dim =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure(1.0f));
  auto bright =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure(4.0f));
  ASSERT_TRUE(dim.ok()) << dim.status().message();
  ASSERT_TRUE(bright.ok()) << bright.status().message();
  const Frame a = renderFrame(**dim, cornellFrontCamera(), ShadingView::kBakedOnly);
  const Frame b = renderFrame(**bright, cornellFrontCamera(), ShadingView::kBakedOnly);
  ASSERT_EQ(a.radiance.size(), size_t(kWidth) * kHeight * 3);
  EXPECT_TRUE(a.radiance == b.radiance) << "the radiance changed with the exposure";
  size_t lit = 0, changed = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    if (a.pixels[i] == 0) continue;
    ++lit;
    if (a.pixels[i] != b.pixels[i]) ++changed;
  }
  EXPECT_GT(lit, a.pixels.size() / 2);
  EXPECT_GT(changed, lit * 9 / 10) << "exposure 4 left most pixels as exposure 1 drew them";
}

// render() leaves the target drawing to attachment 0 only: a host's clear
// (a HUD) after it turns the display colour white, the radiance stays.
TEST(SceneRendererRadiance, HostDrawingAfterRenderLeavesTheRadiance) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure(1.0f));
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Frame frame = renderFrame(**renderer, cornellFrontCamera(), ShadingView::kBakedOnly);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (*renderer)->offscreenFramebuffer());
  glClearColor(1, 1, 1, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  const std::vector<uint8_t> hud = (*renderer)->readPixels();
  EXPECT_TRUE(std::all_of(hud.begin(), hud.end(), [](uint8_t v) { return v == 255; }))
      << "the clear did not reach";
  EXPECT_TRUE((*renderer)->readRadiance() == frame.radiance)
      << "the host's clear reached the radiance";
}

// No frame: nothing to read or write. A frame into the default framebuffer
// (no radiance attachment) keeps the previous offscreen frame's radiance.
TEST(SceneRendererRadiance, DefaultFramebufferFramesKeepThePreviousRadiance) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context(kWidth, kHeight);
  SVIT_REQUIRE_GL(context);
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure(1.0f));
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  EXPECT_TRUE((*renderer)->readRadiance().empty());
  const std::string never = pngPath("svit_radiance_never_written.exr");
  const Status before = (*renderer)->writeExr(never);
  ASSERT_FALSE(before.ok());
  EXPECT_NE(before.message().find(never), std::string::npos) << before.message();
  EXPECT_FALSE(fs::exists(never));

  const Frame offscreen = renderFrame(**renderer, cornellFrontCamera(), ShadingView::kBakedOnly);
  Camera elsewhere = cornellFrontCamera();
  elsewhere.look_at = {0.5f, 0.3f, 0};
  ASSERT_TRUE((*renderer)
                  ->render(elsewhere, ShadingView::kBakedOnly, /*to_default_framebuffer=*/true)
                  .ok());
  EXPECT_TRUE((*renderer)->readRadiance() == offscreen.radiance);
}

// writeExr: fp32 R, G, B that LoadEXR reads back as the same floats (alpha
// 1), rows top first; nothing left beside it. A missing directory is an
// error naming the path, and writes nothing.
TEST(SceneRendererRadiance, WriteExrRoundTripsThroughLoadExr) {
  const BakedLevel& level = bakedLevel(cornellLevel());
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure(1.0f));
  ASSERT_TRUE(renderer.ok()) << renderer.status().message();
  const Frame frame = renderFrame(**renderer, cornellFrontCamera(), ShadingView::kBakedOnly);
  const fs::path dir =
      fs::temp_directory_path() / ("svit_radiance_exr_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "frame.exr").string();
  const Status written = (*renderer)->writeExr(path);
  ASSERT_TRUE(written.ok()) << written.message();
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  float* rgba = nullptr;
  int width = 0, height = 0;
  const char* error = nullptr;
  const int loaded = LoadEXR(&rgba, &width, &height, path.c_str(), &error);
  ASSERT_EQ(loaded, TINYEXR_SUCCESS) << (error != nullptr ? error : "");
  ASSERT_EQ(width, kWidth);
  ASSERT_EQ(height, kHeight);
  size_t mismatches = 0;
  for (size_t p = 0; p < size_t(width) * size_t(height); ++p) {
    for (size_t c = 0; c < 3; ++c)
      mismatches += rgba[p * 4 + c] != frame.radiance[p * 3 + c] ? 1 : 0;
  }
  std::free(rgba);
  EXPECT_EQ(mismatches, 0u);

  const std::string missing = (dir / "missing" / "frame.exr").string();
  const Status refused = (*renderer)->writeExr(missing);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find(missing), std::string::npos) << refused.message();
  EXPECT_FALSE(fs::exists(dir / "missing"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace svit

// Eight baked point lamps whose light overlaps on the Cornell box's floor,
// all masked (issue 21: no cap of 4 shadowed lights per texel), each
// switched off in turn at run time: the picture is the bake of the level
// without that lamp, per pixel. Label `gl` (xvfb-run).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "runtime/gl_test_context.h"
#include "runtime/picture_comparison_png.h"
#include "runtime/picture_metric.h"
#include "runtime/picture_views.h"
#include "scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit {
namespace {

using namespace svit::render_test;  // NOLINT: test helpers
using test::comparePictures;
using test::LinearFrame;
using test::readLinearFrame;

constexpr int kLamps = 8;
constexpr TestBake kRuntimeBake{1, 1, 3};
constexpr TestBake kReferenceBake{2, 1, 3};

// The Cornell box with the eight point lamps 1.5 m over the floor (above
// the tall box) on a 4 x 2 grid (0.3 cd each: together about the ceiling
// lamp's light on the floor), lamp `left_out` left out (-1: none); the tall box dynamic (the
// runtime's level: a level with dynamic objects is masked) or static where
// it stands (the references).
std::string eightLampsLevel(int left_out, bool box_dynamic) {
  std::string lights;
  for (int i = 0; i < kLamps; ++i) {
    if (i == left_out) continue;
    const double x = -0.6 + 0.4 * (i % 4), z = -0.4 + 0.8 * (i / 4);
    if (!lights.empty()) lights += ", ";
    lights += R"({"name": "lamp)" + std::to_string(i) +
              R"(", "type": "point", "color": [1, 1, 1], "intensity_cd": 0.3, "position": [)" +
              std::to_string(x) + ", 1.5, " + std::to_string(z) + "]}";
  }
  return writeLevel("cornell_eight_lamps" + std::string(box_dynamic ? "_box" : "") +
                        (left_out < 0 ? "" : "_but_" + std::to_string(left_out)),
                    R"({"gltf": ")" + cornellGltf() + R"(", )" +
                        (box_dynamic ? R"("dynamic": ["tallBox"], )" : "") + R"("lights": [)" +
                        lights + "]}");
}

// The bake emitter of the level's light `light` (Scene::lights index).
uint32_t lightEmitter(const BakeData& bake, uint32_t light) {
  for (uint32_t e = 0; e < bake.emitters.size(); ++e) {
    const BakeEmitter& emitter = bake.emitters[e];
    if (emitter.kind == BakeEmitter::Kind::kLight && emitter.index == light) return e;
  }
  return kInvalidId;
}

bool isMasked(const BakeData& bake, uint32_t emitter) {
  return std::any_of(bake.masks.lights.begin(), bake.masks.lights.end(),
                     [&](const BakeMaskedLight& m) { return m.emitter == emitter; });
}

// The runtime's picture with the baked emitter `emitter` at `scale`.
LinearFrame frameWithScale(Viewer& v, uint32_t emitter, float scale, const Camera& camera) {
  EXPECT_TRUE(v.runtime->setBakedEmitterScale(emitter, scale).ok());
  EXPECT_TRUE(v.renderer->setBakedEmitterScale(emitter, scale).ok());
  const FrameStats stats = v.runtime->update(0);
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  EXPECT_TRUE(v.renderer->render(camera, ShadingView::kRuntime).ok());
  return readLinearFrame(*v.renderer);
}

// Each lamp off: its direct light goes per pixel (its mask channel is its
// own, so no other lamp's light goes with it) and its bounce as the
// runtime's patch deltas take it. Against the bake without that lamp, the
// picture is within the noise floor (the runtime's bake against a bake of
// another seed, all lamps on; sqrt 2 for both being noisy), where leaving
// the lamp on would be at least twice the floor.
TEST(MaskedLamps, EightOverlappingLampsEachSwitchedOffMatchTheBakeWithoutIt) {
  test::GlTestContext context;
  SVIT_REQUIRE_GL(context);
  const Camera camera = cornellFrontCamera();
  const BakedLevel& level = bakedLevel(eightLampsLevel(-1, true), kRuntimeBake);
  ASSERT_GE(level.bake.masks.channels, uint32_t(kLamps));
  Viewer v = makeViewer(level, 0);
  ASSERT_TRUE(v.renderer);
  const LinearFrame all_on = frameWithScale(v, lightEmitter(level.bake, 0), 1, camera);
  const double noise =
      comparePictures(all_on,
                      bakedPicture(bakedLevel(eightLampsLevel(-1, false), kReferenceBake), camera))
          .static_rel_rms;
  std::printf("all eight on against a bake of another seed (noise floor): %.4f\n", noise);
  for (int lamp = 0; lamp < kLamps; ++lamp) {
    const uint32_t emitter = lightEmitter(level.bake, uint32_t(lamp));
    ASSERT_NE(emitter, kInvalidId);
    ASSERT_TRUE(isMasked(level.bake, emitter)) << "lamp " << lamp;
    const LinearFrame without =
        bakedPicture(bakedLevel(eightLampsLevel(lamp, false), kReferenceBake), camera);
    const LinearFrame off = frameWithScale(v, emitter, 0, camera);
    const double error = comparePictures(off, without).static_rel_rms;
    const double left_on = comparePictures(all_on, without).static_rel_rms;
    std::printf("lamp %d off against the bake without it: %.4f (left on: %.4f)\n", lamp, error,
                left_on);
    EXPECT_TRUE(test::writeComparisonPng(
                    pngPath("svit_picture_eight_lamps_off_" + std::to_string(lamp) + ".png"), off,
                    without, 1)
                    .ok());
    EXPECT_GE(left_on, 2 * noise) << "lamp " << lamp;
    EXPECT_LE(error, std::sqrt(2.0) * noise) << "lamp " << lamp;
    frameWithScale(v, emitter, 1, camera);
  }
}

}  // namespace
}  // namespace svit

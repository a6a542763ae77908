// What the API abuse driver found, one test each, so that every finding
// stays fixed: each call was taken (or silently ignored) before, and
// overflowed the deltas or the frame to infinity, counted a frame, or gave a
// message that did not say which argument was wrong. Each is now refused
// with an error naming the argument and its value, and changes nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "runtime_abuse_driver.h"

namespace svit {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

DynamicMesh crate() {
  DynamicMesh mesh;
  mesh.name = "crate";
  mesh.positions = {{-0.1f, 0, -0.1f}, {0.1f, 0, -0.1f}, {0, 0.2f, 0.1f}, {0, 0, 0.1f}};
  mesh.indices = {0, 2, 1, 0, 3, 2, 1, 2, 3, 0, 1, 3};
  return mesh;
}

Mat4 at(float x, float y, float z) {
  Mat4 m;
  m.m[12] = x, m.m[13] = y, m.m[14] = z;
  return m;
}

void expectRefused(const Status& status, const std::string& names) {
  EXPECT_FALSE(status.ok()) << "accepted; expected an error naming '" << names << "'";
  EXPECT_NE(status.message().find(names), std::string::npos)
      << "'" << status.message() << "' does not name '" << names << "'";
}

class RuntimeAbuseFindings : public ::testing::Test {
 protected:
  void SetUp() override {
    SVIT_REQUIRE_GL(gl_);
    const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
    Expected<abuse::Twin> twin = abuse::makeTwin(level.scene, level.bake, level.dir);
    ASSERT_TRUE(twin.ok()) << twin.status().message();
    twin_ = std::move(twin).value();
    Expected<ObjectId> id = runtime().addObject(crate(), at(0, 0.5f, 0));
    ASSERT_TRUE(id.ok()) << id.status().message();
    crate_ = *id;
    Light lamp;
    lamp.position = {0, 1, 0};
    lamp.intensity = 5;
    Expected<LightId> light = runtime().addLight(lamp);
    ASSERT_TRUE(light.ok()) << light.status().message();
    lamp_ = *light;
    settled_ = settle();
  }
  Runtime& runtime() { return *twin_.runtime; }
  // Updates until idle and returns the deltas: what "nothing changed" is
  // measured against (a refused call must leave the next update idle).
  std::vector<Rgb> settle() {
    for (int i = 0; i < 16 && !runtime().update(0).idle; ++i) {}
    return runtime().patchDeltas();
  }
  void expectUnchanged() {
    const FrameStats next = runtime().update(0);
    EXPECT_TRUE(next.idle) << "a refused call left work for the next update";
    EXPECT_EQ(runtime().patchDeltas().size(), settled_.size());
    for (size_t p = 0; p < settled_.size(); ++p) {
      ASSERT_EQ(runtime().patchDeltas()[p].r, settled_[p].r) << "patch " << p;
    }
  }
  test::GlTestContext gl_;
  abuse::Twin twin_;
  ObjectId crate_ = kInvalidId;
  LightId lamp_ = kInvalidId;
  std::vector<Rgb> settled_;
};

TEST_F(RuntimeAbuseFindings, UpdateBudgetNegativeOrNaNIsRefusedAndCountsNoFrame) {
  const uint64_t before = runtime().emitterStates().front().refreshed_frame;
  for (double budget : {-1.0, double(kNaN), -double(kInf)}) {
    const FrameStats stats = runtime().update(budget);
    EXPECT_NE(stats.error.find("budget_ms"), std::string::npos) << stats.error;
    EXPECT_FALSE(stats.idle);
  }
  EXPECT_EQ(runtime().emitterStates().front().refreshed_frame, before);
  EXPECT_TRUE(runtime().update(double(kInf)).error.empty()) << "infinity: no limit";
  expectUnchanged();
}

TEST_F(RuntimeAbuseFindings, PlacementsBeyondTheWorldAreRefused) {
  Mat4 far = at(1e30f, 0, 0);
  expectRefused(runtime().setObjectTransform(crate_, far), "beyond");
  Mat4 blown_up = at(0, 0.5f, 0);
  blown_up.m[0] = blown_up.m[5] = blown_up.m[10] = 1e20f;
  expectRefused(runtime().setObjectTransform(crate_, blown_up), "beyond");
  expectRefused(runtime().addObject(crate(), far).status(), "beyond");
  std::vector<Vec3> huge(runtime().objectInfo(crate_)->world_positions.size(), Vec3{1e30f, 0, 0});
  expectRefused(runtime().deformObject(crate_, huge), "beyond");
  Light lamp = runtime().lightInfo(lamp_)->light;
  lamp.position.x = 1e30f;
  expectRefused(runtime().setLight(lamp_, lamp), "beyond");
  expectUnchanged();
}

TEST_F(RuntimeAbuseFindings, TransformsThatAreNotPlacementsAreRefused) {
  Mat4 projective = at(0, 0.5f, 0);
  projective.m[3] = 0.5f;
  expectRefused(runtime().setObjectTransform(crate_, projective), "affine");
  Mat4 nan = at(0, 0.5f, 0);
  nan.m[13] = kNaN;
  expectRefused(runtime().setObjectTransform(crate_, nan), "m[13] = nan");
  expectUnchanged();
}

TEST_F(RuntimeAbuseFindings, OverflowingLightValuesAreRefusedNamingTheValue) {
  Light lamp = runtime().lightInfo(lamp_)->light;
  lamp.intensity = 3e38f;
  expectRefused(runtime().setLight(lamp_, lamp), "intensity x colour 3e+38");
  lamp.intensity = kInf;
  expectRefused(runtime().setLight(lamp_, lamp), "intensity inf");
  lamp.intensity = 5;
  lamp.position.y = kNaN;
  expectRefused(runtime().setLight(lamp_, lamp), "position (0, nan, 0)");
  expectRefused(runtime().setLightDimmer(lamp_, 3e38f), "dimmer 3e+38");
  expectRefused(runtime().setBakedEmitterScale(0, 3e38f), "scale 3e+38");
  DynamicMesh glowing = crate();
  glowing.emission = {1e20f, 0, 0};
  expectRefused(runtime().addObject(glowing, at(0, 0.5f, 0)).status(), "emission (1e+20, 0, 0)");
  // The largest legal values stay finite.
  lamp = runtime().lightInfo(lamp_)->light;
  lamp.intensity = 1e12f;
  ASSERT_TRUE(runtime().setLight(lamp_, lamp).ok());
  settle();
  for (const Rgb& d : runtime().patchDeltas())
    ASSERT_TRUE(std::isfinite(d.r) && std::isfinite(d.g) && std::isfinite(d.b));
}

TEST_F(RuntimeAbuseFindings, ViewErrorsNameTheField) {
  RuntimeView view;
  view.position = {0, 1, 1};
  view.look_at = {0, 1, 0};
  view.aspect = 0;
  expectRefused(runtime().setView(view), "aspect 0");
  view.aspect = 1;
  view.position.z = kNaN;
  expectRefused(runtime().setView(view), "position (0, 1, nan)");
  expectUnchanged();
}

TEST_F(RuntimeAbuseFindings, RendererRefusesBadViewsCamerasAndSizes) {
  SceneRenderer& renderer = *twin_.renderer;
  Camera camera;
  camera.position = {0, 1, 1.5f};
  camera.look_at = {0, 1, 0};
  ASSERT_TRUE(renderer.render(camera, ShadingView::kRuntime).ok());
  const std::vector<float> frame = renderer.readRadiance();
  expectRefused(renderer.render(camera, ShadingView(255)).status(), "view 255");
  Camera endless = camera;
  endless.far_m = kInf;
  expectRefused(renderer.render(endless, ShadingView::kRuntime).status(), "far");
  expectRefused(renderer.resize(0, 36), "0x36");
  expectRefused(renderer.resize(64, 1 << 20), "64x1048576");
  EXPECT_EQ(renderer.width(), 64);
  EXPECT_EQ(renderer.height(), 36);
  EXPECT_EQ(renderer.readRadiance(), frame) << "a refused call changed the last frame";
}

}  // namespace
}  // namespace svit

// Extreme but legal use of the runtime on the Cornell box: far objects,
// objects through walls, many objects, teleports, a light inside an object.
// Output stays finite, GL raises no error, and each case holds a bound of
// its own on the flux the static patches gain or lose: a far object next to
// none, an object through a wall and a curtain of crates little, a closed
// shade keeps all of its lamp's light in unless another object pierces it.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "abuse/box_mesh.h"
#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "scene/numeric.h"
#include "svit/runtime.h"

namespace svit {
namespace {

DynamicMesh cube(const std::string& name, float half) {
  DynamicMesh mesh = test::boxMesh(name, half);
  mesh.albedo = {0.6f, 0.5f, 0.4f};
  return mesh;
}

Mat4 at(float x, float y, float z) {
  Mat4 m;
  m.m[12] = x;
  m.m[13] = y;
  m.m[14] = z;
  return m;
}

void expectFinite(const Runtime& runtime) {
  for (const Rgb& d : runtime.patchDeltas()) {
    ASSERT_TRUE(std::isfinite(d.r) && std::isfinite(d.g) && std::isfinite(d.b));
  }
  const Rgb floor = runtime.irradianceAt({0.2f, 0.0f, 0.3f}, {0, 1, 0});
  EXPECT_TRUE(std::isfinite(floor.r) && floor.r >= 0) << floor.r;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// Flux the static patches receive beyond the bake (lm): each runtime
// patch's luminance delta (lux), less `before`'s when given, times its area,
// gains and losses summed apart.
struct DeltaFlux {
  double gained_lm = 0, lost_lm = 0;
  uint32_t changed_patches = 0;
};
DeltaFlux staticDeltaFlux(const Runtime& runtime, const std::vector<Rgb>& before = {}) {
  DeltaFlux flux;
  for (uint32_t p = 0; p < runtime.staticPatchCount(); ++p) {
    Rgb d = runtime.patchDeltas()[p];
    if (!before.empty()) d = {d.r - before[p].r, d.g - before[p].g, d.b - before[p].b};
    const double lm = double(luminance(d)) * double(runtime.patchInfo(p)->area_m2);
    (lm > 0 ? flux.gained_lm : flux.lost_lm) += std::abs(lm);
    if (d.r != 0 || d.g != 0 || d.b != 0) ++flux.changed_patches;
  }
  return flux;
}

// Updates until the runtime has nothing left to do (at most 16 updates; the
// level's own dynamic tall box has deltas of its own, and they settle over
// updates) and returns the static deltas then: what a change is measured from.
std::vector<Rgb> settledDeltas(Runtime& runtime) {
  for (int i = 0; i < 16; ++i) {
    const FrameStats stats = runtime.update(0);
    EXPECT_TRUE(stats.error.empty()) << stats.error;
    if (stats.idle) break;
  }
  return runtime.patchDeltas();
}

class RuntimeRobustness : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(gl_.ok());
    runtime_ = create();
  }
  static std::unique_ptr<Runtime> create() {
    const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
    RuntimeSettings settings;
    settings.map_resolution = 64;  // llvmpipe: keep 256 objects quick
    Expected<std::unique_ptr<Runtime>> created =
        Runtime::create(level.scene, level.bake, level.dir, settings);
    EXPECT_TRUE(created.ok()) << created.status().message();
    return created.ok() ? std::move(created).value() : nullptr;
  }
  test::GlTestContext gl_;
  std::unique_ptr<Runtime> runtime_;
};

TEST_F(RuntimeRobustness, ObjectFarFromTheOrigin) {
  const std::vector<Rgb> before = settledDeltas(*runtime_);
  Expected<ObjectId> far = runtime_->addObject(cube("far", 0.5f), at(1e4f, 3, -1e4f));
  ASSERT_TRUE(far.ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime_->update(0).error.empty());
  expectFinite(*runtime_);
  // 14 km from the box, outside every emitter's reach and outside the
  // level's box, it takes no light and none of the ambient (Receiver::
  // shares_ambient): it changes no static patch. Before the ambient was
  // kept to the level, its 6 m2 diluted the ambient of every patch: 1118
  // patches changed, 0.013 lm lost. Now one patch differs by the bounce
  // solver's rounding (re-solved with the object's receivers appended):
  // measured 4.9e-16 lm. Bound: 1e-9 lm, in at most 2 patches.
  settledDeltas(*runtime_);
  const DeltaFlux flux = staticDeltaFlux(*runtime_, before);
  std::printf("[measured] far object: %u patches changed, gained %.4g lm, lost %.4g lm\n",
              flux.changed_patches, flux.gained_lm, flux.lost_lm);
  EXPECT_LT(flux.gained_lm + flux.lost_lm, 1e-9);
  EXPECT_LE(flux.changed_patches, 2u);
}

TEST_F(RuntimeRobustness, ObjectThroughAWall) {
  const std::vector<Rgb> before = settledDeltas(*runtime_);
  Expected<ObjectId> through = runtime_->addObject(cube("through", 0.3f), at(-1.0f, 1.0f, 0));
  ASSERT_TRUE(through.ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime_->update(0).error.empty());
  expectFinite(*runtime_);
  settledDeltas(*runtime_);
  const DeltaFlux flux = staticDeltaFlux(*runtime_, before);
  std::printf("[measured] through a wall: %u patches changed, gained %.4g lm, lost %.4g lm\n",
              flux.changed_patches, flux.gained_lm, flux.lost_lm);
  // The cube (albedo 0.6, 40 % absorbed) casts a shadow and reflects only
  // part of what it intercepts: the static surfaces lose more than they gain
  // (measured: 0.51 lm lost, 0.008 lm gained).
  EXPECT_GT(flux.lost_lm, 0.0);
  EXPECT_LT(flux.gained_lm, flux.lost_lm);
}

TEST_F(RuntimeRobustness, ManyObjectsAndTeleports) {
  const std::vector<Rgb> before = settledDeltas(*runtime_);
  std::vector<ObjectId> ids;
  for (int i = 0; i < 256; ++i) {
    Expected<ObjectId> id =
        runtime_->addObject(cube("crate " + std::to_string(i), 0.02f),
                            at(-0.8f + 0.1f * float(i % 16), 0.05f + 0.1f * float(i / 16), 0.5f));
    ASSERT_TRUE(id.ok());
    ids.push_back(*id);
  }
  FrameStats stats = runtime_->update(50);  // a budget: not everything settles in one frame
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  for (size_t i = 0; i < ids.size(); i += 7)
    ASSERT_TRUE(runtime_->setObjectTransform(ids[i], at(0.5f, 1.5f, -0.5f)).ok());
  stats = runtime_->update(50);
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  expectFinite(*runtime_);
  settledDeltas(*runtime_);
  const DeltaFlux flux = staticDeltaFlux(*runtime_, before);
  std::printf("[measured] 256 crates: %u patches changed, gained %.4g lm, lost %.4g lm\n",
              flux.changed_patches, flux.gained_lm, flux.lost_lm);
  // A curtain of small crates (albedo 0.6) shadows the floor and throws
  // some light back on the walls: measured 0.47 lm gained and 0.29 lm lost
  // of the ceiling lamp's 7 lm. Bound: 1 lm in all, and some shadow.
  EXPECT_GT(flux.lost_lm, 0.0);
  EXPECT_LT(flux.gained_lm + flux.lost_lm, 1.0);
}

// What the static patches gained and lost, as a share of an isotropic
// lamp's flux (4 pi x intensity lm).
double shareOfLampFlux(const DeltaFlux& flux, const Light& lamp) {
  return (flux.gained_lm + flux.lost_lm) / (4.0 * kPi * double(lamp.intensity));
}

// Flux a 1e6 cd lamp at `lamp_at` adds to the static patches (what a
// shade around it at `shade_at` already changed subtracted; deltas hold the
// lamp's bounced light, its direct light is the shaders'), as a share of
// its flux, 4 pi x 1e6 lm. Output stays finite, on the shade too.
double lampLeak(Runtime& runtime, const Vec3& shade_at, const Vec3& lamp_at) {
  EXPECT_TRUE(
      runtime.addObject(cube("lamp shade", 0.2f), at(shade_at.x, shade_at.y, shade_at.z)).ok());
  const std::vector<Rgb> shaded = settledDeltas(runtime);
  Light lamp;
  lamp.name = "inside";
  lamp.position = lamp_at;
  lamp.intensity = 1e6f;
  EXPECT_TRUE(runtime.addLight(lamp).ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime.update(0).error.empty());
  expectFinite(runtime);
  for (uint32_t t = 0; t < 12; ++t) {
    const Rgb shade = *runtime.objectPatchIrradiance(runtime.objects().back(), t);
    EXPECT_TRUE(std::isfinite(shade.r) && std::isfinite(shade.g) && std::isfinite(shade.b));
  }
  settledDeltas(runtime);
  return shareOfLampFlux(staticDeltaFlux(runtime, shaded), lamp);
}

// A closed shade in free air (nothing else inside it) keeps all of its
// lamp's light: the lamp's maps show only the shade's back faces, which
// absorb, so no static patch changes at all. Measured: 0 (exactly). The
// same lamp with no shade gives 52.5 % for scale.
TEST_F(RuntimeRobustness, LightInsideAnObject) {
  const Vec3 shade_at{0.0f, 1.5f, 0.5f}, lamp_at{0.05f, 1.53f, 0.52f};
  const double leak = lampLeak(*runtime_, shade_at, lamp_at);
  std::unique_ptr<Runtime> unshaded = create();
  ASSERT_TRUE(unshaded);
  const std::vector<Rgb> unlit = settledDeltas(*unshaded);
  Light lamp;
  lamp.position = lamp_at;
  lamp.intensity = 1e6f;
  ASSERT_TRUE(unshaded->addLight(lamp).ok());
  settledDeltas(*unshaded);
  const DeltaFlux open = staticDeltaFlux(*unshaded, unlit);
  const double open_share = shareOfLampFlux(open, lamp);
  std::printf(
      "[measured] lamp in a shade in free air: %.3g %% of its flux; without the shade %.3f %%\n",
      100.0 * leak, 100.0 * open_share);
  EXPECT_LT(leak, 1e-9);
  EXPECT_GT(open_share, 0.3);  // the lamp does light the box: the bound above can fail
}

// The same shade at (0, 1, 0), where the level's tall box passes through
// it: the lamp lights the part of the tall box's face inside the shade
// (17.5 % of its flux lands on that face), and the face, one runtime patch,
// reflects it from all of its area, nine tenths of it outside the shade.
// Patches reflect what they get uniformly (thesis 5.3); interpenetrating
// objects leak by the share of a patch that lies inside. Measured: 7.7 %;
// bound 9 %. With the tall box hidden the same shade and lamp leak nothing,
// which shows that the leak is the tall box's.
TEST_F(RuntimeRobustness, LightInsideAnObjectThatAnotherPierces) {
  const Vec3 shade_at{0.0f, 1.0f, 0.0f}, lamp_at{0.05f, 1.03f, 0.02f};
  const double pierced = lampLeak(*runtime_, shade_at, lamp_at);
  std::unique_ptr<Runtime> without_box = create();
  ASSERT_TRUE(without_box);
  const ObjectId tall_box = without_box->objects().front();
  ASSERT_EQ(without_box->objectInfo(tall_box)->name, "tallBox");
  ASSERT_TRUE(without_box->setObjectVisible(tall_box, false).ok());
  const double alone = lampLeak(*without_box, shade_at, lamp_at);
  std::printf(
      "[measured] lamp in a shade the tall box pierces: %.3f %% of its flux; "
      "with the tall box hidden %.3g %%\n",
      100.0 * pierced, 100.0 * alone);
  EXPECT_LT(pierced, 0.09);
  EXPECT_GT(pierced, 0.01);  // the patch path does leak here: the case is what it says
  EXPECT_LT(alone, 1e-9);
}

}  // namespace
}  // namespace svit

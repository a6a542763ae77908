// Extreme but legal use of the runtime: far objects, objects through walls,
// many objects, teleports, a light inside an object. Output stays finite and
// GL raises no error.

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <cmath>

#include "gl_test_context.h"
#include "runtime_test_util.h"
#include "svit/runtime.h"

namespace svit {
namespace {

DynamicMesh cube(const std::string& name, float half) {
  DynamicMesh mesh;
  mesh.name = name;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back({(i & 1) ? half : -half, (i & 2) ? half : -half, (i & 4) ? half : -half});
  }
  // Outward, counter-clockwise faces.
  mesh.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
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

class RuntimeRobustness : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(gl_.ok());
    const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
    RuntimeSettings settings;
    settings.map_resolution = 64;  // llvmpipe: keep 256 objects quick
    Expected<std::unique_ptr<Runtime>> created = Runtime::create(level.scene, level.bake, level.dir, settings);
    ASSERT_TRUE(created.ok()) << created.status().message();
    runtime_ = std::move(created).value();
  }
  test::GlTestContext gl_;
  std::unique_ptr<Runtime> runtime_;
};

TEST_F(RuntimeRobustness, ObjectFarFromTheOrigin) {
  Expected<ObjectId> far = runtime_->addObject(cube("far", 0.5f), at(1e4f, 3, -1e4f));
  ASSERT_TRUE(far.ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime_->update(0).error.empty());
  expectFinite(*runtime_);
}

TEST_F(RuntimeRobustness, ObjectThroughAWall) {
  Expected<ObjectId> through = runtime_->addObject(cube("through", 0.3f), at(-1.0f, 1.0f, 0));
  ASSERT_TRUE(through.ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime_->update(0).error.empty());
  expectFinite(*runtime_);
}

TEST_F(RuntimeRobustness, ManyObjectsAndTeleports) {
  std::vector<ObjectId> ids;
  for (int i = 0; i < 256; ++i) {
    Expected<ObjectId> id = runtime_->addObject(cube("crate " + std::to_string(i), 0.02f),
                                                at(-0.8f + 0.1f * float(i % 16), 0.05f + 0.1f * float(i / 16), 0.5f));
    ASSERT_TRUE(id.ok());
    ids.push_back(*id);
  }
  FrameStats stats = runtime_->update(50);  // a budget: not everything settles in one frame
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  for (size_t i = 0; i < ids.size(); i += 7) ASSERT_TRUE(runtime_->setObjectTransform(ids[i], at(0.5f, 1.5f, -0.5f)).ok());
  stats = runtime_->update(50);
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  expectFinite(*runtime_);
}

TEST_F(RuntimeRobustness, LightInsideAnObject) {
  ASSERT_TRUE(runtime_->addObject(cube("lamp shade", 0.2f), at(0, 1, 0)).ok());
  Light lamp;
  lamp.name = "inside";
  lamp.position = {0.05f, 1.03f, 0.02f};
  lamp.intensity = 1e6f;
  Expected<LightId> id = runtime_->addLight(lamp);
  ASSERT_TRUE(id.ok());
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(runtime_->update(0).error.empty());
  expectFinite(*runtime_);
  for (uint32_t t = 0; t < 12; ++t) {
    const Rgb shade = *runtime_->objectPatchIrradiance(runtime_->objects().back(), t);
    EXPECT_TRUE(std::isfinite(shade.r) && std::isfinite(shade.g) && std::isfinite(shade.b));
  }
}

}  // namespace
}  // namespace svit

// The Runtime's contract at its boundary: no context, a bake of another
// level, bad objects and lights, and "pay for what is used" on a static level.

#include <gtest/gtest.h>

#include <cmath>

#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "svit/runtime.h"

namespace svit {
namespace {

using test::bakedLevel;

TEST(RuntimeApi, WithoutContextIsAClearError) {
  const test::BakedLevel& level = bakedLevel("cornell_static", test::cornellGltf());
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_FALSE(runtime.ok());
  EXPECT_NE(runtime.status().message().find("no current OpenGL context"), std::string::npos);
}

TEST(RuntimeApi, RejectsTheBakeOfAnotherLevel) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell_static", test::cornellGltf());
  Scene other = level.scene;
  other.materials[0].base_color.r *= 0.5f;
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(other, level.bake, level.dir);
  ASSERT_FALSE(runtime.ok());
  EXPECT_EQ(runtime.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(runtime.status().message().find("another level"), std::string::npos)
      << runtime.status().message();
}

TEST(RuntimeApi, RejectsSettingsOutOfRange) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell_static", test::cornellGltf());
  RuntimeSettings settings;
  settings.map_resolution = 4;
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  ASSERT_FALSE(runtime.ok());
  EXPECT_NE(runtime.status().message().find("map_resolution"), std::string::npos);
}

TEST(RuntimeApi, StaticLevelRendersNoMapsAndAllocatesNothing) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell_static", test::cornellGltf());
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(runtime.ok()) << runtime.status().message();
  for (int frame = 0; frame < 10; ++frame) {
    const FrameStats stats = (*runtime)->update(16);
    EXPECT_TRUE(stats.idle);
    EXPECT_EQ(stats.faces_rendered, 0u);
    EXPECT_EQ(stats.samples_rendered, 0u);
    EXPECT_EQ(stats.gl_objects_created, 0u);
    EXPECT_TRUE(stats.error.empty());
  }
  EXPECT_EQ((*runtime)->shadingResources().patch_delta_buffer, 0u);
  // A game cannot add dynamic content the bake was not made for.
  DynamicMesh mesh;
  mesh.positions = {{0, 0.5f, 0}, {0.1f, 0.5f, 0}, {0, 0.6f, 0}};
  mesh.indices = {0, 1, 2};
  Expected<ObjectId> added = (*runtime)->addObject(mesh, Mat4{});
  ASSERT_FALSE(added.ok());
  EXPECT_NE(added.status().message().find("no runtime sections"), std::string::npos);
}

TEST(RuntimeApi, BadObjectsAndLightsAreRejected) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = bakedLevel("cornell", test::cornellLevel());
  Expected<std::unique_ptr<Runtime>> created = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  DynamicMesh mesh;
  mesh.name = "crate";
  mesh.positions = {{0, 0.5f, 0}, {0.1f, 0.5f, 0}, {0, 0.6f, 0}};
  mesh.indices = {0, 1, 5};
  Expected<ObjectId> bad_index = runtime.addObject(mesh, Mat4{});
  ASSERT_FALSE(bad_index.ok());
  EXPECT_NE(bad_index.status().message().find("'crate': index 2 = 5 >= vertex count 3"),
            std::string::npos)
      << bad_index.status().message();
  mesh.indices = {0, 1, 2};
  mesh.positions[1].y = std::nanf("");
  EXPECT_FALSE(runtime.addObject(mesh, Mat4{}).ok());
  mesh.positions[1].y = 0.5f;
  mesh.albedo = {1.5f, 0.5f, 0.5f};
  EXPECT_FALSE(runtime.addObject(mesh, Mat4{}).ok());
  mesh.albedo = {0.5f, 0.5f, 0.5f};
  Mat4 nan_matrix;
  nan_matrix.m[12] = std::nanf("");
  EXPECT_FALSE(runtime.addObject(mesh, nan_matrix).ok());
  Expected<ObjectId> ok = runtime.addObject(mesh, Mat4{});
  ASSERT_TRUE(ok.ok()) << ok.status().message();
  EXPECT_FALSE(runtime.setObjectTransform(*ok, nan_matrix).ok());
  EXPECT_EQ(runtime.setObjectTransform(9999, Mat4{}).code(), StatusCode::kNotFound);
  EXPECT_TRUE(runtime.removeObject(*ok).ok());
  EXPECT_EQ(runtime.removeObject(*ok).code(), StatusCode::kNotFound);
  EXPECT_FALSE(runtime
                   .deformObject(runtime.objectForNode(level.scene.findNode("tallBox")),
                                 std::vector<Vec3>(2))
                   .ok());

  Light sun_like;
  sun_like.type = LightType::kDirectional;
  EXPECT_FALSE(runtime.addLight(sun_like).ok());
  Light negative;
  negative.intensity = -1;
  EXPECT_FALSE(runtime.addLight(negative).ok());
  Light spot;
  spot.type = LightType::kSpot;
  spot.inner_cone_rad = 0.8f;
  spot.outer_cone_rad = 0.4f;
  EXPECT_FALSE(runtime.addLight(spot).ok());
  EXPECT_EQ(runtime.setLightDimmer(77, 1).code(), StatusCode::kNotFound);
  EXPECT_FALSE(runtime.setBakedEmitterScale(100000, 1).ok());
  EXPECT_NE(runtime.objectForNode(level.scene.findNode("tallBox")), kInvalidId);
}

}  // namespace
}  // namespace svit

// level.json loading (docs/level-format.md) on the small files in
// tests/data/ (written by tests/data/make_test_data.py). Every level names
// good_quad.gltf (one 2 m^2 quad, node 'Quad') relative to itself, except
// missing_gltf.level.json. Bad fields must fail naming the level file and the
// field; the checked substrings are short and case-insensitive on purpose.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scene_test_util.h"
#include "svit/level.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {
namespace {

using test::dataPath;
using test::describe;
using test::messageHas;

// Values written in the file and stored as float come back as the nearest
// float (relative error <= 6e-8); 1e-6 relative covers them with margin.
constexpr float kRelative = 1e-6f;

Status loadFailure(const std::string& name) {
  Expected<Scene> result = loadLevel(dataPath(name));
  if (result.ok()) {
    ADD_FAILURE() << name << " loaded without error";
    return Status::okStatus();
  }
  return result.status();
}

TEST(LevelJson, GoodLevelLoadsEveryField) {
  const std::string path = dataPath("good_level.json");
  Expected<Scene> result = loadLevel(path);
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;

  // The glTF is found relative to the level file, not the working directory.
  EXPECT_EQ(scene.source_path, path);
  std::error_code ec;
  EXPECT_TRUE(std::filesystem::equivalent(scene.gltf_path, dataPath("good_quad.gltf"), ec))
      << scene.gltf_path << " " << ec.message();
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].triangleCount(), 2u);
  ASSERT_GE(scene.findNode("Quad"), 0);
  EXPECT_TRUE(scene.warnings.empty()) << test::joinLines(scene.warnings);

  // sun: direction_to_sun [0, 2, 0] is normalised on load.
  EXPECT_TRUE(scene.sun.enabled);
  EXPECT_TRUE(test::vecNear(scene.sun.direction_to_sun, {0, 1, 0}, kRelative));
  EXPECT_NEAR(scene.sun.illuminance_lux, 100000.0f, 100000.0f * kRelative);
  EXPECT_NEAR(scene.sun.angular_radius_rad, 0.01f, 0.01f * kRelative);
  EXPECT_TRUE(test::rgbNear(scene.sun.color, {1.0f, 0.96f, 0.9f}, kRelative));

  // sky: gradient; horizon_luminance 6000 is a single number = grey.
  EXPECT_EQ(scene.sky.model, SkyModel::kGradient);
  EXPECT_TRUE(test::rgbNear(scene.sky.zenith_luminance, {4000, 5000, 7000}, 7000 * kRelative));
  EXPECT_TRUE(test::rgbNear(scene.sky.horizon_luminance, {6000, 6000, 6000}, 6000 * kRelative));
  EXPECT_TRUE(test::rgbNear(scene.sky.ground_luminance, {100, 80, 60}, 100 * kRelative));

  // lights: one level light (good_quad.gltf has none of its own).
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light& lamp = scene.lights[0];
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(lamp.type, LightType::kPoint);
  EXPECT_TRUE(test::vecNear(lamp.position, {0, 1.5f, 0}, kRelative));
  EXPECT_TRUE(test::rgbNear(lamp.color, {1.0f, 0.9f, 0.8f}, kRelative));
  EXPECT_NEAR(lamp.intensity, 120.0f, 120.0f * kRelative);
  EXPECT_EQ(lamp.range_m, 0.0f);
  EXPECT_TRUE(lamp.dynamic);
  EXPECT_EQ(lamp.node, -1);

  // Nothing in the level marks nodes dynamic.
  for (const Instance& instance : scene.instances) EXPECT_FALSE(instance.dynamic);
  EXPECT_TRUE(scene.object_paths.empty());

  // camera_paths[0] 'main': two keys.
  ASSERT_EQ(scene.camera_paths.size(), 1u);
  const CameraPath& camera = scene.camera_paths[0];
  EXPECT_EQ(camera.name, "main");
  EXPECT_FALSE(camera.loop);
  ASSERT_EQ(camera.keys.size(), 2u);
  EXPECT_EQ(camera.keys[0].t_s, 0.0f);
  EXPECT_TRUE(test::vecNear(camera.keys[0].position, {0, 1, 3.5f}, kRelative));
  EXPECT_TRUE(test::vecNear(camera.keys[0].look_at, {0, 1, 0}, kRelative));
  EXPECT_NEAR(camera.keys[0].yfov_rad, 0.69f, 0.69f * kRelative);
  EXPECT_NEAR(camera.keys[1].t_s, 6.0f, 6.0f * kRelative);
  EXPECT_TRUE(test::vecNear(camera.keys[1].position, {0.5f, 1.2f, 2.5f}, 2.5f * kRelative));
  EXPECT_TRUE(test::vecNear(camera.keys[1].look_at, {0, 0.8f, 0}, kRelative));
  // The second key has no yfov_rad: it keeps the previous key's (the
  // importer's rule; a field of view does not jump back to 60 degrees
  // between keys).
  EXPECT_NEAR(camera.keys[1].yfov_rad, 0.69f, 0.69f * kRelative);
}

TEST(LevelJson, UnknownDynamicNode) {
  // dynamic: ["NoSuchNode"]; good_quad.gltf has only 'Quad'.
  const Status status = loadFailure("unknown_node.level.json");
  ASSERT_FALSE(status.ok());
  // svit/status.h: kNotFound = "a file, node or element that was named does not exist".
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << describe(status);
  EXPECT_TRUE(messageHas(status, {"unknown_node.level.json", "dynamic[0]", "NoSuchNode"}));
}

TEST(LevelJson, BadJsonSyntax) {
  // Missing comma at the end of line 2.
  const Status status = loadFailure("bad_level_json.json");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"bad_level_json.json", "line 3"}));
}

TEST(LevelJson, NegativeLightIntensity) {
  // lights[0].intensity_cd = -3.
  const Status status = loadFailure("negative_level_light.level.json");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"negative_level_light.level.json", "lights[0].intensity_cd", "-3"}));
}

TEST(LevelJson, UnknownFieldIsAnError) {
  // "lihgts" (a typo of "lights") must not be ignored silently.
  const Status status = loadFailure("unknown_field.level.json");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"unknown_field.level.json", "lihgts"}));
}

TEST(LevelJson, MissingGltf) {
  // gltf: "no_such_scene.gltf", which does not exist next to the level.
  const Status status = loadFailure("missing_gltf.level.json");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << describe(status);
  EXPECT_TRUE(messageHas(status, {"missing_gltf.level.json", "no_such_scene.gltf"}));
}

}  // namespace
}  // namespace svit

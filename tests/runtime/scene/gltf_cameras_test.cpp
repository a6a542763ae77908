// glTF cameras as viewpoints (Scene::cameras): placed by their node's world
// transform, named, bad projections refused naming the camera and value,
// orthographic ones a warning, and written back by writeGltf.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "scene_test_util.h"
#include "svit/bake_file.h"
#include "svit/level.h"

namespace svit::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// good_quad.gltf with a parent node at (0, 1, 0) turned 90 degrees about +Y
// holding a child at z = 2 with perspective camera 0 ("Door view"), and a
// root node with orthographic camera 1.
Json quadWithCameras() {
  Json gltf = Json::parse(std::ifstream(dataPath("good_quad.gltf")));
  gltf["cameras"] = Json::array(
      {{{"name", "Door view"},
        {"type", "perspective"},
        {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"zfar", 50.0}}}},
       {{"type", "orthographic"},
        {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}}});
  const double half = std::sqrt(0.5);
  gltf["nodes"].push_back({{"name", "rig"},
                           {"translation", {0, 1, 0}},
                           {"rotation", {0, half, 0, half}},
                           {"children", {2}}});
  gltf["nodes"].push_back({{"name", "eye"}, {"translation", {0, 0, 2}}, {"camera", 0}});
  gltf["nodes"].push_back({{"name", "plan"}, {"camera", 1}});
  gltf["scenes"][0]["nodes"] = {0, 1, 3};
  return gltf;
}

std::string writeTemp(const Json& gltf, const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("svit_camera_test_" + name + ".gltf");
  std::ofstream(path) << gltf.dump();
  return path.string();
}

void expectNear(const Vec3& v, float x, float y, float z) {
  EXPECT_NEAR(v.x, x, 1e-5f);
  EXPECT_NEAR(v.y, y, 1e-5f);
  EXPECT_NEAR(v.z, z, 1e-5f);
}

TEST(GltfCameras, PerspectiveCamerasArePlacedByTheirNode) {
  Expected<Scene> scene = loadLevel(writeTemp(quadWithCameras(), "placed"));
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  ASSERT_EQ(scene->cameras.size(), 1u);
  const SceneCamera& camera = scene->cameras[0];
  EXPECT_EQ(camera.name, "Door view");
  EXPECT_EQ(camera.node, 2);
  // The child's z = 2 turned 90 degrees about +Y is x = 2; -Z turns to -X.
  expectNear(camera.position, 2, 1, 0);
  expectNear(camera.forward, -1, 0, 0);
  expectNear(camera.up, 0, 1, 0);
  EXPECT_FLOAT_EQ(camera.yfov_rad, 0.8f);
  EXPECT_FLOAT_EQ(camera.near_m, 0.1f);
  EXPECT_FLOAT_EQ(camera.far_m, 50.0f);
  EXPECT_TRUE(someWarningHas(scene->warnings, {"camera 1", "orthographic", "skipped"}));
}

TEST(GltfCameras, AnUnnamedCameraTakesItsNodesName) {
  Json gltf = quadWithCameras();
  gltf["cameras"][0].erase("name");
  Expected<Scene> scene = loadLevel(writeTemp(gltf, "unnamed"));
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  ASSERT_EQ(scene->cameras.size(), 1u);
  EXPECT_EQ(scene->cameras[0].name, "eye");
}

TEST(GltfCameras, BadProjectionsAreRefusedNamingTheCamera) {
  const struct {
    const char* field;
    double value;
    const char* says;
  } cases[] = {{"yfov", 0.0, "yfov"},
               {"yfov", 3.5, "yfov"},
               {"znear", 0.0, "znear"},
               {"zfar", 0.05, "zfar"}};
  for (const auto& c : cases) {
    Json gltf = quadWithCameras();
    gltf["cameras"][0]["perspective"][c.field] = c.value;
    const Expected<Scene> scene = loadLevel(writeTemp(gltf, std::string("bad_") + c.field));
    ASSERT_FALSE(scene.ok()) << c.field << " " << c.value;
    EXPECT_EQ(scene.status().code(), StatusCode::kInvalidInput);
    EXPECT_TRUE(messageHas(scene.status(), {"svit_camera_test_bad", "Door view", c.says}));
  }
  Json gltf = quadWithCameras();
  gltf["nodes"][2]["camera"] = 7;
  const Expected<Scene> scene = loadLevel(writeTemp(gltf, "missing"));
  ASSERT_FALSE(scene.ok());
  EXPECT_TRUE(messageHas(scene.status(), {"node 'eye'", "camera 7", "does not exist"}));
}

TEST(GltfCameras, CamerasDoNotChangeTheLevelHash) {
  Expected<Scene> with = loadLevel(writeTemp(quadWithCameras(), "hash"));
  Expected<Scene> without = loadLevel(dataPath("good_quad.gltf"));
  ASSERT_TRUE(with.ok() && without.ok());
  EXPECT_EQ(hashLevel(*with), hashLevel(*without));
}

TEST(GltfCameras, WriteGltfKeepsThem) {
  Expected<Scene> scene = loadLevel(writeTemp(quadWithCameras(), "write"));
  ASSERT_TRUE(scene.ok());
  const std::string copy = (fs::temp_directory_path() / "svit_camera_test_copy.gltf").string();
  ASSERT_TRUE(writeGltf(*scene, copy).ok());
  Expected<Scene> again = loadLevel(copy);
  ASSERT_TRUE(again.ok()) << again.status().message();
  ASSERT_EQ(again->cameras.size(), 1u);
  EXPECT_EQ(again->cameras[0].name, "Door view");
  expectNear(again->cameras[0].position, 2, 1, 0);
  expectNear(again->cameras[0].forward, -1, 0, 0);
  EXPECT_FLOAT_EQ(again->cameras[0].far_m, 50.0f);
}

}  // namespace
}  // namespace svit::test

// The sample walkthrough levels of samples/levels (samples/levels/README.md)
// load and have the dynamic objects, lights and paths they promise, and the
// house generator writes what is committed and scales to 8 x 8 rooms.
// Sponza and the city read their glTF from ../shared/scenes: without it they skip.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "shared_scene.h"
#include "svit/level.h"
#include "svit/scene.h"
#include "svit/scene_summary.h"

namespace svit {
namespace {

const std::string kLevels = std::string(SVIT_SOURCE_DIR) + "/samples/levels";

// Textures are not needed to count objects and lights (Sponza decodes 63 MB).
Scene load(const std::string& path) {
  LoadOptions options;
  options.load_textures = false;
  Expected<Scene> result = loadLevel(path, options);
  if (!result.ok()) {
    ADD_FAILURE() << result.status().message();
    return Scene();
  }
  return std::move(result).value();
}

const Instance* instanceOf(const Scene& scene, const std::string& node_name) {
  const int node = scene.findNode(node_name);
  for (const Instance& instance : scene.instances) {
    if (instance.node == node) return &instance;
  }
  return nullptr;
}

bool hasPathFor(const Scene& scene, const std::string& node_name) {
  const int node = scene.findNode(node_name);
  for (const ObjectPath& path : scene.object_paths) {
    if (path.node == node && node >= 0) return true;
  }
  return false;
}

bool inside(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y && p.z > lo.z && p.z < hi.z;
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

TEST(SampleLevels, CornellTallBoxMoves) {
  const Scene scene = load(kLevels + "/cornell/level.json");
  EXPECT_TRUE(scene.warnings.empty());
  const Instance* box = instanceOf(scene, "tallBox");
  ASSERT_NE(box, nullptr);
  EXPECT_TRUE(box->dynamic);
  EXPECT_TRUE(hasPathFor(scene, "tallBox"));
  EXPECT_GT(summarize(scene).emissive_triangles, 0u);  // the lamp svit-walk dims
  ASSERT_FALSE(scene.camera_paths.empty());
  EXPECT_GE(scene.camera_paths[0].keys.size(), 2u);
}

TEST(SampleLevels, SponzaHasArcadeLampsACarriedLampARollingBallAndAWalk) {
  SVIT_SKIP_WITHOUT_SHARED_SCENE("sponza/Sponza.gltf");
  const Scene scene = load(kLevels + "/sponza/level.json");
  EXPECT_TRUE(scene.warnings.empty());
  EXPECT_TRUE(scene.sun.enabled);
  EXPECT_EQ(scene.sky.model, SkyModel::kGradient);

  // Six baked arcade lamps, in the ground-floor arcades: above the floor
  // (y = 3.98 m), below the arcade vault (~9.3 m), between the outer walls
  // (z = -9.1 and 7.6 m) and the column rows (|z + 0.75| > 2.8 m).
  size_t arcade = 0;
  for (const Light& light : scene.lights) {
    if (light.dynamic) continue;
    ++arcade;
    EXPECT_EQ(light.type, LightType::kPoint) << light.name;
    EXPECT_GT(light.intensity, 0.0f) << light.name;
    EXPECT_TRUE(inside(light.position, {-20, 4.5f, -9}, {17, 9, 7.5f})) << light.name;
    EXPECT_GT(std::abs(light.position.z + 0.75f), 2.8f) << light.name;
  }
  EXPECT_EQ(arcade, 6u);

  // The carried lamp hangs on the lantern, which follows a path.
  const int lantern = scene.findNode("lantern");
  ASSERT_GE(lantern, 0);
  size_t carried = 0;
  for (const Light& light : scene.lights) {
    if (!light.dynamic) continue;
    ++carried;
    ASSERT_GE(light.node, 0);
    EXPECT_EQ(scene.nodes[size_t(light.node)].parent, lantern) << light.name;
  }
  EXPECT_EQ(carried, 1u);
  ASSERT_NE(instanceOf(scene, "lantern"), nullptr);
  EXPECT_TRUE(instanceOf(scene, "lantern")->dynamic);
  EXPECT_TRUE(hasPathFor(scene, "lantern"));

  // The ball rolls: dynamic, on a path with turning keys.
  const Instance* ball = instanceOf(scene, "ball");
  ASSERT_NE(ball, nullptr);
  EXPECT_TRUE(ball->dynamic);
  EXPECT_TRUE(hasPathFor(scene, "ball"));
  for (const ObjectPath& path : scene.object_paths) {
    if (path.node != scene.findNode("ball")) continue;
    ASSERT_GT(path.keys.size(), 2u);
    EXPECT_NE(path.keys[0].rotation.w, path.keys[1].rotation.w);
  }

  // A camera walk through the atrium, inside the building.
  ASSERT_EQ(scene.camera_paths.size(), 1u);
  EXPECT_GE(scene.camera_paths[0].keys.size(), 4u);
  for (const CameraKey& key : scene.camera_paths[0].keys) {
    EXPECT_TRUE(inside(key.position, {-20, 4, -9}, {17.3f, 21, 7.6f}));
  }
}

TEST(SampleLevels, CityVehiclesFollowTheGltfAnimation) {
  SVIT_SKIP_WITHOUT_SHARED_SCENE("virtual_city/VC.gltf");
  const Scene scene = load(kLevels + "/city/level.json");
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_TRUE(scene.sun.enabled);
  EXPECT_NE(scene.sky.model, SkyModel::kNone);
  // Every node the animation moves has a path that plays it, so is dynamic
  // (no "animated but static" warnings, checked above).
  ASSERT_EQ(scene.animations.size(), 1u);
  std::set<int> animated;
  for (const AnimationTrack& track : scene.animations[0].tracks) animated.insert(track.node);
  EXPECT_EQ(animated.size(), 41u);
  std::set<int> driven;
  for (const ObjectPath& path : scene.object_paths) {
    EXPECT_EQ(path.animation, 0);
    EXPECT_TRUE(scene.nodes[size_t(path.node)].dynamic);
    driven.insert(path.node);
  }
  EXPECT_EQ(driven, animated);
  const SceneSummary summary = summarize(scene);
  EXPECT_GT(summary.dynamic_triangles, 1000u);
  EXPECT_GT(summary.static_triangles, 1000u);
  // The sky box (node 19) is left out: nothing may stand between the city and the sun.
  for (const Instance& instance : scene.instances) EXPECT_NE(instance.node, 19);
  ASSERT_EQ(scene.camera_paths.size(), 1u);
  EXPECT_GE(scene.camera_paths[0].keys.size(), 4u);
}

// The committed 2 x 2 house: eight lamps, doors and tables that move.
TEST(SampleLevels, HouseHasLampsDoorsTablesAndAWalk) {
  const Scene scene = load(kLevels + "/house/level.json");
  EXPECT_TRUE(scene.warnings.empty());
  size_t lamps = 0;
  for (const Light& light : scene.lights)
    lamps += (light.type == LightType::kPoint && !light.dynamic) ? 1 : 0;
  EXPECT_EQ(lamps, 8u);
  for (const char* name :
       {"door_x1_0", "door_x1_1", "door_z1_0", "door_z1_1", "table_0_0", "table_1_1"}) {
    const Instance* instance = instanceOf(scene, name);
    ASSERT_NE(instance, nullptr) << name;
    EXPECT_TRUE(instance->dynamic) << name;
  }
  EXPECT_FALSE(instanceOf(scene, "room_0_0")->dynamic);
  EXPECT_TRUE(hasPathFor(scene, "table_0_0"));
  EXPECT_TRUE(hasPathFor(scene, "door_z1_0"));  // the door off the walk swings
  ASSERT_EQ(scene.camera_paths.size(), 1u);
  EXPECT_EQ(scene.camera_paths[0].keys.size(), 7u);  // 4 rooms, 3 doorways
}

#ifdef SVIT_PYTHON3
// Runs make_house.py into a fresh directory; returns it, or "" on failure.
std::string makeHouse(const std::string& arguments) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path out =
      std::filesystem::path(::testing::TempDir()) / ("svit_house_" + std::string(info->name()));
  std::filesystem::remove_all(out);
  const std::string command = std::string("\"") + SVIT_PYTHON3 + "\" \"" + kLevels +
                              "/house/make_house.py\" " + arguments + " --out \"" + out.string() +
                              "\" > \"" + out.string() + ".log\" 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) {
    ADD_FAILURE() << command << " -> " << status << "\n" << readFile(out.string() + ".log");
    return "";
  }
  return out.string();
}

TEST(SampleLevels, HouseGeneratorWritesWhatIsCommitted) {
  // Default arguments give the committed 2 x 2 house, byte for byte: the
  // committed files are not stale, and the generator is deterministic.
  const std::string out = makeHouse("");
  ASSERT_FALSE(out.empty());
  for (const char* file : {"house.gltf", "house.bin", "level.json"}) {
    EXPECT_EQ(readFile(out + "/" + file), readFile(kLevels + "/house/" + file))
        << file << " differs: run samples/levels/house/make_house.py";
  }
}

TEST(SampleLevels, HouseGeneratorScalesTo64RoomsWith128Lamps) {
  const std::string out = makeHouse("--rooms-x 8 --rooms-z 8");
  ASSERT_FALSE(out.empty());
  const Scene scene = load(out + "/level.json");
  EXPECT_TRUE(scene.warnings.empty());
  std::set<std::string> lamps;
  for (const Light& light : scene.lights) {
    if (light.type == LightType::kPoint && !light.dynamic) lamps.insert(light.name);
  }
  EXPECT_EQ(lamps.size(), 128u);  // two per room, each named once
  size_t rooms = 0, tables = 0, doors = 0;
  for (const Instance& instance : scene.instances) {
    const std::string& name = scene.nodes[size_t(instance.node)].name;
    if (name.rfind("room_", 0) == 0) rooms += instance.dynamic ? 0 : 1;
    if (name.rfind("table_", 0) == 0) tables += instance.dynamic ? 1 : 0;
    if (name.rfind("door_", 0) == 0) doors += instance.dynamic ? 1 : 0;
  }
  EXPECT_EQ(rooms, 64u);
  EXPECT_EQ(tables, 64u);
  EXPECT_EQ(doors, 2u * 8u * 7u);  // every wall between two rooms
  ASSERT_EQ(scene.camera_paths.size(), 1u);
  EXPECT_EQ(scene.camera_paths[0].keys.size(), 15u);  // 8 rooms, 7 doorways
  EXPECT_EQ(scene.object_paths.size(), 2u);
  std::filesystem::remove_all(out);
}

TEST(SampleLevels, HouseGeneratorRejectsBadSizes) {
  const std::filesystem::path out = std::filesystem::path(::testing::TempDir()) / "svit_house_bad";
  const std::string command = std::string("\"") + SVIT_PYTHON3 + "\" \"" + kLevels +
                              "/house/make_house.py\" --rooms-x 0 --out \"" + out.string() +
                              "\" > /dev/null 2>&1";
  EXPECT_NE(std::system(command.c_str()), 0);
  EXPECT_FALSE(std::filesystem::exists(out / "level.json"));
}
#else
TEST(SampleLevels, HouseGenerator) { GTEST_SKIP() << "no Python 3 interpreter found by CMake"; }
#endif

}  // namespace
}  // namespace svit

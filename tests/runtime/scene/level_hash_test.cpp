// hashLevel (svit/bake_file.h), what a bake file records of its level:
// stable across loads, sensitive to what a bake depends on, blind to names.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene_test_util.h"
#include "svit/bake_file.h"
#include "svit/level.h"

namespace svit {
namespace {

using test::describe;

const std::string kCornell = SVIT_CORNELL_GLTF;

Scene loadCornell() {
  Expected<Scene> scene = loadLevel(kCornell);
  EXPECT_TRUE(scene.ok()) << describe(scene.status());
  return scene.ok() ? std::move(scene).value() : Scene();
}

TEST(LevelHash, EqualForTwoLoadsOfTheSameGltf) {
  const Scene a = loadCornell(), b = loadCornell();
  ASSERT_FALSE(a.meshes.empty());
  EXPECT_EQ(hashLevel(a), hashLevel(b));
  EXPECT_NE(hashLevel(a), hashLevel(Scene()));
}

TEST(LevelHash, ChangesWithALightsIntensity) {
  Scene base = loadCornell();
  Light lamp;
  lamp.type = LightType::kPoint;
  lamp.intensity = 10;
  lamp.position = {0, 1.5f, 0};
  base.lights.push_back(lamp);
  Scene brighter = base;
  brighter.lights.back().intensity = 10.5f;
  EXPECT_NE(hashLevel(base), hashLevel(brighter));
  Scene no_light = base;
  no_light.lights.clear();
  EXPECT_NE(hashLevel(base), hashLevel(no_light));
  // The Cornell box's own light is an emissive material.
  Scene dimmer = loadCornell();
  bool changed = false;
  for (Material& m : dimmer.materials) {
    if (m.emissive_luminance.r > 0 && !changed) {
      m.emissive_luminance.r *= 0.5f;
      changed = true;
    }
  }
  ASSERT_TRUE(changed) << "the Cornell box has no emissive material";
  EXPECT_NE(hashLevel(loadCornell()), hashLevel(dimmer));
}

TEST(LevelHash, ChangesWithOneVertex) {
  const Scene base = loadCornell();
  Scene moved = base;
  ASSERT_FALSE(moved.meshes.empty());
  ASSERT_FALSE(moved.meshes[0].positions.empty());
  // one ulp
  moved.meshes[0].positions[0].y = std::nextafter(moved.meshes[0].positions[0].y, 10.0f);
  EXPECT_NE(hashLevel(base), hashLevel(moved));
  Scene dynamic = base;
  ASSERT_FALSE(dynamic.instances.empty());
  dynamic.instances[0].dynamic = !dynamic.instances[0].dynamic;
  EXPECT_NE(hashLevel(base), hashLevel(dynamic));
  Scene sunny = base;
  sunny.sun.enabled = true;
  sunny.sun.illuminance_lux = 1e5f;
  EXPECT_NE(hashLevel(base), hashLevel(sunny));
}

TEST(LevelHash, UnchangedByNamesWarningsAndCameraPaths) {
  const Scene base = loadCornell();
  Scene renamed = base;
  ASSERT_FALSE(renamed.nodes.empty());
  renamed.nodes[0].name += "_renamed";
  EXPECT_EQ(hashLevel(base), hashLevel(renamed));
  if (!renamed.meshes.empty()) renamed.meshes[0].name = "another";
  if (!renamed.materials.empty()) renamed.materials[0].name = "another";
  renamed.warnings.push_back("a warning");
  renamed.source_path = "/elsewhere/level.json";
  CameraPath path;
  path.name = "tour";
  path.keys.push_back({});
  renamed.camera_paths.push_back(path);
  EXPECT_EQ(hashLevel(base), hashLevel(renamed));
}

}  // namespace
}  // namespace svit

// A scene built in code, written with writeGltf and loaded back, keeps its
// geometry, materials, hierarchy, transforms, dynamic marks and lights.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "svit/level.h"

namespace svit {
namespace {

Mesh quadMesh(const std::string& name, uint32_t material) {
  Mesh mesh;
  mesh.name = name;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};
  mesh.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  mesh.uv1 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.triangle_material = {material, material};
  return mesh;
}

Scene builtScene() {
  Scene scene;
  Material grey;
  grey.name = "grey";
  grey.base_color = {0.5f, 0.5f, 0.5f};
  Material lamp;
  lamp.name = "lamp";
  lamp.base_color = {0.8f, 0.8f, 0.8f};
  lamp.emissive_luminance = {200.0f, 150.0f, 100.0f};  // > 1: needs emissive_strength
  lamp.double_sided = true;
  scene.materials = {grey, lamp};
  scene.meshes = {quadMesh("floor", 0), quadMesh("panel", 1)};

  Node root;
  root.name = "root";
  root.children = {1, 2};
  Node floor;
  floor.name = "floor";
  floor.parent = 0;
  floor.mesh = 0;
  floor.scale = {4, 1, 4};
  floor.parent_from_node.m = {4, 0, 0, 0, 0, 1, 0, 0, 0, 0, 4, 0, 0, 0, 0, 1};
  Node mover;
  mover.name = "mover";
  mover.parent = 0;
  mover.mesh = 1;
  mover.dynamic = true;
  mover.has_trs = false;  // written as a matrix
  mover.parent_from_node.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5f, 2, -1, 1};
  mover.children = {3};
  Node spot_node;
  spot_node.name = "spot";
  spot_node.parent = 2;
  spot_node.translation = {0, 1, 0};
  spot_node.parent_from_node.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1};
  scene.nodes = {root, floor, mover, spot_node};
  Light spot;
  spot.name = "spot";
  spot.type = LightType::kSpot;
  spot.intensity = 300;
  spot.inner_cone_rad = 0.2f;
  spot.outer_cone_rad = 0.6f;
  spot.color = {1, 0.9f, 0.8f};
  spot.node = 3;
  scene.lights = {spot};
  return scene;
}

TEST(RoundTrip, WrittenSceneLoadsBackUnchanged) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "svit_round_trip.gltf").string();
  const Scene original = builtScene();
  ASSERT_TRUE(writeGltf(original, path).ok());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  Expected<Scene> loaded = loadLevel(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();

  ASSERT_EQ(loaded->meshes.size(), 2u);
  for (size_t m = 0; m < 2; ++m) {
    const Mesh& a = original.meshes[m];
    const Mesh& b = loaded->meshes[m];
    EXPECT_EQ(b.name, a.name);
    ASSERT_EQ(b.indices, a.indices);
    ASSERT_EQ(b.positions.size(), a.positions.size());
    for (size_t v = 0; v < a.positions.size(); ++v) {
      EXPECT_EQ(b.positions[v].x, a.positions[v].x);
      EXPECT_EQ(b.positions[v].z, a.positions[v].z);
      EXPECT_EQ(b.normals[v].y, a.normals[v].y);
      EXPECT_EQ(b.uv1[v].y, a.uv1[v].y);
    }
    EXPECT_EQ(b.triangle_material, a.triangle_material);
  }
  ASSERT_EQ(loaded->materials.size(), 2u);
  EXPECT_FLOAT_EQ(loaded->materials[0].base_color.g, 0.5f);
  EXPECT_NEAR(loaded->materials[1].emissive_luminance.r, 200.0f, 1e-3f);
  EXPECT_NEAR(loaded->materials[1].emissive_luminance.b, 100.0f, 1e-3f);
  EXPECT_TRUE(loaded->materials[1].double_sided);
  EXPECT_NEAR(loaded->meshes[1].triangle_emission[0].g, 150.0f, 1e-3f);

  ASSERT_EQ(loaded->nodes.size(), 4u);
  EXPECT_FALSE(loaded->nodes[1].dynamic);
  EXPECT_TRUE(loaded->nodes[2].dynamic);
  EXPECT_TRUE(loaded->nodes[3].dynamic);  // inherited
  ASSERT_EQ(loaded->instances.size(), 2u);
  EXPECT_FLOAT_EQ(loaded->instances[0].world_from_object.m[0], 4.0f);
  EXPECT_TRUE(loaded->instances[1].dynamic);
  EXPECT_FLOAT_EQ(loaded->instances[1].world_from_object.m[13], 2.0f);

  ASSERT_EQ(loaded->lights.size(), 1u);
  const Light& spot = loaded->lights[0];
  EXPECT_EQ(spot.type, LightType::kSpot);
  EXPECT_FLOAT_EQ(spot.intensity, 300.0f);
  EXPECT_FLOAT_EQ(spot.outer_cone_rad, 0.6f);
  EXPECT_TRUE(spot.dynamic);  // hangs on a dynamic node
  // World position: mover (0.5, 2, -1) + spot (0, 1, 0); glTF lights shine down -Z.
  EXPECT_FLOAT_EQ(spot.position.x, 0.5f);
  EXPECT_FLOAT_EQ(spot.position.y, 3.0f);
  EXPECT_FLOAT_EQ(spot.direction.z, -1.0f);
  std::filesystem::remove(path);
}

TEST(RoundTrip, FailedWriteLeavesThePreviousFile) {
  const std::string dir = (std::filesystem::temp_directory_path() / "svit_round_trip_dir").string();
  std::filesystem::create_directories(dir);
  // The target is a directory: rename must fail and nothing is replaced.
  const Status status = writeGltf(builtScene(), dir);
  EXPECT_FALSE(status.ok());
  EXPECT_TRUE(std::filesystem::is_directory(dir));
  EXPECT_FALSE(std::filesystem::exists(dir + ".tmp"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace svit

// level.json loading (docs/level-format.md) on the small files in
// tests/data/ (written by tests/data/make_test_data.py). Every level names
// good_quad.gltf (one 2 m^2 quad, node 'Quad') relative to itself, except
// missing_gltf.level.json. Bad fields must fail naming the level file and the
// field; the checked substrings are short and case-insensitive on purpose.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene_test_util.h"
#include "svit/bake_file.h"
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
  EXPECT_TRUE(
      messageHas(status, {"negative_level_light.level.json", "lights[0].intensity_cd", "-3"}));
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

// ---- objects, node indices, exclude, lights on nodes ----
// These levels are written by the test into its own temporary directory and
// name the glTFs of tests/data by absolute path.

std::string writeLevel(const std::string& json) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) /
      ("svit_level_json_" + std::string(info->test_suite_name()) + "_" + info->name());
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "level.json").string();
  std::ofstream(path) << json;
  return path;
}

// A level over good_quad.gltf (node 'Quad') with `fields` added at the top level.
std::string quadLevel(const std::string& fields) {
  return writeLevel("{\"gltf\": \"" + dataPath("good_quad.gltf") + "\", " + fields + "}");
}

Vec3 worldPoint(const Mat4& m, const Vec3& p) {
  return {m.m[0] * p.x + m.m[4] * p.y + m.m[8] * p.z + m.m[12],
          m.m[1] * p.x + m.m[5] * p.y + m.m[9] * p.z + m.m[13],
          m.m[2] * p.x + m.m[6] * p.y + m.m[10] * p.z + m.m[14]};
}

const Instance* instanceOf(const Scene& scene, int node) {
  for (const Instance& instance : scene.instances) {
    if (instance.node == node) return &instance;
  }
  return nullptr;
}

// Every triangle of a convex mesh centred on the origin faces outward, its
// vertex normals are unit length, and its area is `area_m2` within `tolerance`.
void expectClosedOutward(const Mesh& mesh, double area_m2, double tolerance) {
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 c = test::faceCross(mesh, t);
    const Vec3 a = test::corner(mesh, t, 0), b = test::corner(mesh, t, 1),
               d = test::corner(mesh, t, 2);
    const Vec3 centroid{a.x + b.x + d.x, a.y + b.y + d.y, a.z + b.z + d.z};
    ASSERT_GT(test::dot(c, centroid), 0.0f) << mesh.name << " triangle " << t << " faces inward";
  }
  for (const Vec3& n : mesh.normals) ASSERT_NEAR(test::length(n), 1.0f, 1e-5f);
  EXPECT_NEAR(test::meshArea(mesh), area_m2, tolerance) << mesh.name;
}

TEST(LevelJsonObjects, SphereAndBoxBecomeMeshesMaterialsNodesAndInstances) {
  // A 90-degree turn about +Y: (x, y, z) -> (z, y, -x).
  const std::string path = quadLevel(R"(
    "objects": [
      {"name": "ball", "shape": "sphere", "radius_m": 0.5, "segments": 8,
       "albedo": [0.7, 0.2, 0.1], "translation": [1, 0.5, -2], "dynamic": true},
      {"name": "lamp_box", "shape": "box", "size_m": [0.2, 0.4, 0.6], "albedo": 0.3,
       "emissive_luminance": [100, 90, 80], "double_sided": true,
       "translation": [0, 2, 0], "rotation": [0, 0.70710678, 0, 0.70710678]}
    ],
    "lights": [{"name": "carried", "type": "point", "node": "lamp_box",
                "position": [0.1, 0, 0], "intensity_cd": 30}],
    "paths": [{"node": "lamp_box", "keys": [{"t_s": 0}, {"t_s": 2, "translation": [1, 2, 0]}]}])");
  Expected<Scene> result = loadLevel(path);
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  EXPECT_TRUE(scene.warnings.empty()) << test::joinLines(scene.warnings);
  ASSERT_EQ(scene.meshes.size(), 3u);  // the quad, the ball, the box

  // Sphere, 8 segments: 8 around x 4 from pole to pole = 2 x 8 x 3 triangles.
  const int ball = scene.findNode("ball");
  ASSERT_GE(ball, 0);
  const Node& ball_node = scene.nodes[size_t(ball)];
  ASSERT_GE(ball_node.mesh, 0);
  const Mesh& sphere = scene.meshes[size_t(ball_node.mesh)];
  EXPECT_EQ(sphere.triangleCount(), 48u);
  // The polyhedron's area is below 4 pi r^2 = 3.14 m^2: summing its 48
  // triangles in double (corners at polar angles k pi/4, azimuths i pi/4)
  // gives 2.75336 m^2; 1e-5 covers float corners.
  expectClosedOutward(sphere, 2.75336, 1e-5);
  for (const Vec3& p : sphere.positions) EXPECT_NEAR(test::length(p), 0.5f, 1e-6f);
  const Material& red = scene.materials[sphere.triangle_material.at(0)];
  EXPECT_EQ(red.name, "ball");
  EXPECT_TRUE(test::rgbNear(red.base_color, {0.7f, 0.2f, 0.1f}, kRelative));
  EXPECT_TRUE(test::rgbNear(red.emissive_luminance, {0, 0, 0}, 0));
  EXPECT_FALSE(red.double_sided);
  ASSERT_EQ(sphere.triangle_albedo.size(), 48u);
  EXPECT_TRUE(test::rgbNear(sphere.triangle_albedo[47], {0.7f, 0.2f, 0.1f}, kRelative));
  ASSERT_EQ(sphere.triangle_emission.size(), 48u);
  ASSERT_EQ(sphere.triangle_source.size(), 48u);
  const Instance* ball_instance = instanceOf(scene, ball);
  ASSERT_NE(ball_instance, nullptr);
  EXPECT_TRUE(ball_instance->dynamic);
  EXPECT_TRUE(test::vecNear(worldPoint(ball_instance->world_from_object, {0, 0, 0}), {1, 0.5f, -2},
                            kRelative));

  // Box: 12 triangles, area 2 (0.2 x 0.4 + 0.4 x 0.6 + 0.6 x 0.2) = 0.88 m^2,
  // static (no dynamic field) until the path marked it.
  const int box = scene.findNode("lamp_box");
  ASSERT_GE(box, 0);
  const Mesh& cuboid = scene.meshes[size_t(scene.nodes[size_t(box)].mesh)];
  EXPECT_EQ(cuboid.triangleCount(), 12u);
  expectClosedOutward(cuboid, 0.88, 1e-6);
  const Material& glow = scene.materials[cuboid.triangle_material.at(0)];
  EXPECT_TRUE(test::rgbNear(glow.base_color, {0.3f, 0.3f, 0.3f}, kRelative));
  EXPECT_TRUE(test::rgbNear(glow.emissive_luminance, {100, 90, 80}, 100 * kRelative));
  EXPECT_TRUE(glow.double_sided);
  EXPECT_TRUE(test::rgbNear(cuboid.triangle_emission[0], {100, 90, 80}, 100 * kRelative));
  const Instance* box_instance = instanceOf(scene, box);
  ASSERT_NE(box_instance, nullptr);
  EXPECT_TRUE(box_instance->dynamic);
  // The box's local +x corner (0.1, 0, 0) lands at world (0, 2, -0.1).
  EXPECT_TRUE(test::vecNear(worldPoint(box_instance->world_from_object, {0.1f, 0, 0}),
                            {0, 2, -0.1f}, 1e-6f));

  // The path names the object.
  ASSERT_EQ(scene.object_paths.size(), 1u);
  EXPECT_EQ(scene.object_paths[0].node, box);

  // The light hangs on the box: offset (0.1, 0, 0) turned with it, and it
  // moves with it, so it is a runtime light.
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light& carried = scene.lights[0];
  EXPECT_EQ(carried.name, "carried");
  ASSERT_GE(carried.node, 0);
  EXPECT_EQ(scene.nodes[size_t(carried.node)].parent, box);
  EXPECT_TRUE(test::vecNear(carried.position, {0, 2, -0.1f}, 1e-6f));
  EXPECT_TRUE(carried.dynamic);

  // The quad is untouched and static.
  const Instance* quad = instanceOf(scene, scene.findNode("Quad"));
  ASSERT_NE(quad, nullptr);
  EXPECT_FALSE(quad->dynamic);
}

TEST(LevelJsonObjects, SphereDefaultsTo24SegmentsAndGreyAlbedo) {
  const std::string path =
      quadLevel(R"("objects": [{"name": "b", "shape": "sphere", "radius_m": 2}])");
  Expected<Scene> result = loadLevel(path);
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Mesh& sphere = result->meshes[size_t(result->nodes[size_t(result->findNode("b"))].mesh)];
  EXPECT_EQ(sphere.triangleCount(), 2u * 24u * 11u);
  // 24 x 12 facets: within 2% of 4 pi r^2 = 50.3 m^2 (the polyhedron is smaller).
  expectClosedOutward(sphere, 4 * 3.14159265 * 4, 0.02 * 50.3);
  EXPECT_TRUE(test::rgbNear(result->materials[sphere.triangle_material[0]].base_color,
                            {0.8f, 0.8f, 0.8f}, kRelative));
  EXPECT_FALSE(instanceOf(*result, result->findNode("b"))->dynamic);
}

TEST(LevelJsonObjects, ObjectsAreInTheLevelHash) {
  // The bake depends on the object's geometry and material: the hash must see them.
  const std::string object =
      R"("objects": [{"name": "b", "shape": "box", "size_m": 1, "albedo": 0.5}])";
  Expected<Scene> a = loadLevel(quadLevel(object));
  ASSERT_TRUE(a.ok()) << describe(a.status());
  const uint64_t hash_a = hashLevel(*a);
  Expected<Scene> same = loadLevel(quadLevel(object));
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(hashLevel(*same), hash_a);
  Expected<Scene> bigger = loadLevel(
      quadLevel(R"("objects": [{"name": "b", "shape": "box", "size_m": 1.1, "albedo": 0.5}])"));
  ASSERT_TRUE(bigger.ok());
  EXPECT_NE(hashLevel(*bigger), hash_a);
  Expected<Scene> darker = loadLevel(
      quadLevel(R"("objects": [{"name": "b", "shape": "box", "size_m": 1, "albedo": 0.4}])"));
  ASSERT_TRUE(darker.ok());
  EXPECT_NE(hashLevel(*darker), hash_a);
  Expected<Scene> none = loadLevel(quadLevel(R"("description": "no objects")"));
  ASSERT_TRUE(none.ok());
  EXPECT_NE(hashLevel(*none), hash_a);
}

struct BadObject {
  const char* objects;  ///< JSON of the "objects" value
  std::vector<const char*> message;
};

TEST(LevelJsonObjects, EveryBadFieldIsAnErrorNamingIt) {
  // objects[0] is good; the second entry carries the defect.
  const std::string good = R"({"name": "ok", "shape": "sphere", "radius_m": 0.1}, )";
  const std::vector<BadObject> cases = {
      {R"({"name": "b", "shape": "sphere", "radius_m": 0})", {"objects[1].radius_m", "> 0"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": -1})", {"objects[1].radius_m", "> 0"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1e39})", {"objects[1].radius_m", "finite"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": "big"})", {"objects[1].radius_m", "number"}},
      {R"({"name": "b", "shape": "sphere"})", {"objects[1].radius_m", "required"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "segments": 3})",
       {"objects[1].segments", "[4, 256]"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "segments": 257})",
       {"objects[1].segments", "[4, 256]"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "segments": 8.5})",
       {"objects[1].segments", "integer"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "size_m": 1})",
       {"objects[1].size_m", "does not apply"}},
      {R"({"name": "b", "shape": "box", "size_m": [1, 0, 1]})", {"objects[1].size_m[1]", "> 0"}},
      {R"({"name": "b", "shape": "box", "size_m": [1, 1]})", {"objects[1].size_m", "3 numbers"}},
      {R"({"name": "b", "shape": "box", "size_m": [1, 1, -1e39]})",
       {"objects[1].size_m[2]", "finite"}},
      {R"({"name": "b", "shape": "box", "size_m": 1, "radius_m": 1})",
       {"objects[1].radius_m", "does not apply"}},
      {R"({"name": "b", "shape": "box", "size_m": 1, "segments": 8})",
       {"objects[1].segments", "does not apply"}},
      {R"({"name": "b", "shape": "cone", "radius_m": 1})", {"objects[1].shape", "cone"}},
      {R"({"name": "b", "radius_m": 1})", {"objects[1].shape", "required"}},
      {R"({"shape": "sphere", "radius_m": 1})", {"objects[1].name", "required"}},
      {R"({"name": "", "shape": "sphere", "radius_m": 1})", {"objects[1].name", "empty"}},
      {R"({"name": "Quad", "shape": "sphere", "radius_m": 1})",
       {"objects[1].name", "'Quad' already exists"}},
      {R"({"name": "ok", "shape": "sphere", "radius_m": 1})",
       {"objects[1].name", "'ok' already exists"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "albedo": [0.5, 1.5, 0.5]})",
       {"objects[1].albedo", "<= 1"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "albedo": -0.5})",
       {"objects[1].albedo", "negative"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "emissive_luminance": [-1, 0, 0]})",
       {"objects[1].emissive_luminance[0]", "negative"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "double_sided": "yes"})",
       {"objects[1].double_sided", "true or false"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "dynamic": 1})",
       {"objects[1].dynamic", "true or false"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "translation": [0, 1e39, 0]})",
       {"objects[1].translation[1]", "finite"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "rotation": [0, 0, 0, 0]})",
       {"objects[1].rotation", "zero length"}},
      {R"({"name": "b", "shape": "sphere", "radius_m": 1, "colour": [1, 0, 0]})",
       {"objects[1].colour", "unknown field"}},
      {R"("ball")", {"objects[1]", "JSON object"}},
  };
  for (const BadObject& bad : cases) {
    SCOPED_TRACE(bad.objects);
    const std::string path = quadLevel("\"objects\": [" + good + bad.objects + "]");
    Expected<Scene> result = loadLevel(path);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidInput) << describe(result.status());
    EXPECT_TRUE(messageHas(result.status(), {"level.json"}));
    for (const char* part : bad.message) EXPECT_TRUE(messageHas(result.status(), {part}));
  }
  const Status not_array = loadLevel(quadLevel(R"("objects": {"name": "b"})")).status();
  EXPECT_TRUE(messageHas(not_array, {"objects", "must be an array"}));
}

TEST(LevelJsonNodes, NodesCanBeNamedByIndex) {
  // good_quad.gltf has one node, 0 ('Quad').
  Expected<Scene> good = loadLevel(quadLevel(R"("dynamic": [0])"));
  ASSERT_TRUE(good.ok()) << describe(good.status());
  EXPECT_TRUE(good->nodes[0].dynamic);
  EXPECT_TRUE(instanceOf(*good, 0)->dynamic);

  const Status past_end = loadLevel(quadLevel(R"("dynamic": [1])")).status();
  EXPECT_EQ(past_end.code(), StatusCode::kNotFound) << describe(past_end);
  EXPECT_TRUE(messageHas(past_end, {"dynamic[0]", "no node 1", "good_quad.gltf", "1 nodes"}));
  const Status negative =
      loadLevel(quadLevel(R"("paths": [{"node": -1, "animation": 0}])")).status();
  EXPECT_EQ(negative.code(), StatusCode::kNotFound) << describe(negative);
  EXPECT_TRUE(messageHas(negative, {"paths[0].node", "no node -1"}));
  // Indices count the glTF's nodes only: an object is named by its name.
  const Status object =
      loadLevel(quadLevel(R"("objects": [{"name": "b", "shape": "box", "size_m": 1}],
                                               "dynamic": [1])"))
          .status();
  EXPECT_EQ(object.code(), StatusCode::kNotFound) << describe(object);
  EXPECT_TRUE(messageHas(object, {"dynamic[0]", "no node 1"}));
  const Status fraction = loadLevel(quadLevel(R"("dynamic": [0.5])")).status();
  EXPECT_EQ(fraction.code(), StatusCode::kInvalidInput) << describe(fraction);
  EXPECT_TRUE(messageHas(fraction, {"dynamic[0]", "node name or a node index"}));
}

TEST(LevelJsonNodes, ExcludeLeavesOutASubtree) {
  // dynamic_subtree.gltf: Mover (dynamic) -> Arm (mesh) -> Hand (mesh); Floor (mesh).
  const std::string gltf = "{\"gltf\": \"" + dataPath("dynamic_subtree.gltf") + "\", ";
  Expected<Scene> result = loadLevel(writeLevel(gltf + R"("exclude": ["Arm"]})"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  ASSERT_EQ(result->instances.size(), 1u);
  EXPECT_EQ(result->instances[0].node, result->findNode("Floor"));
  // By index, too; the level hash sees the difference.
  Expected<Scene> by_index = loadLevel(writeLevel(gltf + R"("exclude": [1]})"));
  ASSERT_TRUE(by_index.ok()) << describe(by_index.status());
  EXPECT_EQ(hashLevel(*by_index), hashLevel(*result));
  Expected<Scene> whole = loadLevel(writeLevel(gltf + R"("description": "all"})"));
  ASSERT_TRUE(whole.ok());
  EXPECT_EQ(whole->instances.size(), 3u);
  EXPECT_NE(hashLevel(*whole), hashLevel(*result));

  // Nothing may name an excluded node or its subtree.
  const Status hand =
      loadLevel(writeLevel(gltf + R"("exclude": ["Arm"], "dynamic": ["Hand"]})")).status();
  EXPECT_EQ(hand.code(), StatusCode::kInvalidInput) << describe(hand);
  EXPECT_TRUE(messageHas(hand, {"dynamic[0]", "Hand", "exclude"}));
  const Status missing = loadLevel(writeLevel(gltf + R"("exclude": ["Leg"]})")).status();
  EXPECT_EQ(missing.code(), StatusCode::kNotFound) << describe(missing);
  EXPECT_TRUE(messageHas(missing, {"exclude[0]", "Leg"}));
  // Excluding everything leaves nothing to light.
  const Status empty = loadLevel(writeLevel(gltf + R"("exclude": ["Mover", "Floor"]})")).status();
  EXPECT_TRUE(messageHas(empty, {"no triangles"}));
}

TEST(LevelJsonNodes, LightOnAnUnknownNodeIsAnError) {
  const Status status =
      loadLevel(
          quadLevel(
              R"("lights": [{"type": "point", "position": [0, 1, 0], "intensity_cd": 1, "node": "Lantern"}])"))
          .status();
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << describe(status);
  EXPECT_TRUE(messageHas(status, {"level.json", "lights[0].node", "Lantern"}));
}

TEST(LevelJsonNodes, SpotOnAStaticNodeKeepsItsDirectionAndStaysBaked) {
  // A spot hung on the quad's node (identity transform) shining along -Y, and
  // one shining along +Z (the half-turn case of the hanging rotation).
  Expected<Scene> result = loadLevel(quadLevel(R"("lights": [
      {"type": "spot", "node": "Quad", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity_cd": 10},
      {"type": "spot", "node": "Quad", "position": [0, 2, 0], "direction": [0, 0, 1], "intensity_cd": 10}])"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  ASSERT_EQ(result->lights.size(), 2u);
  EXPECT_TRUE(test::vecNear(result->lights[0].position, {0, 2, 0}, 1e-6f));
  EXPECT_TRUE(test::vecNear(result->lights[0].direction, {0, -1, 0}, 1e-6f));
  EXPECT_FALSE(result->lights[0].dynamic);
  EXPECT_TRUE(test::vecNear(result->lights[1].direction, {0, 0, 1}, 1e-6f));
}

}  // namespace
}  // namespace svit

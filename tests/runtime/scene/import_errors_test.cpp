// glTF import of the small files in tests/data/ (written by
// tests/data/make_test_data.py; tests/data/README.md lists the defects).
// Bad files must fail with the right StatusCode and a message naming the file
// and the element; degenerate-but-legal input must load, skip what it has to,
// and say so in Scene::warnings and Scene::counters.
//
// The substrings checked are deliberately short and case-insensitive: the
// importer owns the exact wording, these tests own what it must mention.
// Geometry of the files (see the script): "the quad" is 2 m x 1 m in the
// y = 0 plane, vertices (-1,0,0.5) (1,0,0.5) (1,0,-0.5) (-1,0,-0.5),
// triangles (0,1,2) (0,2,3), facing +Y; accessor 0 = POSITION,
// 1 = NORMAL, 2 = indices; bufferView 0 = indices, 1 = POSITION, 2 = NORMAL.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "scene_test_util.h"
#include "svit/level.h"
#include "svit/scene.h"
#include "svit/scene_summary.h"
#include "svit/status.h"

namespace svit {
namespace {

using test::dataPath;
using test::describe;
using test::messageHas;
using test::someWarningHas;

// Values that the files store exactly as floats (0.5, 1, 10, ...) come back
// exactly; 1e-6 only absorbs a different but equivalent evaluation order.
constexpr float kExact = 1e-6f;
// Normals computed by the importer from float positions with O(1) edges:
// a normalised cross product carries a few ulp (~1e-7) of rounding; 1e-5
// leaves two orders of margin.
constexpr float kDerived = 1e-5f;

// Loads a file that must fail; the caller checks code and message.
Status loadFailure(const std::string& name) {
  Expected<Scene> result = loadLevel(dataPath(name));
  if (result.ok()) {
    ADD_FAILURE() << name << " loaded without error";
    return Status::okStatus();
  }
  return result.status();
}

// ---------------------------------------------------------------------------
// Baselines

TEST(ImportErrors, GoodQuadLoads) {
  const std::string path = dataPath("good_quad.gltf");
  Expected<Scene> result = loadLevel(path);
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;

  EXPECT_EQ(scene.source_path, path);
  EXPECT_EQ(scene.gltf_path, path);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.name, "Quad");
  ASSERT_EQ(mesh.triangleCount(), 2u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (const Vec3& n : mesh.normals) EXPECT_TRUE(test::vecNear(n, {0, 1, 0}, kExact));
  EXPECT_NEAR(test::meshArea(mesh), 2.0, kExact);  // 2 m x 1 m
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_GT(test::faceCross(mesh, t).y, 0.0f)
        << "triangle " << t << " must stay counter-clockwise from +Y";
  }
  ASSERT_EQ(mesh.triangle_material.size(), 2u);
  ASSERT_EQ(mesh.triangle_albedo.size(), 2u);
  ASSERT_EQ(mesh.triangle_emission.size(), 2u);
  ASSERT_EQ(mesh.triangle_source.size(), 2u);
  for (uint32_t t = 0; t < 2; ++t) {
    EXPECT_EQ(mesh.triangle_material[t], 0u);
    EXPECT_TRUE(test::rgbNear(mesh.triangle_albedo[t], {0.5f, 0.5f, 0.5f}, kExact));
    EXPECT_TRUE(test::rgbNear(mesh.triangle_emission[t], {0, 0, 0}, kExact));
    EXPECT_EQ(mesh.triangle_source[t].primitive, 0u);
    EXPECT_EQ(mesh.triangle_source[t].triangle, t);
  }

  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_TRUE(test::rgbNear(scene.materials[0].base_color, {0.5f, 0.5f, 0.5f}, kExact));
  EXPECT_EQ(scene.materials[0].base_color_texture.texture, -1);

  const int quad = scene.findNode("Quad");
  ASSERT_GE(quad, 0);
  EXPECT_EQ(scene.nodes[quad].mesh, 0);
  EXPECT_FALSE(scene.nodes[quad].dynamic);
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].node, quad);
  EXPECT_EQ(scene.instances[0].mesh, 0);
  EXPECT_FALSE(scene.instances[0].dynamic);
  EXPECT_TRUE(scene.lights.empty());
  EXPECT_FALSE(scene.sun.enabled);
  EXPECT_EQ(scene.sky.model, SkyModel::kNone);

  EXPECT_TRUE(scene.warnings.empty()) << test::joinLines(scene.warnings);
  EXPECT_EQ(scene.counters.zero_area_triangles, 0u);
  EXPECT_EQ(scene.counters.skipped_point_line_primitives, 0u);
  EXPECT_EQ(scene.counters.missing_textures, 0u);
  EXPECT_EQ(scene.counters.meshes_with_generated_normals, 0u);
  EXPECT_EQ(scene.counters.repaired_normals, 0u);
  EXPECT_EQ(scene.counters.degenerate_instances, 0u);
}

TEST(ImportErrors, GoodEmissiveQuadHasAnalyticFlux) {
  Expected<Scene> result = loadLevel(dataPath("good_emissive_quad.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;

  // emissiveFactor (1,1,1) x KHR_materials_emissive_strength 10 = 10 cd/m2.
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_TRUE(test::rgbNear(scene.materials[0].emissive_luminance, {10, 10, 10}, kExact));
  EXPECT_FALSE(scene.materials[0].double_sided);
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.meshes[0].triangle_emission.size(), 2u);
  for (const Rgb& e : scene.meshes[0].triangle_emission)
    EXPECT_TRUE(test::rgbNear(e, {10, 10, 10}, kExact));
  EXPECT_TRUE(scene.warnings.empty()) << test::joinLines(scene.warnings);

  // Single-sided Lambertian emitter: flux = pi x L x area = pi x 10 x 2 m^2.
  // Inputs are exact floats; the sum carries float rounding (~1e-7
  // relative), so a 1e-5 relative tolerance has ample margin.
  const SceneSummary summary = summarize(scene);
  const double expected_lm = std::numbers::pi * 10.0 * 2.0;
  EXPECT_EQ(summary.emissive_triangles, 2u);
  EXPECT_NEAR(summary.emitted_flux_lm, expected_lm, expected_lm * 1e-5);
  EXPECT_NEAR(summary.emitted_flux_rgb.r, expected_lm, expected_lm * 1e-5);
  EXPECT_NEAR(summary.emitted_flux_rgb.g, expected_lm, expected_lm * 1e-5);
  EXPECT_NEAR(summary.emitted_flux_rgb.b, expected_lm, expected_lm * 1e-5);
}

// ---------------------------------------------------------------------------
// Unreadable files

TEST(ImportErrors, TruncatedGltf) {
  // JSON cut in the middle: there is no element to name, only the file.
  const Status status = loadFailure("truncated.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"truncated.gltf"}));
}

TEST(ImportErrors, BadJson) {
  // Missing comma after "scene": 0; the parser stops on line 7.
  const Status status = loadFailure("bad_json.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"bad_json.gltf", "line 7"}));
}

TEST(ImportErrors, TruncatedGlb) {
  // The GLB header claims 980 bytes; the file has 926.
  const Status status = loadFailure("truncated.glb");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"truncated.glb", "length"}));
}

TEST(ImportErrors, MissingBufferFile) {
  const Status status = loadFailure("missing_buffer_file.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << describe(status);
  EXPECT_TRUE(messageHas(status, {"missing_buffer_file.gltf", "buffer", "does_not_exist.bin"}));
}

TEST(ImportErrors, ShortBuffer) {
  // byteLength 216, but the data URI decodes to 108 bytes.
  const Status status = loadFailure("short_buffer.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"short_buffer.gltf", "buffer"}));
}

// ---------------------------------------------------------------------------
// Out-of-range references

TEST(ImportErrors, IndexOutOfRange) {
  // Primitive 0 triangle 1 is (0, 2, 9) on a 4-vertex mesh.
  const Status status = loadFailure("index_out_of_range.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"index_out_of_range.gltf", "Quad", "primitive 0", "index 9"}));
}

TEST(ImportErrors, AccessorOutOfBounds) {
  // Accessor 2 (indices) claims 12 x 2 bytes in bufferView 0 of 12 bytes.
  // The overrun stays inside the buffer, so only a per-view check sees it
  // (reading on would yield garbage indices such as 49024, i.e. the wrong
  // error).
  const Status status = loadFailure("accessor_out_of_bounds.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"accessor_out_of_bounds.gltf", "accessor 2", "bufferView"}));
}

TEST(ImportErrors, BufferViewOutOfBounds) {
  // bufferView 2: byteOffset 60 + byteLength 96 > 108 bytes in buffer 0.
  const Status status = loadFailure("buffer_view_out_of_bounds.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"buffer_view_out_of_bounds.gltf", "bufferView 2"}));
}

// ---------------------------------------------------------------------------
// Non-finite data

TEST(ImportErrors, NanPosition) {
  // POSITION of vertex 2 has x = NaN.
  const Status status = loadFailure("nan_position.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"nan_position.gltf", "Quad", "position"}));
}

TEST(ImportErrors, InfNormal) {
  // NORMAL of vertex 1 has y = +Inf.
  const Status status = loadFailure("inf_normal.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"inf_normal.gltf", "Quad", "normal"}));
}

// ---------------------------------------------------------------------------
// Lights and extensions

TEST(ImportErrors, NegativeLightIntensity) {
  // KHR_lights_punctual light 0 'Lamp', point, intensity -5.
  const Status status = loadFailure("negative_light_intensity.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"negative_light_intensity.gltf", "light", "intensity", "-5"}));
}

TEST(ImportErrors, NonFiniteLightIntensity) {
  // Light 0 'Lamp' has intensity 1e300: a finite double that is +Inf as the
  // float Light::intensity (JSON has no NaN/Inf literal; see the script for
  // why neither 1e999 nor "NaN" can express this case).
  const Status status = loadFailure("nan_light_intensity.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"nan_light_intensity.gltf", "light", "intensity"}));
}

TEST(ImportErrors, NonNumericLightIntensity) {
  // Light 0 'Lamp' has "intensity": "NaN" (a string). tinygltf's parsed
  // light silently keeps the default 1.0 for it; the importer must not.
  const Status status = loadFailure("nonnumeric_light_intensity.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"nonnumeric_light_intensity.gltf", "light", "intensity"}));
}

TEST(ImportErrors, BadSpotCone) {
  // Light 0 'Spot': innerConeAngle 0.6 > outerConeAngle 0.4.
  const Status status = loadFailure("bad_spot_cone.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"bad_spot_cone.gltf", "light", "cone"}));
}

TEST(ImportErrors, UnsupportedRequiredExtension) {
  const Status status = loadFailure("unsupported_required_extension.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kUnsupported) << describe(status);
  EXPECT_TRUE(
      messageHas(status, {"unsupported_required_extension.gltf", "KHR_draco_mesh_compression"}));
}

TEST(ImportErrors, EmptySceneHasNoTriangles) {
  // Valid glTF (nodes Root and Child) without meshes: a level with no
  // triangles is an error (svit/level.h).
  const Status status = loadFailure("empty_scene.gltf");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << describe(status);
  EXPECT_TRUE(messageHas(status, {"empty_scene.gltf", "triangle"}));
}

// ---------------------------------------------------------------------------
// Degenerate but legal: loads, skips, warns

TEST(ImportErrors, ZeroAreaFaceIsSkippedWithWarning) {
  // Triangles 0 and 1 are the quad; triangle 2 = (1, 2, 4), where vertex 4
  // repeats vertex 1's position (distinct indices, zero area).
  Expected<Scene> result = loadLevel(dataPath("zero_area_face.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(scene.counters.zero_area_triangles, 1u);
  EXPECT_TRUE(someWarningHas(scene.warnings, {"Quad", "triangle 2"}));
  // The survivors keep their source numbering.
  ASSERT_EQ(mesh.triangle_source.size(), 2u);
  EXPECT_EQ(mesh.triangle_source[0].triangle, 0u);
  EXPECT_EQ(mesh.triangle_source[1].triangle, 1u);
  EXPECT_NEAR(test::meshArea(mesh), 2.0, kExact);
}

TEST(ImportErrors, MissingTextureUsesFactorWithWarning) {
  // baseColorTexture -> image no_such_texture.png, not shipped.
  Expected<Scene> result = loadLevel(dataPath("missing_texture.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  EXPECT_EQ(scene.counters.missing_textures, 1u);
  EXPECT_TRUE(someWarningHas(scene.warnings, {"no_such_texture.png"}));
  ASSERT_EQ(scene.materials.size(), 1u);
  const Material& material = scene.materials[0];
  EXPECT_EQ(material.base_color_texture.texture, -1);
  EXPECT_TRUE(test::rgbNear(material.base_color, {0.8f, 0.2f, 0.1f}, kExact));
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.meshes[0].triangleCount(), 2u);
  ASSERT_EQ(scene.meshes[0].triangle_albedo.size(), 2u);
  for (const Rgb& albedo : scene.meshes[0].triangle_albedo) {
    EXPECT_TRUE(test::rgbNear(albedo, {0.8f, 0.2f, 0.1f}, kExact));
  }
}

TEST(ImportErrors, TriangleStripIsConverted) {
  // Non-indexed strip of 4 vertices -> (0,1,2) (1,3,2), both facing +Y.
  Expected<Scene> result = loadLevel(dataPath("triangle_strip.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  ASSERT_EQ(result->meshes.size(), 1u);
  const Mesh& mesh = result->meshes[0];
  ASSERT_EQ(mesh.triangleCount(), 2u);
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    // Winding must alternate correctly: every face keeps the +Y side front.
    EXPECT_TRUE(test::vecNear(test::normalize(test::faceCross(mesh, t)), {0, 1, 0}, kDerived))
        << "triangle " << t;
  }
  EXPECT_NEAR(test::meshArea(mesh), 2.0, kExact);
  ASSERT_EQ(mesh.triangle_source.size(), 2u);
  EXPECT_EQ(mesh.triangle_source[1].triangle, 1u);
}

TEST(ImportErrors, TriangleFanIsConverted) {
  // Indexed fan of 5 vertices around (0,0,0) -> 3 triangles facing +Y, 1.5 m^2.
  Expected<Scene> result = loadLevel(dataPath("triangle_fan.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  ASSERT_EQ(result->meshes.size(), 1u);
  const Mesh& mesh = result->meshes[0];
  ASSERT_EQ(mesh.triangleCount(), 3u);
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_TRUE(test::vecNear(test::normalize(test::faceCross(mesh, t)), {0, 1, 0}, kDerived))
        << "triangle " << t;
  }
  EXPECT_NEAR(test::meshArea(mesh), 1.5, kExact);
  ASSERT_EQ(mesh.triangle_source.size(), 3u);
  EXPECT_EQ(mesh.triangle_source[2].triangle, 2u);
}

TEST(ImportErrors, PointsAndLinesAreSkippedWithWarning) {
  // Mesh 'Quad': primitive 0 triangles, primitive 1 POINTS, primitive 2 LINES.
  Expected<Scene> result = loadLevel(dataPath("points_and_lines.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].triangleCount(), 2u);
  for (const TriangleSource& source : scene.meshes[0].triangle_source)
    EXPECT_EQ(source.primitive, 0u);
  EXPECT_EQ(scene.counters.skipped_point_line_primitives, 2u);
  EXPECT_TRUE(someWarningHas(scene.warnings, {"Quad", "primitive 1"}));
  EXPECT_TRUE(someWarningHas(scene.warnings, {"Quad", "primitive 2"}));
}

TEST(ImportErrors, MissingNormalsAreGeneratedFlat) {
  // The quad folded along v0-v2 (v2 lifted to y = 1), no NORMAL. Flat
  // normals (glTF spec) are (0,1,1)/sqrt2 and (-1,2,0)/sqrt5; smooth normals
  // at the shared corners would fail the perpendicularity check.
  Expected<Scene> result = loadLevel(dataPath("no_normals.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  EXPECT_EQ(scene.counters.meshes_with_generated_normals, 1u);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.triangleCount(), 2u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 face = test::normalize(test::faceCross(mesh, t));
    const Vec3 e1 = test::normalize(test::sub(test::corner(mesh, t, 1), test::corner(mesh, t, 0)));
    const Vec3 e2 = test::normalize(test::sub(test::corner(mesh, t, 2), test::corner(mesh, t, 0)));
    for (int k = 0; k < 3; ++k) {
      const Vec3& n = mesh.normals.at(mesh.indices[3 * t + static_cast<size_t>(k)]);
      EXPECT_NEAR(test::length(n), 1.0f, kDerived) << "triangle " << t << " corner " << k;
      EXPECT_NEAR(test::dot(n, e1), 0.0f, kDerived) << "triangle " << t << " corner " << k;
      EXPECT_NEAR(test::dot(n, e2), 0.0f, kDerived) << "triangle " << t << " corner " << k;
      EXPECT_GT(test::dot(n, face), 0.0f)
          << "triangle " << t << " corner " << k << " points backwards";
    }
  }
}

TEST(ImportErrors, DynamicMarkIsInheritedBySubtree) {
  // Mover (extras.svit.dynamic, T (0,1,0)) -> Arm (mesh, T (1,0,0)) ->
  // Hand (mesh, T (0,0,1)); Floor (mesh) is a static sibling root.
  Expected<Scene> result = loadLevel(dataPath("dynamic_subtree.gltf"));
  ASSERT_TRUE(result.ok()) << describe(result.status());
  const Scene& scene = *result;
  const int mover = scene.findNode("Mover");
  const int arm = scene.findNode("Arm");
  const int hand = scene.findNode("Hand");
  const int floor_node = scene.findNode("Floor");
  ASSERT_GE(mover, 0);
  ASSERT_GE(arm, 0);
  ASSERT_GE(hand, 0);
  ASSERT_GE(floor_node, 0);
  EXPECT_TRUE(scene.nodes[mover].dynamic);
  EXPECT_TRUE(scene.nodes[arm].dynamic);
  EXPECT_TRUE(scene.nodes[hand].dynamic);
  EXPECT_FALSE(scene.nodes[floor_node].dynamic);
  EXPECT_EQ(scene.nodes[arm].parent, mover);
  EXPECT_EQ(scene.nodes[hand].parent, arm);
  EXPECT_EQ(scene.nodes[floor_node].parent, -1);

  // world_from_node is column-major: translation in m[12..14].
  const Mat4& hand_world = scene.nodes[hand].world_from_node;
  EXPECT_TRUE(
      test::vecNear({hand_world.m[12], hand_world.m[13], hand_world.m[14]}, {1, 1, 1}, kExact));

  ASSERT_EQ(scene.instances.size(), 3u);
  for (const Instance& instance : scene.instances) {
    if (instance.node == arm || instance.node == hand) {
      EXPECT_TRUE(instance.dynamic) << scene.nodes[size_t(instance.node)].name;
    } else {
      EXPECT_EQ(instance.node, floor_node);
      EXPECT_FALSE(instance.dynamic);
    }
    EXPECT_EQ(instance.mesh, 0);
  }

  const SceneSummary summary = summarize(scene);
  EXPECT_EQ(summary.instances, 3u);
  EXPECT_EQ(summary.dynamic_instances, 2u);
  EXPECT_EQ(summary.dynamic_triangles, 4u);
  EXPECT_EQ(summary.static_triangles, 2u);
}

}  // namespace
}  // namespace svit

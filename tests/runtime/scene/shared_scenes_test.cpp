// Every level in ../shared/scenes, and the Cornell box copied from there into
// samples/levels/cornell, imports with the counts its SOURCE.txt states, and
// with physically sensible emitters. A scene missing from ../shared skips.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "shared_scene.h"
#include "svit/level.h"
#include "svit/scene_summary.h"

namespace svit {
namespace {

TEST(SharedScenes, CornellBoxOriginalHas36TrianglesAndOneEmissiveQuad) {
  Expected<Scene> scene = loadLevel(SVIT_CORNELL_GLTF);
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const SceneSummary summary = summarize(*scene);
  EXPECT_EQ(summary.static_triangles, 36u);
  EXPECT_EQ(summary.dynamic_triangles, 0u);
  EXPECT_EQ(summary.instances, 8u);
  EXPECT_EQ(summary.materials, 8u);
  EXPECT_EQ(summary.emissive_triangles, 2u);  // one quad
  // The light quad: emissiveFactor (1, .706, .235) x strength 17, single-sided:
  // flux = pi * Y * area. Its area, from the OBJ: 0.47 x 0.38 m (McGuire's
  // box, x in [-0.24, 0.23], z in [-0.22, 0.16]).
  const double y = 17.0 * (0.2126 * 1.0 + 0.7152 * 0.706 + 0.0722 * 0.235);
  const double expected = 3.14159265358979 * y * 0.47 * 0.38;
  EXPECT_NEAR(summary.emitted_flux_lm, expected, expected * 0.02);
  EXPECT_TRUE(scene->warnings.empty()) << scene->warnings.front();
  // Walls face inward: the floor's normals point up.
  const int floor = scene->findNode("floor");
  ASSERT_GE(floor, 0);
  const Mesh& mesh = scene->meshes[size_t(scene->nodes[size_t(floor)].mesh)];
  for (const Vec3& n : mesh.normals) EXPECT_GT(n.y, 0.99f);
}

TEST(SharedScenes, CornellBoxVinc3rKeepsAuthoredLightmapUvs) {
  SVIT_SKIP_WITHOUT_SHARED_SCENE("cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf");
  Expected<Scene> scene =
      loadLevel(test::sharedScenePath("cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf"));
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const SceneSummary summary = summarize(*scene);
  EXPECT_EQ(summary.static_triangles, 4410u);
  EXPECT_GT(summary.emissive_triangles, 0u);
  size_t meshes_with_uv1 = 0;
  for (const Mesh& mesh : scene->meshes) meshes_with_uv1 += mesh.uv1.empty() ? 0 : 1;
  EXPECT_GT(meshes_with_uv1, 0u);
  EXPECT_EQ(summary.textures, 2u);  // the two checker PNGs, decoded
}

TEST(SharedScenes, SponzaPlaces262087Triangles) {
  SVIT_SKIP_WITHOUT_SHARED_SCENE("sponza/Sponza.gltf");
  Expected<Scene> scene = loadLevel(test::sharedScenePath("sponza/Sponza.gltf"));
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  const SceneSummary summary = summarize(*scene);
  EXPECT_EQ(
      summary.static_triangles + summary.dynamic_triangles + scene->counters.zero_area_triangles,
      262087u)
      << "zero-area skipped: " << scene->counters.zero_area_triangles;
  EXPECT_EQ(summary.emissive_triangles, 0u);
  EXPECT_EQ(summary.point_lights + summary.spot_lights + summary.directional_lights, 0u);
  // Textured albedo: per-triangle means stay in [0, 1] and are not all white.
  size_t non_white = 0;
  for (const Mesh& mesh : scene->meshes) {
    for (const Rgb& a : mesh.triangle_albedo) {
      ASSERT_TRUE(a.r >= 0 && a.r <= 1 && a.g >= 0 && a.g <= 1 && a.b >= 0 && a.b <= 1);
      non_white += (a.r < 0.99f || a.g < 0.99f || a.b < 0.99f) ? 1 : 0;
    }
  }
  EXPECT_GT(non_white, 100000u);
}

TEST(SharedScenes, VirtualCityAnimationIsFound) {
  SVIT_SKIP_WITHOUT_SHARED_SCENE("virtual_city/VC.gltf");
  Expected<Scene> scene = loadLevel(test::sharedScenePath("virtual_city/VC.gltf"));
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  ASSERT_EQ(scene->animations.size(), 1u);
  EXPECT_EQ(scene->animations[0].tracks.size(), 73u);
  EXPECT_GT(scene->animations[0].duration_s, 0.0f);
  size_t animated = 0;
  for (const Node& node : scene->nodes) animated += node.animated ? 1 : 0;
  EXPECT_GT(animated, 0u);
  // Not marked dynamic in the bare glTF: baked at rest, with a warning.
  bool warned = false;
  for (const std::string& w : scene->warnings)
    warned = warned || w.find("is animated but static") != std::string::npos;
  EXPECT_TRUE(warned);
  const SceneSummary summary = summarize(*scene);
  EXPECT_EQ(summary.static_triangles + scene->counters.zero_area_triangles, 8383u);
}

}  // namespace
}  // namespace svit

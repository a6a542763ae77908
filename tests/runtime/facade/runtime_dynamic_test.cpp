// The runtime against independent answers: the Cornell box's tall box made
// dynamic and moved, against a bake with the box static at the new place;
// and a small emissive panel carried over a floor, against the analytic
// differential-area-to-parallel-rectangle form factor.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "baker/test_scenes.h"
#include "runtime/cornell_probes.h"
#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "svit/baked_surfaces.h"
#include "svit/runtime.h"

namespace svit {
namespace {

using namespace svit::test;

TEST(RuntimeDynamic, MovedTallBoxMatchesTheBakerAndMovingBackRestores) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
  Expected<std::unique_ptr<Runtime>> created = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  const ObjectId box = runtime.objectForNode(level.scene.findNode("tallBox"));
  ASSERT_NE(box, kInvalidId);
  const ObjectInfo start = *runtime.objectInfo(box);
  // The level's path key at 3 s: 25 cm right, 10 cm forward, turned 30 degrees.
  const glm::mat4 moved = glm::translate(glm::mat4(1), glm::vec3(0.25f, 0, 0.1f)) *
                          glm::mat4_cast(glm::quat(0.9659258f, 0, 0.2588190f, 0));
  const glm::mat4 original(1.0f);
  ASSERT_TRUE(settle(runtime));
  ASSERT_TRUE(runtime.setObjectTransform(box, fromGlmMat(moved)).ok());
  ASSERT_TRUE(settle(runtime));
  const ObjectInfo after = *runtime.objectInfo(box);
  const Aabb short_box = [&] {
    Expected<Scene> s = loadLevel(test::cornellGltf());
    std::vector<Vec3> corners;
    for (const Instance& inst : s->instances) {
      if (s->nodes[size_t(inst.node)].name != "shortBox") continue;
      for (const Vec3& p : s->meshes[size_t(inst.mesh)].positions) corners.push_back(p);
    }
    return boundsOf(corners);
  }();
  const std::vector<Probe> probes =
      cornellProbes({boundsOf(start.world_positions), boundsOf(after.world_positions), short_box});
  ASSERT_GE(probes.size(), 50u);

  const test::BakedLevel& static_moved =
      test::bakedLevel("cornell_moved", writeCornellWithBoxAt(moved, "moved"));
  const std::vector<Rgb> expected_moved = bakedAt(static_moved, probes);
  const std::vector<Rgb> got_moved = runtimeAt(runtime, probes);
  const std::vector<Rgb> baked_only = bakedAt(level, probes);
  double worst = 0;
  const double rms_moved = normalizedRms(got_moved, expected_moved, &worst);
  const double rms_without = normalizedRms(baked_only, expected_moved);
  std::printf(
      "moved tall box, %zu probes: runtime vs static bake RMS %.2f%% (worst %.1f%%); "
      "bake without the box would be %.2f%%\n",
      probes.size(), 100 * rms_moved, 100 * worst, 100 * rms_without);
  EXPECT_LT(rms_moved, 0.05);

  // Back where it started: the runtime returns to what it showed before.
  ASSERT_TRUE(runtime.setObjectTransform(box, fromGlmMat(original)).ok());
  ASSERT_TRUE(settle(runtime));
  const test::BakedLevel& static_original = test::bakedLevel("cornell_static", test::cornellGltf());
  const std::vector<Rgb> expected_original = bakedAt(static_original, probes);
  const std::vector<Rgb> got_back = runtimeAt(runtime, probes);
  const double rms_back = normalizedRms(got_back, expected_original, &worst);
  std::printf("moved back: runtime vs static bake RMS %.2f%% (worst %.1f%%)\n", 100 * rms_back,
              100 * worst);
  // At its first place the box stands 10-30 cm from two walls: the gaps are
  // narrower than two runtime patches, so the shading interpolation blurs
  // the contact shadows there; a looser bound, stated.
  EXPECT_LT(rms_back, 0.10);
}

TEST(RuntimeDynamic, MovingBackRestoresTheRuntimeWithinOnePercent) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
  Expected<std::unique_ptr<Runtime>> created = Runtime::create(level.scene, level.bake, level.dir);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  const ObjectId box = runtime.objectForNode(level.scene.findNode("tallBox"));
  ASSERT_TRUE(settle(runtime));
  const ObjectInfo start = *runtime.objectInfo(box);
  const std::vector<Probe> probes = cornellProbes({boundsOf(start.world_positions)});
  const std::vector<Rgb> before = runtimeAt(runtime, probes);
  for (float x : {0.1f, 0.3f, 0.5f}) {
    ASSERT_TRUE(runtime
                    .setObjectTransform(
                        box, fromGlmMat(glm::translate(glm::mat4(1), glm::vec3(x, 0, 0.2f))))
                    .ok());
    runtime.update(0);
  }
  ASSERT_TRUE(runtime.setObjectTransform(box, start.world_from_object).ok());
  ASSERT_TRUE(settle(runtime));
  double worst = 0;
  const double rms = normalizedRms(runtimeAt(runtime, probes), before, &worst);
  std::printf("restored after 3 moves: RMS %.4f%%, worst %.4f%%\n", 100 * rms, 100 * worst);
  EXPECT_LT(worst, 0.01);
}

// Form factor from a differential area to a parallel rectangle with a
// corner above it (Howell's catalogue, C-11): sides a, b at height c.
double cornerFormFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * 3.14159265358979);
}

// Point under an axis-aligned rectangle [x0,x1] x [z0,z1] at height h:
// signed sum of the four corner rectangles.
double rectangleFormFactor(double px, double pz, double x0, double x1, double z0, double z1,
                           double h) {
  auto corner = [&](double dx, double dz) {
    const double sx = dx < 0 ? -1 : 1, sz = dz < 0 ? -1 : 1;
    return sx * sz * cornerFormFactor(std::abs(dx), std::abs(dz), h);
  };
  return corner(x1 - px, z1 - pz) - corner(x0 - px, z1 - pz) - corner(x1 - px, z0 - pz) +
         corner(x0 - px, z0 - pz);
}

TEST(RuntimeDynamic, EmissivePanelLightsTheFloorByTheAnalyticAmount) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  // A black 4 x 4 m floor of 32 x 32 quads, a faint static lamp so the bake
  // has light, and a 20 cm black emissive panel facing down, dynamic.
  test::SceneBuilder b;
  const int black = b.material({0, 0, 0});
  std::vector<Vec3> floor;
  const int n = 32;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const float x0 = -2 + 4.0f * i / n, x1 = -2 + 4.0f * (i + 1) / n, z0 = -2 + 4.0f * j / n,
                  z1 = -2 + 4.0f * (j + 1) / n;
      floor.insert(floor.end(),
                   {{x0, 0, z0}, {x0, 0, z1}, {x1, 0, z1}, {x0, 0, z0}, {x1, 0, z1}, {x1, 0, z0}});
    }
  }
  b.addMesh("floor", floor, black);
  const float half = 0.1f, luminance_cd = 1000.0f;
  const int glow = b.material({0, 0, 0}, {luminance_cd, luminance_cd, luminance_cd});
  b.addQuad("panel", {-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half},
            glow);  // faces down
  b.addPointLight({0, 8, 0}, 0.01f);
  Scene& scene = b.scene();
  scene.nodes.back().dynamic = true;
  scene.nodes.back().translation = {0, 0.5f, 0};
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("svit_panel_" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(dir);
  ASSERT_TRUE(writeGltf(scene, dir + "/panel.gltf").ok());
  const test::BakedLevel& level = test::bakedLevel("panel", dir + "/panel.gltf");
  RuntimeSettings settings;
  // The panel is 20 cm across at 40 cm: its point samples must resolve it
  // (a point set's error on the nearest patches grows as (size / distance)^2).
  settings.max_samples_per_emitter = 64;
  Expected<std::unique_ptr<Runtime>> created =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Runtime& runtime = **created;
  const ObjectId panel = runtime.objectForNode(level.scene.findNode("panel"));
  ASSERT_NE(panel, kInvalidId);
  // Carried over the floor: check at two places.
  for (const glm::vec3 at : {glm::vec3(0.3f, 0.6f, -0.2f), glm::vec3(-0.5f, 0.4f, 0.7f)}) {
    ASSERT_TRUE(
        runtime.setObjectTransform(panel, fromGlmMat(glm::translate(glm::mat4(1), at))).ok());
    ASSERT_TRUE(settle(runtime));
    const std::vector<Rgb>& deltas = runtime.patchDeltas();
    double worst = 0, peak = 0;
    std::vector<std::pair<double, double>> compared;
    for (uint32_t p = 0; p < runtime.staticPatchCount(); ++p) {
      const PatchInfo info = *runtime.patchInfo(p);
      // Analytic mean irradiance over the patch: E = pi L F, averaged over
      // 15 interior points per sub-triangle (the panel is 20 cm across at >= 40 cm).
      double sum = 0, area = 0;
      for (size_t t = 0; t + 2 < info.triangles.size(); t += 3) {
        const glm::vec3 a(info.triangles[t].x, 0, info.triangles[t].z);
        const glm::vec3 bb(info.triangles[t + 1].x, 0, info.triangles[t + 1].z);
        const glm::vec3 c(info.triangles[t + 2].x, 0, info.triangles[t + 2].z);
        const double tri_area = 0.5 * glm::length(glm::cross(bb - a, c - a));
        for (int u = 0; u < 5; ++u) {
          for (int v = 0; v < 5 - u; ++v) {
            const float s = (u + 0.33f) / 5.0f, r = (v + 0.33f) / 5.0f;
            const glm::vec3 q = a + s * (bb - a) + r * (c - a);
            sum += tri_area / 15 * 3.14159265358979 * luminance_cd *
                   rectangleFormFactor(q.x, q.z, at.x - half, at.x + half, at.z - half, at.z + half,
                                       at.y);
          }
        }
        area += tri_area;
      }
      const double expected = sum / area;
      peak = std::max(peak, expected);
      compared.push_back({expected, double(luminance(deltas[p]))});
    }
    for (auto& [expected, got] : compared) {
      if (expected < 0.1 * peak) continue;
      worst = std::max(worst, std::abs(got - expected) / expected);
    }
    std::printf("panel at (%.1f, %.1f, %.1f): peak %.1f lux, worst patch error %.2f%%\n", at.x,
                at.y, at.z, peak, 100 * worst);
    EXPECT_LT(worst, 0.03);
  }
}

}  // namespace
}  // namespace svit

// CIE 171:2006 test cases through the whole bake (svit::baker::bakeLevel)
// and the probe lookup a game makes (svit::baker::probeBake): bilinear in
// the lightmap at the nearest surface point.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "baker/test_scenes.h"
#include "svit/baker/bake.h"
#include "svit/baker/probe.h"
#include "svit/level.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;
using test::SceneBuilder;

struct Expectation {
  float x, z;
  double lux;
};

// Writes the scene as glTF into a fresh directory, bakes it, probes the
// floor (normal up) at the expectations and checks each within `tolerance`.
void bakeAndProbe(Scene& scene, const std::string& name, const std::vector<Expectation>& expected,
                  double tolerance, double texels_per_m) {
  const fs::path dir = fs::temp_directory_path() / ("svit_cie_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string level = (dir / "level.gltf").string();
  ASSERT_TRUE(writeGltf(scene, level).ok());
  BakeOptions options;
  options.level_path = level;
  options.out_dir = (dir / "out").string();
  // CIE_QUALITY overrides, to watch convergence by hand.
  options.quality = std::getenv("CIE_QUALITY") ? std::atof(std::getenv("CIE_QUALITY")) : 0.5;
  options.texels_per_m = texels_per_m;
  Expected<BakeResult> result = bakeLevel(options, {}, nullptr);
  ASSERT_TRUE(result.ok()) << result.status().message();
  std::vector<ProbePoint> points;
  for (const Expectation& e : expected) points.push_back({{e.x, 0.0f, e.z}, {0, 1, 0}});
  Expected<std::vector<ProbeResult>> probes = probeBake(options.out_dir, points);
  ASSERT_TRUE(probes.ok()) << probes.status().message();
  for (size_t i = 0; i < expected.size(); ++i) {
    const double got = luminance((*probes)[i].irradiance);
    std::printf("%s (%.2f, %.2f): %.3f lx, expected %.3f (%+.2f%%)\n", name.c_str(), expected[i].x,
                expected[i].z, got, expected[i].lux, 100.0 * (got / expected[i].lux - 1.0));
    EXPECT_NEAR(got, expected[i].lux, expected[i].lux * tolerance)
        << name << " at (" << expected[i].x << ", " << expected[i].z << ")";
    EXPECT_LT((*probes)[i].distance_m, 1e-4);
  }
  fs::remove_all(dir);
}

// CIE 171:2006 5.2: I = I0 cos(theta), I0 = 1000 cd, h = 3 m over a black
// 4x4 m floor; E = I0 h^2 / d^4. Modelled as a 2x2 cm emitter of
// 2.5e6 cd/m2 facing down (I0 = L * A = 1000 cd). The emitter is 1/150 of
// h wide: the point-source formula holds to ~1e-5.
TEST(Cie171, Case5_2LambertianPointSource) {
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  const int lamp = b.material({0, 0, 0}, {2.5e6f, 2.5e6f, 2.5e6f});
  b.addQuad("floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, black);
  b.addQuad("lamp", {-0.01f, 3, -0.01f}, {0.01f, 3, -0.01f}, {0.01f, 3, 0.01f}, {-0.01f, 3, 0.01f},
            lamp);
  // Direct light only; every shadow ray sees the lamp, so the estimate is
  // the average of cos*cos/d^2 over the lamp: noise < 1e-4.
  bakeAndProbe(b.scene(), "5_2",
               {{0, 0, 111.111},
                {0.5f, 0, 105.186},
                {1, 0, 90.000},
                {1.5f, 0, 71.111},
                {0.5f, 0.5f, 99.723},
                {1, 1, 74.380},
                {1.5f, 1.5f, 49.383}},
               0.01, 32);
}

// The same with an isotropic KHR_lights_punctual point light of 1000 cd:
// E = I h / d^3.
TEST(Cie171, Case5_2IsotropicPointLight) {
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  b.addQuad("floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, black);
  b.addPointLight({0, 3, 0}, 1000.0f);
  // The light must hang on a node to be written to glTF.
  Node lamp;
  lamp.name = "lamp";
  lamp.translation = {0, 3, 0};
  lamp.parent_from_node.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 3, 0, 1};
  b.scene().nodes.push_back(lamp);
  b.scene().lights[0].node = int(b.scene().nodes.size() - 1);
  std::vector<Expectation> expected;
  for (const auto& [x, z] : std::vector<std::pair<float, float>>{
           {0, 0}, {0.5f, 0}, {1, 0}, {1.5f, 0}, {0.5f, 0.5f}, {1, 1}, {1.5f, 1.5f}}) {
    const double d = std::sqrt(double(x) * x + double(z) * z + 9.0);
    expected.push_back({x, z, 1000.0 * 3.0 / (d * d * d)});
  }
  bakeAndProbe(b.scene(), "5_2_point", expected, 0.01, 32);
}

// CIE 171:2006 5.3: a 1x1 m emitter of 1000 cd/m2 centred 3 m above the
// floor of a black 4x4x3 m room; floor points (2, y) for y = 0.25 .. 1.75
// (here x and z, y up): 61.42, 79.26, 95.67, 105.78 lx. The emitter hangs
// 1 mm below the ceiling (0.07% less distance: 0.05% more light, inside 1%).
TEST(Cie171, Case5_3AreaSourceInBlackRoom) {
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  const int lamp = b.material({0, 0, 0}, {1000, 1000, 1000});
  b.addRoom("room", {0, 0, 0}, {4, 3, 4}, black);
  b.addQuad("lamp", {1.5f, 2.999f, 1.5f}, {2.5f, 2.999f, 1.5f}, {2.5f, 2.999f, 2.5f},
            {1.5f, 2.999f, 2.5f}, lamp);
  // 8 samples x passes over a 1 m lamp 3 m away: the integrand cos*cos/d^2
  // varies ~10% over the lamp, stratified -> well under 0.5% noise.
  bakeAndProbe(b.scene(), "5_3",
               {{2, 0.25f, 61.42}, {2, 0.75f, 79.26}, {2, 1.25f, 95.67}, {2, 1.75f, 105.78}}, 0.01,
               32);
}

}  // namespace
}  // namespace svit::baker

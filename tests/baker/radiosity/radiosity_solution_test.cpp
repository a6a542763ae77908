// Queries of a solved radiosity solution (RadiositySolver::irradianceAt):
// element-centre and vertex interpolation, hard corners, continuity across
// shared edges. Random points come from a fixed seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "baker/radiosity_test_util.h"
#include "svit/baker/radiosity.h"
#include "util/random.h"

namespace svit::baker {
namespace {

using test::finiteNonNegative;
using test::prepare;
using test::roomWithLight;
using test::solvePasses;
using test::Timer;

TEST(Interpolation, CentreModeAndHardCornersWithoutSubdivision) {
  Timer timer("Interpolation.CentreModeAndHardCornersWithoutSubdivision");
  // Light low and near the -x wall: floor, -x and -z walls see it differently.
  const Scene scene = roomWithLight(0.5f, {0.4f, 0.5f, 1.0f}, 100.0f);
  RadiositySettings settings;
  settings.subdiv = 1e-12;  // leaves are the triangles: their values are the triangle means
  settings.first_pass_rays = 8192;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 2).ok());
  RadiositySolver& solver = *solved->solver;
  solver.prepareQueries();
  const std::vector<Rgb> mean = solver.triangleIrradiance(true);
  const std::vector<float>& area = solved->geometry.areas_m2;
  // Float means against double leaf values: 1e-5 relative is ~100 float ulps.
  for (uint32_t t = 0; t < mean.size(); ++t) {
    const Rgb centre =
        solver.irradianceAt(t, true, 1.0 / 3.0, 1.0 / 3.0, InterpolationMode::kElementCentre);
    EXPECT_NEAR(centre.g, mean[t].g, 1e-5 * mean[t].g) << "triangle " << t;
    EXPECT_NEAR(centre.r, mean[t].r, 1e-5 * mean[t].r) << "triangle " << t;
  }
  // Corner (0, 0, 0) is corner 0 of floor triangles 0, 1, -x wall 4, 5 and
  // -z wall 8, 9 (addRoom's order). Walls meet at 90 degrees > 30, so each
  // side's vertex value averages its own two triangles only.
  auto side = [&](uint32_t t0, uint32_t t1) {
    return (double(mean[t0].g) * area[t0] + double(mean[t1].g) * area[t1]) /
           (double(area[t0]) + area[t1]);
  };
  const double floor_side = side(0, 1), x_side = side(4, 5), z_side = side(8, 9);
  const double floor_value = solver.irradianceAt(0, true, 0, 0, InterpolationMode::kVertex).g;
  const double x_value = solver.irradianceAt(4, true, 0, 0, InterpolationMode::kVertex).g;
  const double z_value = solver.irradianceAt(8, true, 0, 0, InterpolationMode::kVertex).g;
  std::printf("corner: floor %.3f (own %.3f), -x %.3f (own %.3f), -z %.3f (own %.3f)\n",
              floor_value, floor_side, x_value, x_side, z_value, z_side);
  EXPECT_NEAR(floor_value, floor_side, 1e-5 * floor_side);
  EXPECT_NEAR(x_value, x_side, 1e-5 * x_side);
  EXPECT_NEAR(z_value, z_side, 1e-5 * z_side);
  // The sides really differ (the light is 0.4 m from -x, 1 m from -z), so
  // averaging across the hard edge would have been visible.
  EXPECT_GT(std::abs(floor_value - x_value), 0.05 * floor_value);
  // The same corner seen from the other floor triangle (1: a, c, d) agrees.
  EXPECT_NEAR(solver.irradianceAt(1, true, 0, 0, InterpolationMode::kVertex).g, floor_value,
              1e-6 * floor_value);
}

TEST(Interpolation, VertexModeIsContinuousAcrossTheFloorDiagonal) {
  Timer timer("Interpolation.VertexModeIsContinuousAcrossTheFloorDiagonal");
  const Scene scene = roomWithLight(0.5f, {1.0f, 1.0f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.min_perimeter_m = 0.2;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 2).ok());
  ASSERT_GT(solved->solver->stats().subdivisions, 0u);
  RadiositySolver& solver = *solved->solver;
  solver.prepareQueries();
  // Floor triangles 0 = (a, b, c) and 1 = (a, c, d) share the diagonal a-c:
  // the point a + s (c - a) is (u, v) = (0, s) in 0 and (s, 0) in 1.
  Rng rng(hashIds(3, 14));
  for (int i = 0; i < 200; ++i) {
    const double s = i < 9 ? 0.1 * (i + 1) : rng.uniformDouble();
    const Rgb from0 = solver.irradianceAt(0, true, 0.0, s, InterpolationMode::kVertex);
    const Rgb from1 = solver.irradianceAt(1, true, s, 0.0, InterpolationMode::kVertex);
    ASSERT_TRUE(finiteNonNegative(from0) && finiteNonNegative(from1));
    // Both interpolate the same two vertex values of one conforming leaf
    // edge; they differ by double rounding, then float (6e-8).
    EXPECT_NEAR(from0.g, from1.g, 1e-6 * std::max(from0.g, from1.g)) << "s = " << s;
  }
  // Both modes finite everywhere on every triangle (seeded points).
  for (uint32_t t = 0; t < solved->geometry.triangleCount(); ++t) {
    for (int i = 0; i < 50; ++i) {
      double u = rng.uniformDouble(), v = rng.uniformDouble();
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      EXPECT_TRUE(
          finiteNonNegative(solver.irradianceAt(t, true, u, v, InterpolationMode::kVertex)));
      EXPECT_TRUE(
          finiteNonNegative(solver.irradianceAt(t, true, u, v, InterpolationMode::kElementCentre)));
    }
  }
}

}  // namespace
}  // namespace svit::baker

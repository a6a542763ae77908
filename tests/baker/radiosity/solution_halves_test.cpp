// The solver's two half solutions (svit/baker/radiosity.h SolutionHalf),
// which a bake's lighting passes gather from in turn so that the
// lightmap's split-half estimate sees the solution's noise: the whole until
// two passes completed, then two different answers to the same question
// whose pass-weighted mean is the whole. Fixed seeds throughout.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "baker/radiosity_test_util.h"
#include "svit/baker/radiosity.h"

namespace svit::baker {
namespace {

using test::prepare;
using test::roomWithLight;
using test::solvePasses;

struct Probe {
  uint32_t triangle;
  double u, v;
};

// Points spread over every triangle of the room (its corners and middles).
std::vector<Probe> probes(const BakeGeometry& geometry) {
  std::vector<Probe> out;
  for (uint32_t t = 0; t < geometry.triangleCount(); ++t)
    for (const auto& [u, v] : {std::pair{0.2, 0.2}, {0.6, 0.2}, {0.2, 0.6}, {1.0 / 3, 1.0 / 3}})
      out.push_back({t, u, v});
  return out;
}

double green(const RadiositySolver& solver, const Probe& p, SolutionHalf half) {
  return solver.irradianceAt(p.triangle, true, p.u, p.v, InterpolationMode::kVertex, half).g;
}

// The lit room solved for `passes` passes of few rays (seed 5); the scene
// outlives the solver that points into it.
std::unique_ptr<test::Solved> solvedRoom(uint32_t passes) {
  static const Scene room = roomWithLight(0.6f, {1.0f, 1.8f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.first_pass_rays = 20000;
  settings.seed = 5;
  auto solved = prepare(room, settings);
  EXPECT_TRUE(solved->solver && solvePasses(*solved->solver, passes).ok());
  return solved;
}

TEST(SolutionHalves, AreTheWholeBeforeTwoPassesCompleted) {
  auto solved = solvedRoom(1);
  ASSERT_TRUE(solved->solver);
  const RadiositySolver& solver = *solved->solver;
  EXPECT_FALSE(solver.hasSolutionHalves());
  for (const Probe& p : probes(solved->geometry)) {
    const double whole = green(solver, p, SolutionHalf::kWhole);
    EXPECT_EQ(green(solver, p, SolutionHalf::kEven), whole);
    EXPECT_EQ(green(solver, p, SolutionHalf::kOdd), whole);
  }
}

TEST(SolutionHalves, AreTwoAnswersToTheSameQuestionWhoseMeanIsTheWhole) {
  auto solved = solvedRoom(4);
  ASSERT_TRUE(solved->solver);
  const RadiositySolver& solver = *solved->solver;
  ASSERT_TRUE(solver.hasSolutionHalves());
  size_t differing = 0, count = 0;
  for (const Probe& p : probes(solved->geometry)) {
    const double whole = green(solver, p, SolutionHalf::kWhole);
    const double even = green(solver, p, SolutionHalf::kEven);
    const double odd = green(solver, p, SolutionHalf::kOdd);
    // The whole is the halves' mean weighted by their passes' rays: between
    // them, up to float rounding of the cached values (1e-6 relative).
    const double slack = 1e-6 * whole;
    EXPECT_GE(whole, std::min(even, odd) - slack) << p.triangle;
    EXPECT_LE(whole, std::max(even, odd) + slack) << p.triangle;
    // Each half is an answer of its own: within 25 % of the whole (a few
    // passes of 20,000 rays over 12 triangles leave a few % of noise).
    EXPECT_NEAR(even, whole, 0.25 * whole) << p.triangle;
    EXPECT_NEAR(odd, whole, 0.25 * whole) << p.triangle;
    differing += even != odd;
    ++count;
  }
  // Independent noise: the halves differ nearly everywhere.
  EXPECT_GT(differing, count * 9 / 10);
}

}  // namespace
}  // namespace svit::baker

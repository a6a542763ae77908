// Stiff scenes: albedo 0.999 in closed rooms, where light bounces ~1000
// times before it is absorbed. The answer must stay finite, conserve flux
// (what is emitted is absorbed: sum of (1 - rho) * E * A over every side
// equals the emitted flux), and the solver's error estimate must not claim
// a convergence it does not have.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stability_util.h"
#include "util/random.h"

namespace svit::baker {
namespace {

using test::kPi;
using test::reportFigure;
using test::SceneBuilder;
using test::Solved;

constexpr float kRho = 0.999f;

// Absorbed flux: sum over triangle sides of (1 - albedo) * E * A, lm.
double absorbedFlux(const RadiositySolver& solver, const BakeGeometry& g) {
  double absorbed = 0;
  for (bool front : {true, false}) {
    const std::vector<Rgb> e = solver.triangleIrradiance(front);
    for (size_t t = 0; t < g.triangleCount(); ++t) {
      if (!front && !g.double_sided[t]) continue;
      const Rgb& a = g.albedo[t];
      const Rgb absorbed_rgb{(1.0f - a.r) * e[t].r, (1.0f - a.g) * e[t].g, (1.0f - a.b) * e[t].b};
      absorbed += double(luminance(absorbed_rgb)) * g.areas_m2[t];
    }
  }
  return absorbed;
}

// Emitted flux: pi * L * A per emitting side plus the point lights, lm.
double emittedFlux(const Scene& scene, const BakeGeometry& g) {
  double emitted = 0;
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    emitted +=
        kPi * double(luminance(g.emission[t])) * g.areas_m2[t] * (g.double_sided[t] ? 2.0 : 1.0);
  }
  for (const Light& light : scene.lights)
    emitted += 4.0 * kPi * double(light.intensity) * double(luminance(light.color));
  return emitted;
}

// A 4 x 3 x 5 m closed room, a 1 m box standing on the floor (open at the
// bottom, as game assets are: the floor under it is hidden inside it), a
// double-sided 1 x 1 m panel of 20 cd/m2 hanging 0.5 m below the ceiling
// and a 10 cd point light; every surface has albedo `rho`.
Scene stiffRoom(float rho) {
  SceneBuilder b;
  const int wall = b.material({rho, rho, rho});
  const int panel = b.material({rho, rho, rho}, {20, 20, 20}, true);
  b.addRoom("room", {0, 0, 0}, {4, 3, 5}, wall);
  b.addMesh("box",
            {{2.5f, 1, 1}, {2.5f, 1, 2}, {3.5f, 1, 2}, {2.5f, 1, 1}, {3.5f, 1, 2}, {3.5f, 1, 1},
             {2.5f, 0, 1}, {2.5f, 0, 2}, {2.5f, 1, 2}, {2.5f, 0, 1}, {2.5f, 1, 2}, {2.5f, 1, 1},
             {3.5f, 0, 1}, {3.5f, 1, 1}, {3.5f, 1, 2}, {3.5f, 0, 1}, {3.5f, 1, 2}, {3.5f, 0, 2},
             {2.5f, 0, 1}, {2.5f, 1, 1}, {3.5f, 1, 1}, {2.5f, 0, 1}, {3.5f, 1, 1}, {3.5f, 0, 1},
             {2.5f, 0, 2}, {3.5f, 0, 2}, {3.5f, 1, 2}, {2.5f, 0, 2}, {3.5f, 1, 2}, {2.5f, 1, 2}},
            wall);
  b.addQuad("panel", {1.5f, 2.5f, 2}, {2.5f, 2.5f, 2}, {2.5f, 2.5f, 3}, {1.5f, 2.5f, 3}, panel);
  b.addPointLight({1.0f, 2.0f, 4.0f}, 10.0f);
  return b.scene();
}

TEST(Stiff, ClosedRoomWithABoxOnTheFloorConservesFluxAtAlbedo0p999) {
  test::StabilityTimer timer;
  const Scene scene = stiffRoom(kRho);
  RadiositySettings settings;
  settings.first_pass_rays = 1024;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  StopRule stop;
  stop.max_passes = 2;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const RadiositySolver& solver = *solved->solver;
  const BakeGeometry& g = solved->geometry;
  for (bool front : {true, false}) {
    for (const Rgb& e : solver.triangleIrradiance(front)) ASSERT_TRUE(test::finiteNonNegative(e));
    for (const Rgb& r : solver.triangleRadiosity(front)) ASSERT_TRUE(test::finiteNonNegative(r));
  }
  Rng rng(hashIds(5, 5));
  for (uint32_t t = 0; t < g.triangleCount(); ++t) {
    for (int i = 0; i < 16; ++i) {
      const double u = 0.5 * rng.uniformDouble(), v = 0.5 * rng.uniformDouble();
      ASSERT_TRUE(
          test::finiteNonNegative(solver.irradianceAt(t, true, u, v, InterpolationMode::kVertex)));
      ASSERT_TRUE(test::finiteNonNegative(
          solver.irradianceAt(t, true, u, v, InterpolationMode::kElementCentre)));
    }
  }
  const double emitted = emittedFlux(scene, g), absorbed = absorbedFlux(solver, g);
  const SolverStats stats = solver.stats();
  const double balance = absorbed / emitted - 1.0;
  reportFigure("absorbed / emitted flux - 1", balance);
  reportFigure("rays", double(stats.rays));
  reportFigure("reflected rays found starting inside the box (shot again)",
               double(stats.inside_origin_rays));
  reportFigure("rays absorbed by back faces", double(stats.back_absorbed));
  reportFigure("captured fraction of surface rays", stats.captured_fraction);
  reportFigure("estimated rel. error", solver.estimatedRelativeError());
  // Every ray carries 1/N of the flux and every bounce keeps rho of it; the
  // unshot remainder is compensated as ambient light U / (A (1 - rho)),
  // which closes the balance exactly for uniform albedo in a closed room.
  // What breaks it is flux lost on the way, amplified ~1/(1 - rho) = 1000
  // times: before reflected rays from the hidden floor under the box were
  // shot again (baker/src/radiosity/radiosity_solver.cpp, step 3b) they went into
  // the box's black insides and the balance was -85%. 1% is the issue's
  // bound; measured now: -3e-7.
  EXPECT_LT(std::abs(balance), 0.01);
}

// The exact answer of a closed uniform enclosure: every side of a 2 m cube
// emits luminance 1 and reflects rho, so E = B = pi / (1 - rho) everywhere.
struct Enclosure {
  Scene scene;
  std::unique_ptr<Solved> solved;
};

std::unique_ptr<Enclosure> uniformEnclosure(uint32_t first_pass_rays, uint64_t seed) {
  auto e = std::make_unique<Enclosure>();
  SceneBuilder b;
  const int wall = b.material({kRho, kRho, kRho}, {1, 1, 1});
  b.addRoom("cube", {0, 0, 0}, {2, 2, 2}, wall);
  e->scene = b.scene();
  RadiositySettings settings;
  settings.first_pass_rays = first_pass_rays;
  settings.seed = seed;
  e->solved = test::prepareSolver(e->scene, settings);
  return e;
}

// Area-weighted RMS relative error of the front irradiance against a
// uniform exact value: the metric the estimate stands for.
double trueError(const RadiositySolver& solver, const BakeGeometry& g, double exact) {
  const std::vector<Rgb> e = solver.triangleIrradiance(true);
  double sq = 0, area = 0;
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    const double d = (double(luminance(e[t])) - exact) / exact;
    sq += d * d * g.areas_m2[t];
    area += g.areas_m2[t];
  }
  return std::sqrt(sq / area);
}

// Runs `solver` to doubling ray budgets (mid-pass stops, pass ends, then
// `passes` passes) and checks at every stop that the estimate is at least
// the true error minus `slack` (what the exact answer itself may be off by).
// Returns the smallest estimate / true error seen.
double checkEstimateAtEveryStop(RadiositySolver& solver, const std::function<double()>& true_error,
                                uint32_t passes, double slack, int* stops) {
  double worst_ratio = 1e300;
  for (uint64_t budget = 1u << 10; solver.stats().passes_completed < passes; budget *= 2) {
    StopRule stop;
    stop.max_rays = budget;
    EXPECT_TRUE(solver.improve(stop).ok());
    const double truth = true_error();
    const double estimate = solver.estimatedRelativeError();
    const SolverStats stats = solver.stats();
    std::printf("%10llu rays, %u passes: estimate %.5f, true error %.5f\n",
                (unsigned long long)stats.rays, stats.passes_completed, estimate, truth);
    EXPECT_TRUE(std::isfinite(estimate));
    EXPECT_LE(estimate, 1.0);
    EXPECT_GE(estimate + slack, truth)
        << stats.rays << " rays, " << stats.passes_completed << " passes";
    worst_ratio = std::min(worst_ratio, estimate / truth);
    ++*stops;
  }
  return worst_ratio;
}

TEST(Stiff, EstimatedErrorIsNeverBelowTheTrueErrorOfAUniformEnclosure) {
  test::StabilityTimer timer;
  // Exact: E = pi / (1 - rho) on every triangle (rho as the float it is).
  const double exact = kPi / (1.0 - double(kRho));
  auto e = uniformEnclosure(256, 1);
  ASSERT_TRUE(e->solved->solver);
  RadiositySolver& solver = *e->solved->solver;
  int stops = 0;
  const double worst = checkEstimateAtEveryStop(
      solver, [&] { return trueError(solver, e->solved->geometry, exact); }, 3, 0.0, &stops);
  reportFigure("stops checked (2^10 rays doubling to 3 passes)", stops);
  reportFigure("smallest estimate / true error", worst);
}

TEST(Stiff, EstimatedErrorIsNeverBelowTheTrueErrorOfTheRoomWithABox) {
  test::StabilityTimer timer;
  // Nearly exact: at albedo 0.999 the room fills with a uniform field of
  // E = Phi / ((1 - rho) A_visible) (flux balance over what light can
  // reach), plus direct light of order (1 - rho) of it: per triangle within
  // ~0.3% (the panel's light on the ceiling above it is the largest term).
  // A triangle's mean is that times its visible share: the floor triangle
  // under the box has 1 m2 of its 10 m2 hidden.
  const Scene scene = stiffRoom(kRho);
  RadiositySettings settings;
  settings.first_pass_rays = 512;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  RadiositySolver& solver = *solved->solver;
  const BakeGeometry& g = solved->geometry;
  double total_area = 0;
  std::vector<double> visible(g.triangleCount());
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    const int sides = g.double_sided[t] ? 2 : 1;
    total_area += sides * g.areas_m2[t];
    // The floor's second triangle (0,0)-(4,5)-(4,0) holds the box's 1 m2
    // footprint (x 2.5-3.5, z 1-2 lies below z = 1.25 x).
    visible[t] = (g.instance[t] == 0 && g.mesh_triangle[t] == 1)
                     ? (g.areas_m2[t] - 1.0) / g.areas_m2[t]
                     : 1.0;
  }
  const double e_visible = emittedFlux(scene, g) / ((1.0 - double(kRho)) * (total_area - 1.0));
  auto true_error = [&] {
    const std::vector<Rgb> e = solver.triangleIrradiance(true);
    double sq = 0, area = 0;
    for (size_t t = 0; t < g.triangleCount(); ++t) {
      const double exact = e_visible * visible[t];
      const double d = (double(luminance(e[t])) - exact) / e_visible;
      sq += d * d * g.areas_m2[t];
      area += g.areas_m2[t];
    }
    return std::sqrt(sq / area);
  };
  int stops = 0;
  const double worst = checkEstimateAtEveryStop(solver, true_error, 2, 0.003, &stops);
  reportFigure("stops checked (2^10 rays doubling to 2 passes)", stops);
  reportFigure("smallest estimate / true error", worst);
  reportFigure("true error after 2 passes", true_error());
}

}  // namespace
}  // namespace svit::baker

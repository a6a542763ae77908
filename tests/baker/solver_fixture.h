#pragma once
// A scene's static geometry, its ray caster and a radiosity solver over
// them, for the baker tests; heap-allocated because they reference one
// another.

#include <gtest/gtest.h>

#include <memory>

#include "svit/baker/radiosity.h"

namespace svit::test {

struct Solved {
  baker::BakeGeometry geometry;
  std::unique_ptr<baker::RayCaster> caster;
  std::unique_ptr<baker::RadiositySolver> solver;
};

/// Flattens `scene`, builds the caster (Embree, or the brute-force oracle)
/// and the solver. Failures are reported as test failures; `solver` is then null.
inline std::unique_ptr<Solved> prepareSolver(const Scene& scene,
                                             const baker::RadiositySettings& settings,
                                             bool brute_force = false) {
  auto solved = std::make_unique<Solved>();
  Expected<baker::BakeGeometry> geometry = baker::flattenStaticGeometry(scene);
  EXPECT_TRUE(geometry.ok()) << geometry.status().message();
  if (!geometry.ok()) return solved;
  solved->geometry = std::move(geometry).value();
  if (brute_force) {
    solved->caster = baker::makeBruteForceCaster(solved->geometry);
  } else {
    Expected<std::unique_ptr<baker::RayCaster>> caster = baker::makeEmbreeCaster(solved->geometry);
    EXPECT_TRUE(caster.ok()) << caster.status().message();
    if (!caster.ok()) return solved;
    solved->caster = std::move(caster).value();
  }
  Expected<std::unique_ptr<baker::RadiositySolver>> solver =
      baker::RadiositySolver::create(scene, solved->geometry, *solved->caster, settings);
  EXPECT_TRUE(solver.ok()) << solver.status().message();
  if (solver.ok()) solved->solver = std::move(solver).value();
  return solved;
}

}  // namespace svit::test

#pragma once
// Helpers of the radiosity solver tests (element tree, light sources,
// solution queries, the solver): a timer that prints, a solver prepared and
// run for whole passes, area means, a spot light and a closed room around a
// point light.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "solver_fixture.h"
#include "svit/baker/radiosity.h"
#include "test_scenes.h"

namespace svit::test {

// Prints how long a test took (each test file should stay under ~40 s on 2 cores).
class Timer {
 public:
  explicit Timer(const char* name) : name_(name), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { std::printf("[timing] %s: %.3f s\n", name_, seconds()); }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

inline std::unique_ptr<Solved> prepare(const Scene& scene, const baker::RadiositySettings& settings,
                                       bool brute_force = false) {
  return prepareSolver(scene, settings, brute_force);
}

inline Status solvePasses(baker::RadiositySolver& solver, uint32_t passes) {
  baker::StopRule stop;
  stop.max_passes = passes;
  return solver.improve(stop);
}

// Area-weighted mean luminance of per-triangle values.
inline double areaMean(const std::vector<Rgb>& values, const baker::BakeGeometry& g) {
  double sum = 0, area = 0;
  for (size_t t = 0; t < values.size(); ++t) {
    sum += double(luminance(values[t])) * g.areas_m2[t];
    area += g.areas_m2[t];
  }
  return sum / area;
}

inline bool finiteNonNegative(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 &&
         c.b >= 0;
}

inline Light spotLight(Vec3 position, Vec3 direction, float intensity_cd, float inner_rad,
                       float outer_rad) {
  Light light;
  light.name = "spot";
  light.type = LightType::kSpot;
  light.position = position;
  light.direction = direction;
  light.intensity = intensity_cd;
  light.inner_cone_rad = inner_rad;
  light.outer_cone_rad = outer_rad;
  return light;
}

// A closed room from the origin to `hi`, grey `albedo` walls facing in, a
// point light of `intensity_cd` at `light`.
inline Scene roomWithLight(float albedo, Vec3 light, float intensity_cd,
                           Vec3 hi = {3.0f, 2.5f, 4.0f}) {
  SceneBuilder b;
  const int wall = b.material({albedo, albedo, albedo});
  b.addRoom("room", {0, 0, 0}, hi, wall);
  b.addPointLight(light, intensity_cd);
  return b.scene();
}

}  // namespace svit::test

#pragma once
// Shared pieces of the stiff-and-extreme suite (CTest label `stability`):
// the test level every scale/offset/emitter case rebuilds, the metrics the
// cases compare with, and how a measured figure is printed so that
// docs/stability.md can be reproduced from the test output.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "baker/solver_fixture.h"
#include "baker/test_scenes.h"
#include "svit/baker/radiosity.h"

namespace svit::test {

constexpr double kPi = 3.14159265358979323846;

/// Prints `stability | <case> | <what> | <value>` (the docs table's row) and
/// records it as a gtest property, so `ctest --output-on-failure -V` or the
/// XML output carry every measured figure.
inline void reportFigure(const std::string& what, double value) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "?";
  std::printf("stability | %s | %s | %.6g\n", name.c_str(), what.c_str(), value);
  std::fflush(stdout);
  std::string key = what;
  for (char& c : key) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  ::testing::Test::RecordProperty(key, std::to_string(value));
}

/// Wall time of a test, printed at the end (the label must stay under ~60 s).
class StabilityTimer {
 public:
  StabilityTimer() : start_(std::chrono::steady_clock::now()) {}
  ~StabilityTimer() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::printf("[timing] %s.%s: %.3f s\n", info ? info->test_suite_name() : "?",
                info ? info->name() : "?", seconds());
  }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

inline bool finiteNonNegative(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 &&
         c.b >= 0;
}

/// The test level: a closed 4 x 3 x 5 m room (walls grey 0.6, one red wall),
/// a 1 m box standing on the floor, a 1 x 1 m emissive panel 1 cm below the
/// ceiling facing down (luminance `luminance_cd_m2`) and a point light of
/// `point_cd` candela, all scaled by `scale` about the origin and then moved
/// by `offset_m`. With the point light's intensity scaled by scale^2 the
/// irradiance is the same at every scale (an area emitter's is by itself).
struct LevelSpec {
  double scale = 1.0;
  Vec3 offset_m{0, 0, 0};
  float luminance_cd_m2 = 100.0f;
  float point_cd = 50.0f;
};

inline Scene testLevel(const LevelSpec& spec) {
  SceneBuilder b;
  auto at = [&](float x, float y, float z) -> Vec3 {
    return {float(double(x) * spec.scale + spec.offset_m.x),
            float(double(y) * spec.scale + spec.offset_m.y),
            float(double(z) * spec.scale + spec.offset_m.z)};
  };
  const int grey = b.material({0.6f, 0.6f, 0.6f});
  const int red = b.material({0.7f, 0.15f, 0.1f});
  const int box = b.material({0.5f, 0.5f, 0.5f});
  const int lamp = b.material({0.0f, 0.0f, 0.0f},
                              {spec.luminance_cd_m2, spec.luminance_cd_m2, spec.luminance_cd_m2});
  // Room [0,4] x [0,3] x [0,5], faces inwards.
  b.addQuad("floor", at(0, 0, 0), at(0, 0, 5), at(4, 0, 5), at(4, 0, 0), grey);
  b.addQuad("ceiling", at(0, 3, 0), at(4, 3, 0), at(4, 3, 5), at(0, 3, 5), grey);
  b.addQuad("wall -x", at(0, 0, 0), at(0, 3, 0), at(0, 3, 5), at(0, 0, 5), red);
  b.addQuad("wall +x", at(4, 0, 0), at(4, 0, 5), at(4, 3, 5), at(4, 3, 0), grey);
  b.addQuad("wall -z", at(0, 0, 0), at(4, 0, 0), at(4, 3, 0), at(0, 3, 0), grey);
  b.addQuad("wall +z", at(0, 0, 5), at(0, 3, 5), at(4, 3, 5), at(4, 0, 5), grey);
  // Box [2.5,3.5] x [0,1] x [1,2], faces outwards, as one object.
  const float x0 = 2.5f, x1 = 3.5f, y0 = 0.0f, y1 = 1.0f, z0 = 1.0f, z1 = 2.0f;
  b.addMesh("box",
            // top
            {at(x0, y1, z0), at(x0, y1, z1), at(x1, y1, z1), at(x0, y1, z0), at(x1, y1, z1),
             at(x1, y1, z0),
             // -x
             at(x0, y0, z0), at(x0, y0, z1), at(x0, y1, z1), at(x0, y0, z0), at(x0, y1, z1),
             at(x0, y1, z0),
             // +x
             at(x1, y0, z0), at(x1, y1, z0), at(x1, y1, z1), at(x1, y0, z0), at(x1, y1, z1),
             at(x1, y0, z1),
             // -z
             at(x0, y0, z0), at(x0, y1, z0), at(x1, y1, z0), at(x0, y0, z0), at(x1, y1, z0),
             at(x1, y0, z0),
             // +z
             at(x0, y0, z1), at(x1, y0, z1), at(x1, y1, z1), at(x0, y0, z1), at(x1, y1, z1),
             at(x0, y1, z1)},
            box);
  // Panel [1.5,2.5] x 2.99 x [2,3], facing down.
  b.addQuad("panel", at(1.5f, 2.99f, 2), at(2.5f, 2.99f, 2), at(2.5f, 2.99f, 3), at(1.5f, 2.99f, 3),
            lamp);
  if (spec.point_cd > 0) {
    b.addPointLight(at(1.0f, 2.0f, 4.0f), float(double(spec.point_cd) * spec.scale * spec.scale));
  }
  return b.scene();
}

inline float channel(const Rgb& c, int i) { return i == 0 ? c.r : i == 1 ? c.g : c.b; }

/// Area-weighted RMS of (a - b) / mean(b) over front sides, and the largest
/// per-triangle |a - b| / b among triangles whose b is at least 5% of the mean;
/// per channel, with `a` multiplied by `a_scale` first.
struct Difference {
  double rms_rel = 0;
  double max_rel = 0;
};

inline Difference compare(const std::vector<Rgb>& a, const std::vector<Rgb>& b,
                          const std::vector<float>& areas_m2, double a_scale = 1.0) {
  double area = 0, sum_b = 0;
  for (size_t t = 0; t < b.size(); ++t) {
    area += areas_m2[t];
    sum_b += areas_m2[t] * double(luminance(b[t]));
  }
  const double mean_b = sum_b / area;
  Difference d;
  double sq = 0;
  for (size_t t = 0; t < b.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const double x = double(channel(a[t], c)) * a_scale, y = double(channel(b[t], c));
      sq += areas_m2[t] * (x - y) * (x - y) / 3.0;
      if (y >= 0.05 * mean_b) d.max_rel = std::max(d.max_rel, std::abs(x - y) / y);
    }
  }
  d.rms_rel = std::sqrt(sq / area) / mean_b;
  return d;
}

}  // namespace svit::test

// Direct light of an emissive surface right beside it (texel_lighting.cpp
// sampleEmitter): a 1 m square lamp and points 2 mm to 1 m below its
// centre, its corner and the middle of its edge, against the closed form
// of a parallel rectangle. Area sampling's 1 / d^2 has unbounded variance
// there (a point 2 mm from the lamp's corner got single shadow rays worth
// 100 times its value: the fireflies of cornell_box_vinc3r's ceiling beside
// its lamp); sampling by solid angle leaves only the cosine's spread.
// Seeds fixed: a failure replays.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "baker/solver_fixture.h"
#include "baker/test_scenes.h"
#include "scene/numeric.h"
#include "svit/baker/texel_lighting.h"

namespace svit::baker {
namespace {

constexpr float kLuminance = 100.0f;  // cd/m2
constexpr float kLampY = 1.0f;        // the lamp covers x, z in [0, 1] at this height, facing down

// Irradiance at a point h below a corner of a w x l rectangle of radiance L
// facing it (the parallel-rectangle form factor, Howell's catalogue C-11).
double cornerIrradiance(double w, double l, double h) {
  const double x = w / h, y = l / h;
  const double f = (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                    y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
                   (2.0 * kPi);
  return kPi * kLuminance * f;
}

struct Case {
  Vec3 position;
  double exact;  ///< lux
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (double h : {0.002, 0.01, 0.1, 1.0}) {
    const float y = float(kLampY - h);
    out.push_back({{0.5f, y, 0.5f}, 4.0 * cornerIrradiance(0.5, 0.5, h)});
    out.push_back({{0.0f, y, 0.0f}, cornerIrradiance(1.0, 1.0, h)});
    out.push_back({{0.5f, y, 0.0f}, 2.0 * cornerIrradiance(0.5, 1.0, h)});
  }
  return out;
}

// The lamp above the cases' points (and, with `decoy`, a lamp of 100 times
// its flux under the floor, facing down: it lights none of them), each
// case's direct light lit over 64 passes (seeds 1..64), checked against
// the closed form.
void checkNearField(bool decoy) {
  test::SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int lamp = b.material({0, 0, 0}, {kLuminance, kLuminance, kLuminance});
  b.addQuad("floor", {-5, -1, -5}, {-5, -1, 5}, {5, -1, 5}, {5, -1, -5}, grey);
  // Counter-clockwise seen from below: faces -y.
  b.addQuad("lamp", {0, kLampY, 0}, {1, kLampY, 0}, {1, kLampY, 1}, {0, kLampY, 1}, lamp);
  if (decoy) b.addQuad("decoy", {-5, -2, -5}, {5, -2, -5}, {5, -2, 5}, {-5, -2, 5}, lamp);
  const Scene& scene = b.scene();
  RadiositySettings settings;
  settings.first_pass_rays = 4096;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  StopRule stop;
  stop.max_passes = 1;
  ASSERT_TRUE(solved->solver->improve(stop).ok());

  // Texels in the air facing up at the cases' points (on the floor's
  // triangle: nothing but the lamp is above them).
  const std::vector<Case> all = cases();
  TexelSet texels;
  texels.page_width = uint32_t(all.size());
  texels.page_height = texels.page_count = 1;
  for (uint32_t i = 0; i < all.size(); ++i) {
    TexelSample s;
    s.x = i;
    s.position = all[i].position;
    s.triangle = 0;
    s.normal = {0, 1, 0};
    s.coverage = 1;
    texels.samples.push_back(s);
  }
  constexpr int kSeeds = 64;
  std::vector<double> sum(all.size(), 0.0), squares(all.size(), 0.0);
  for (int seed = 1; seed <= kSeeds; ++seed) {
    TexelLightingSettings lighting;
    lighting.gather_rays = 0;
    lighting.seed = uint64_t(seed);
    Expected<std::vector<TexelIrradiance>> lit =
        lightTexels(scene, solved->geometry, *solved->caster, *solved->solver, texels, lighting);
    ASSERT_TRUE(lit.ok()) << lit.status().message();
    for (size_t i = 0; i < all.size(); ++i) {
      const double got = luminance((*lit)[i].direct);
      ASSERT_TRUE(std::isfinite(got));
      sum[i] += got;
      squares[i] += (got / all[i].exact - 1.0) * (got / all[i].exact - 1.0);
    }
  }
  for (size_t i = 0; i < all.size(); ++i) {
    const Vec3& p = all[i].position;
    // 16 stratified shadow rays over the lamp's solid angle leave the
    // cosine's spread over it, most where the lamp fills the hemisphere:
    // 3-4.6 % per pass within 10 cm (measured; 1,024 passes' means were
    // within 0.25 % of the closed form everywhere), so the mean of 64
    // passes is within 2 % (4 sigma). Area sampling read 0.02-24 times the
    // closed form at 1 cm and closer, single passes up to 300 times.
    const double rms = std::sqrt(squares[i] / kSeeds);
    EXPECT_LT(rms, 0.07) << "per-pass RMS at (" << p.x << ", " << p.y << ", " << p.z << ")";
    EXPECT_NEAR(sum[i] / kSeeds, all[i].exact, 0.02 * all[i].exact)
        << "mean at (" << p.x << ", " << p.y << ", " << p.z << ")";
  }
}

TEST(EmitterNearField, DirectLightBesideALampMatchesTheClosedFormWithoutFireflies) {
  checkNearField(false);
}

// Few emitters are picked by what they give each texel, not by their
// flux: picked by flux, the decoy would take 99 % of the shadow rays and
// leave the lamp's light ten times noisier (a ring of fireflies beside
// cornell_box_vinc3r's lamp, whose bright side strips carry 5 % of its
// flux); by importance it takes none and nothing changes.
TEST(EmitterNearField, ABrightEmitterThatLightsNoneOfThePointsTakesNoneOfTheirRays) {
  checkNearField(true);
}

}  // namespace
}  // namespace svit::baker

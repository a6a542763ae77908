// Index-map layouts (thesis 5.2.4): what each layout misses of each lobe,
// which one chooseLayout() takes, and energy: a sample inside a closed box
// hands all of its flux to the box. Plus the error paths, determinism and
// the no-allocation steady state the Runtime relies on.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <tuple>

#include "index_map_test_util.h"
#include "runtime/gl_test_context.h"

namespace svit::test {
namespace {

using gl::IndexMapRenderer;
using gl::IndexMapSettings;
using gl::Lobe;
using gl::MapLayout;
using gl::PointSample;

std::unique_ptr<IndexMapRenderer> makeRenderer(const IndexMapSettings& settings = {}) {
  Expected<std::unique_ptr<IndexMapRenderer>> r = IndexMapRenderer::create(settings);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? std::move(r).value() : nullptr;
}

PointSample sample(Lobe lobe, glm::dvec3 position, glm::dvec3 axis, float roll_rad = 0.3f) {
  PointSample s;
  s.lobe = lobe;
  s.position = vec(position);
  s.axis = vec(glm::normalize(axis));
  s.roll_rad = roll_rad;
  return s;
}

PointSample spot(double outer_deg, double inner_deg) {
  PointSample s = sample(Lobe::kSpot, {0, 0, 0}, {0, -1, 0});
  s.cos_outer = float(std::cos(outer_deg * kTestPi / 180));
  s.cos_inner = float(std::cos(inner_deg * kTestPi / 180));
  return s;
}

TEST(IndexMapLayout, MissedSharesAndChoice) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  const PointSample cosine = sample(Lobe::kCosine, {0, 0, 0}, {0, 1, 0});
  const PointSample isotropic = sample(Lobe::kIsotropic, {0, 0, 0}, {0, 1, 0});
  PointSample parallel = sample(Lobe::kParallel, {0, 0, 0}, {0, -1, 0});
  parallel.half_extent_m = 5;
  // Covering layouts miss nothing: the texel weights are normalised by their
  // own sum over the cube, so "0" is exact up to double rounding.
  EXPECT_LT(r->missedShare(MapLayout::kHemicube, cosine), 1e-12);
  EXPECT_LT(r->missedShare(MapLayout::kCube, cosine), 1e-12);
  EXPECT_LT(r->missedShare(MapLayout::kCube, isotropic), 1e-12);
  EXPECT_LT(r->missedShare(MapLayout::kParallel, parallel), 1e-12);
  EXPECT_LT(r->missedShare(MapLayout::kSingle, spot(40, 20)), 1e-12);
  // The hemicube is half the sphere; a single face of a cosine lobe misses
  // 1 - the form factor of its square: 4 corner rectangles X = Y = 1,
  // F = 4 / (2 pi) (2 X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2))) = 0.5541
  // (midpoint rule at 128^2 within 1e-4).
  EXPECT_NEAR(r->missedShare(MapLayout::kHemicube, isotropic), 0.5, 1e-3);
  const double single_cosine = r->missedShare(MapLayout::kSingle, cosine);
  const double x = 1 / std::sqrt(2.0);
  const double face_form_factor = 4 / (2 * kTestPi) * 2 * x * std::atan(x);
  EXPECT_NEAR(single_cosine, 1 - face_form_factor, 1e-4);
  const double triple_cosine = r->missedShare(MapLayout::kTriple, cosine);
  std::printf("missed shares: triple/cosine %.4f, single/cosine %.4f, hemicube/isotropic %.4f\n",
              triple_cosine, single_cosine, r->missedShare(MapLayout::kHemicube, isotropic));
  // The triple covers the cone of acos(1/3) = 70.5 degrees around its corner
  // fully and parts of the rest: it misses a few % of a cosine lobe.
  EXPECT_GT(triple_cosine, 0.005);
  EXPECT_LT(triple_cosine, 0.1);
  EXPECT_DOUBLE_EQ(r->missedShare(MapLayout::kParallel, cosine), 1.0);
  EXPECT_DOUBLE_EQ(r->missedShare(MapLayout::kCube, parallel), 1.0);

  EXPECT_EQ(r->chooseLayout(cosine), MapLayout::kHemicube);
  EXPECT_EQ(r->chooseLayout(isotropic), MapLayout::kCube);
  EXPECT_EQ(r->chooseLayout(parallel), MapLayout::kParallel);
  EXPECT_EQ(r->chooseLayout(spot(45, 30)), MapLayout::kSingle);
  // inside the triple's 70.5-degree cone
  EXPECT_EQ(r->chooseLayout(spot(65, 30)), MapLayout::kTriple);
  EXPECT_EQ(r->chooseLayout(spot(85, 30)), MapLayout::kHemicube);
  EXPECT_EQ(r->chooseLayout(spot(120, 30)), MapLayout::kCube);
}

TEST(IndexMapLayout, DiscreteNormaliserMatchesTheAnalyticIntegral) {
  // The midpoint rule's error is O(1 / res^2): ~1e-4 at 128 for smooth
  // lobes; a spot's kink at its cones costs a few texels' worth more.
  for (auto [lobe, ci, co, tol] :
       {std::tuple{Lobe::kCosine, 0.0, 0.0, 1e-4}, std::tuple{Lobe::kIsotropic, 0.0, 0.0, 1e-4},
        std::tuple{Lobe::kSpot, 0.9, 0.7, 2e-3}}) {
    const gl::LobeCoverage c = gl::lobeCoverage(lobe, ci, co, 128);
    const double analytic = gl::lobeIntegral(lobe, ci, co);
    EXPECT_NEAR(c.normaliser_face_axis / analytic, 1.0, tol) << int(lobe);
    EXPECT_NEAR(c.normaliser_corner_axis / analytic, 1.0, tol) << int(lobe);
  }
}

// A cosine sample on the floor of a closed box, and an isotropic point in a
// closed cube: every direction ends on the box, so the share is 1 up to the
// fixed-point rounding (2^-40 per texel) and float texel weights (~1e-7).
TEST(IndexMapLayout, ClosedBoxGetsAllTheFlux) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  gl::MapTriangles box;
  addBox(box, {-1, -1, -1}, {1, 1, 1}, /*inward=*/true, 0);
  r->setStaticTriangles(box);
  r->setReceiverCount(1);
  std::vector<PointSample> samples = {sample(Lobe::kCosine, {0.1, -1 + 1e-3, 0.2}, {0, 1, 0}),
                                      sample(Lobe::kIsotropic, {0.2, 0.1, -0.3}, {0, 0, 1})};
  samples[1].slot = 1;
  std::vector<float> shares;
  gl::GatherStats stats;
  ASSERT_TRUE(r->gather(samples, 2, shares, &stats).ok());
  std::printf(
      "closed box: cosine %.6f, isotropic %.6f (%u faces, %.1f ms render, %.1f ms reduce)\n",
      shares[0], shares[1], stats.faces_rendered, stats.render_ms, stats.reduce_ms);
  EXPECT_NEAR(shares[0], 1.0, 1e-3);
  EXPECT_NEAR(shares[1], 1.0, 1e-3);
  EXPECT_EQ(stats.faces_rendered, 5u + 6u);

  // The same box seen from outside its fronts (normals inward, sample
  // outside): it shows only back faces, which absorb.
  gl::MapTriangles outward;
  addBox(outward, {-1, -1, -1}, {1, 1, 1}, /*inward=*/false, 0);
  r->setStaticTriangles(outward);
  ASSERT_TRUE(r->gather(samples, 2, shares).ok());
  EXPECT_EQ(shares[0], 0.0f);
  EXPECT_EQ(shares[1], 0.0f);
}

// Form factor from a point on the floor's centre to the ceiling of a cube of
// side 2: four corner rectangles a = b = 1 at height c = 2,
// F = 4 / (2 pi) (2 X / sqrt(1 + X^2) atan(X / sqrt(1 + X^2))), X = 1/2.
// The map's error is the texel edges along the square's outline: ~64 texels
// per side at 128^2, +-1/4 texel per row on average -> ~0.2%; tolerance 0.5%.
TEST(IndexMapLayout, CeilingFormFactorMatchesAnalytic) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  gl::MapTriangles box;
  addBox(box, {-1, -1, -1}, {1, 1, 1}, true, 0, /*per_face=*/true);
  r->setStaticTriangles(box);
  r->setReceiverCount(6);
  std::vector<float> shares;
  const PointSample s = sample(Lobe::kCosine, {0, -1 + 1e-4, 0}, {0, 1, 0}, 0.37f);
  ASSERT_TRUE(r->gather({&s, 1}, 1, shares).ok());
  const double x = 0.5, q = std::sqrt(1 + x * x);
  const double analytic = 4 / (2 * kTestPi) * 2 * (x / q) * std::atan(x / q);
  std::printf("ceiling form factor: map %.5f analytic %.5f\n", shares[3], analytic);
  EXPECT_NEAR(shares[3] / analytic, 1.0, 5e-3);
  EXPECT_NEAR(rowSum(shares, 0, 6), 1.0, 1e-3);
}

// The triple layout (a 60-degree spot) in a closed box: all of the flux.
TEST(IndexMapLayout, ClosedBoxGetsAllOfATripleSpot) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  gl::MapTriangles box;
  addBox(box, {-1, -1, -1}, {1, 1, 1}, true, 0);
  r->setStaticTriangles(box);
  r->setReceiverCount(1);
  PointSample s = spot(60, 30);
  s.axis = vec(glm::normalize(glm::dvec3(0.3, -1, 0.2)));
  s.position = {0.1f, 0.5f, -0.2f};
  ASSERT_EQ(r->chooseLayout(s), MapLayout::kTriple);
  std::vector<float> shares;
  gl::GatherStats stats;
  ASSERT_TRUE(r->gather({&s, 1}, 1, shares, &stats).ok());
  EXPECT_EQ(stats.faces_rendered, 3u);
  EXPECT_NEAR(shares[0], 1.0, 1e-3);
}

// Dynamic triangles are numbered after the static ones: a scene split into
// a static and a dynamic set gives the very maps (and bits) of the whole,
// own_triangle included.
TEST(IndexMapLayout, DynamicTrianglesFollowTheStaticOnes) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  gl::MapTriangles room, crate, whole;
  addBox(room, {-2, -1, -2}, {2, 1.5, 2}, true, 0, true);
  addBox(crate, {-0.5, -1, -0.5}, {0.3, 0.2, 0.4}, false, 6, true);
  // A field of small triangles on the crate's far side exercises the fallback.
  for (int i = 0; i < 40; ++i) {
    const glm::dvec3 p(-0.45 + 0.02 * i, -0.6 + 0.01 * i, 0.41);
    addTriangle(crate, p, p + glm::dvec3(0.01, 0, 0), p + glm::dvec3(0, 0.01, 0), 12, 12);
  }
  whole = room;
  whole.positions.insert(whole.positions.end(), crate.positions.begin(), crate.positions.end());
  whole.front_receiver.insert(whole.front_receiver.end(), crate.front_receiver.begin(),
                              crate.front_receiver.end());
  whole.back_receiver.insert(whole.back_receiver.end(), crate.back_receiver.begin(),
                             crate.back_receiver.end());
  std::vector<PointSample> samples = {sample(Lobe::kIsotropic, {0.2, 0.3, 1.0}, {0, 1, 0}),
                                      sample(Lobe::kCosine, {0.1, 0.2 + 1e-3, 0}, {0, 1, 0})};
  // the crate's top (+y, second pair)
  samples[1].own_triangle = uint32_t(room.triangleCount() + 6);
  samples[1].slot = 1;
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  r->setReceiverCount(13);
  std::vector<float> split, joined;
  r->setStaticTriangles(room);
  r->setDynamicTriangles(crate);
  gl::GatherStats stats;
  ASSERT_TRUE(r->gather(samples, 2, split, &stats).ok());
  EXPECT_GT(stats.fallback_triangles, 0u);
  r->setStaticTriangles(whole);
  r->setDynamicTriangles({});
  ASSERT_TRUE(r->gather(samples, 2, joined).ok());
  ASSERT_EQ(split.size(), joined.size());
  EXPECT_EQ(std::memcmp(split.data(), joined.data(), split.size() * sizeof(float)), 0);
  EXPECT_GT(split[12], 0.0f);      // the small field gets light
  EXPECT_GT(split[13 + 3], 0.0f);  // the ceiling sees the crate-top sample
}

TEST(IndexMapLayout, CreateWithoutContextIsAnError) {
  Expected<std::unique_ptr<IndexMapRenderer>> r = IndexMapRenderer::create({});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(r.status().message().find("no current OpenGL context"), std::string::npos)
      << r.status().message();
}

TEST(IndexMapLayout, BadSettingsAreErrorsNamingTheField) {
  IndexMapSettings s;
  s.resolution = 4;
  Expected<std::unique_ptr<IndexMapRenderer>> r = IndexMapRenderer::create(s);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(r.status().message().find("resolution 4"), std::string::npos) << r.status().message();
  s = {};
  s.resolution = 4096;
  s.max_batch_samples = 64;  // 4096^2 x 384 layers x 12 bytes: 77 GiB
  r = IndexMapRenderer::create(s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("MiB of maps"), std::string::npos) << r.status().message();
}

TEST(IndexMapLayout, BadSamplesAndTrianglesAreErrorsAndLeaveSharesAlone) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  auto r = makeRenderer();
  ASSERT_TRUE(r);
  gl::MapTriangles box;
  addBox(box, {-1, -1, -1}, {1, 1, 1}, true, 0);
  r->setStaticTriangles(box);
  r->setReceiverCount(1);
  std::vector<float> shares = {42.0f};
  PointSample s = sample(Lobe::kIsotropic, {0, 0, 0}, {0, 1, 0});
  s.position.y = std::nanf("");
  Status status = r->gather({&s, 1}, 1, shares);
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput);
  EXPECT_NE(status.message().find("sample 0: position"), std::string::npos) << status.message();
  s = sample(Lobe::kIsotropic, {0, 0, 0}, {0, 1, 0});
  s.axis = {0, 0, 0};
  EXPECT_NE(r->gather({&s, 1}, 1, shares).message().find("axis"), std::string::npos);
  s = sample(Lobe::kIsotropic, {0, 0, 0}, {0, 1, 0});
  s.slot = 3;
  EXPECT_NE(r->gather({&s, 1}, 1, shares).message().find("slot 3 >= slot count 1"),
            std::string::npos);
  ASSERT_EQ(shares.size(), 1u);
  EXPECT_EQ(shares[0], 42.0f);

  // A bad triangle set sticks until a good one replaces it.
  gl::MapTriangles broken = box;
  broken.positions[7].x = std::numeric_limits<float>::infinity();
  r->setDynamicTriangles(broken);
  s = sample(Lobe::kIsotropic, {0, 0, 0}, {0, 1, 0});
  status = r->gather({&s, 1}, 1, shares);
  EXPECT_EQ(status.code(), StatusCode::kInvalidInput);
  EXPECT_NE(status.message().find("dynamic triangle 2: corner 1 is not finite"), std::string::npos)
      << status.message();
  EXPECT_EQ(shares[0], 42.0f);
  r->setDynamicTriangles({});
  EXPECT_TRUE(r->gather({&s, 1}, 1, shares).ok());
  EXPECT_NEAR(shares[0], 1.0, 1e-3);
}

// Integer atomics commute: two gathers agree bit for bit, and once the
// buffers fit, a gather allocates nothing (the Runtime's static levels).
TEST(IndexMapLayout, DeterministicAndAllocationFreeWhenSteady) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  IndexMapSettings settings;
  settings.max_batch_samples = 3;  // several batches
  auto r = makeRenderer(settings);
  ASSERT_TRUE(r);
  gl::MapTriangles scene;
  addBox(scene, {-2, -1, -2}, {2, 1.5, 2}, true, 0, true);
  addBox(scene, {-0.5, -1, -0.5}, {0.3, 0.2, 0.4}, false, 6, true);
  r->setStaticTriangles(scene);
  gl::MapTriangles moving;
  addBox(moving, {0.6, -1, 0.6}, {1.2, -0.2, 1.1}, false, 12, true);
  r->setDynamicTriangles(moving);
  r->setReceiverCount(18);
  std::vector<PointSample> samples;
  for (int i = 0; i < 8; ++i) {
    PointSample s = sample(i % 2 ? Lobe::kIsotropic : Lobe::kCosine,
                           {-1.5 + 0.3 * i, 1.0, -1 + 0.2 * i}, {0.1, -1, 0.2}, 0.7f * float(i));
    s.slot = uint32_t(i % 3);
    s.weight = 0.25f;
    samples.push_back(s);
  }
  std::vector<float> first, second;
  gl::GatherStats stats;
  ASSERT_TRUE(r->gather(samples, 3, first, &stats).ok());
  ASSERT_TRUE(r->gather(samples, 3, second, &stats).ok());
  ASSERT_EQ(first.size(), 3u * 18u);
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
  EXPECT_EQ(stats.buffer_allocations, 0u);
  EXPECT_EQ(stats.samples, 8u);
  // Slot 0 holds samples 0, 3, 6 at weight 1/4 each, all inside the room.
  EXPECT_NEAR(rowSum(first, 0, 18), 0.75, 1e-3);
  // Re-setting the same dynamic set allocates nothing either.
  r->setDynamicTriangles(moving);
  ASSERT_TRUE(r->gather(samples, 3, second, &stats).ok());
  EXPECT_EQ(stats.buffer_allocations, 0u);
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace svit::test

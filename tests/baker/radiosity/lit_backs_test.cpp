// Which double-sided backs light reaches (lit_backs.h), on scenes built in
// code: a closed room of double-sided walls lit from inside has no lit back
// and so the atlas of a one-sided room; under a sky, or beside a lamp
// outside, its outer faces are lit; a back that sees only the void stays
// dark, one that sees a lit front or a lit back is lit; and the answer does
// not depend on the thread count. End to end through bakes: leak_test.cpp.

#include <gtest/gtest.h>

#include <numeric>

#include "baker/solver_fixture.h"
#include "baker/test_scenes.h"
#include "svit/baker/lightmap_atlas.h"

namespace svit::baker {
namespace {

using test::SceneBuilder;

size_t litCount(const std::vector<uint8_t>& lit) {
  return size_t(std::accumulate(lit.begin(), lit.end(), 0));
}

std::vector<uint8_t> litBacks(const Scene& scene, int threads = 1, LitBacksStats* stats = nullptr) {
  RadiositySettings settings;
  settings.threads = threads;
  std::unique_ptr<test::Solved> solved = test::prepareSolver(scene, settings);
  if (!solved->solver) return {};
  return solved->solver->litBacks(stats);
}

// A 3 x 2.5 x 4 m room, faces inward, of one material, with a lamp inside.
Scene lampInRoom(bool double_sided) {
  SceneBuilder b;
  b.addRoom("room", {0, 0, 0}, {3, 2.5f, 4}, b.material({0.5f, 0.5f, 0.5f}, {}, double_sided));
  b.addPointLight({1.5f, 1.2f, 2}, 100);
  return b.scene();
}

TEST(LitBacks, AClosedRoomLitFromInsideHasNoLitBackAndTheAtlasOfAOneSidedRoom) {
  LitBacksStats stats;
  const std::vector<uint8_t> lit = litBacks(lampInRoom(true), 1, &stats);
  ASSERT_EQ(lit.size(), 12u);
  EXPECT_EQ(litCount(lit), 0u) << "the outer faces see only the void";
  EXPECT_EQ(stats.double_sided, 12u);
  EXPECT_EQ(stats.lit, 0u);
  EXPECT_EQ(stats.sealed, 12u) << "the flood from the lamp never left the room";

  const auto texels = [](const Scene& scene, const std::vector<uint8_t>& backs) {
    Expected<BakeGeometry> geometry = flattenStaticGeometry(scene);
    EXPECT_TRUE(geometry.ok());
    AtlasSettings settings;
    settings.texels_per_m = 16;
    settings.lit_backs = backs;
    Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, *geometry, settings);
    EXPECT_TRUE(atlas.ok()) << atlas.status().message();
    return atlas.ok() ? atlas->back_triangles.size() * 1000 + atlas->triangle_page.size() : 0;
  };
  EXPECT_EQ(texels(lampInRoom(true), lit), texels(lampInRoom(false), {}))
      << "no back faces: the faces and backs of a one-sided room";
  EXPECT_NE(texels(lampInRoom(true), {}), texels(lampInRoom(false), {}))
      << "without lit_backs every double-sided back is a face";
}

TEST(LitBacks, UnderASkyOrBesideALampOutsideTheOuterFacesAreLit) {
  Scene sky = lampInRoom(true);
  sky.sky.model = SkyModel::kUniform;
  sky.sky.zenith_luminance = {1000, 1000, 1000};
  const std::vector<uint8_t> sky_lit = litBacks(sky);
  ASSERT_EQ(sky_lit.size(), 12u);
  EXPECT_EQ(sky_lit[0] + sky_lit[1], 0) << "the floor's underside sees the sky's black ground";
  EXPECT_EQ(litCount(sky_lit), 10u) << "every other outer face sees the sky";

  Scene lamp = lampInRoom(true);
  lamp.lights.front().position = {1.5f, 6, 2};  // above the room, outside
  const std::vector<uint8_t> lit = litBacks(lamp);
  ASSERT_EQ(lit.size(), 12u);
  EXPECT_EQ(lit[2] + lit[3], 2) << "the ceiling's outside faces the lamp";
  EXPECT_EQ(lit[0] + lit[1], 0) << "the floor's underside sees only the void";
}

// An open box (Cornell's five walls) lit inside, and a double-sided panel
// in front of its opening whose back looks into the box.
TEST(LitBacks, ABackSeeingALitFrontIsLitOneSeeingTheVoidIsNot) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f}, {}, true);
  b.addQuad("floor", {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}, grey);
  b.addQuad("ceiling", {0, 2, 0}, {2, 2, 0}, {2, 2, 2}, {0, 2, 2}, grey);
  b.addQuad("-x", {0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}, grey);
  b.addQuad("+x", {2, 0, 0}, {2, 0, 2}, {2, 2, 2}, {2, 2, 0}, grey);
  b.addQuad("back", {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, grey);
  // Front faces +z (away from the box): its back looks into the box.
  b.addQuad("panel", {0, 0, 4}, {2, 0, 4}, {2, 2, 4}, {0, 2, 4}, grey);
  b.addPointLight({1, 1, 1}, 100);
  const std::vector<uint8_t> lit = litBacks(b.scene());
  ASSERT_EQ(lit.size(), 12u);
  for (size_t t = 0; t < 10; ++t) EXPECT_EQ(lit[t], 0) << "box wall triangle " << t;
  EXPECT_EQ(lit[10] + lit[11], 2) << "the panel's back sees the lit inside (and the lamp)";
}

// Two double-sided panels whose backs face each other, beside a lamp-lit
// box open at the top (so the flood reaches the space around them, though
// no light goes there): each back sees only the other's back and the void,
// so both settle dark; then the lamp moves out between them and lights both.
TEST(LitBacks, BacksThatSeeOnlyEachOtherSettleDarkUnlessOneIsLit) {
  const auto scene = [](Vec3 lamp) {
    SceneBuilder b;
    const int grey = b.material({0.5f, 0.5f, 0.5f});
    b.addQuad("floor", {10, 0, 0}, {10, 0, 2}, {12, 0, 2}, {12, 0, 0}, grey);
    b.addQuad("-x", {10, 0, 0}, {10, 2, 0}, {10, 2, 2}, {10, 0, 2}, grey);
    b.addQuad("+x", {12, 0, 0}, {12, 0, 2}, {12, 2, 2}, {12, 2, 0}, grey);
    b.addQuad("-z", {10, 0, 0}, {12, 0, 0}, {12, 2, 0}, {10, 2, 0}, grey);
    b.addQuad("+z", {10, 0, 2}, {10, 2, 2}, {12, 2, 2}, {12, 0, 2}, grey);
    const int panel = b.material({0.5f, 0.5f, 0.5f}, {}, true);
    b.addQuad("a", {0, 0, 0}, {0, 0, 2}, {0, 2, 2}, {0, 2, 0}, panel);              // front -x
    b.addQuad("b", {0.5f, 0, 0}, {0.5f, 2, 0}, {0.5f, 2, 2}, {0.5f, 0, 2}, panel);  // front +x
    b.addPointLight(lamp, 100);
    return b.scene();
  };
  LitBacksStats stats;
  const std::vector<uint8_t> dark = litBacks(scene({11, 1, 1}), 1, &stats);
  ASSERT_EQ(dark.size(), 14u);
  EXPECT_EQ(litCount(dark), 0u);
  EXPECT_EQ(stats.sealed, 0u) << "the flood reached them: the rays decided";
  EXPECT_GE(stats.rounds, 1);
  const std::vector<uint8_t> lit = litBacks(scene({0.25f, 1, 1}));
  ASSERT_EQ(lit.size(), 14u);
  EXPECT_EQ(litCount(lit), 4u);
}

TEST(LitBacks, TheSameForOneAndTwoThreads) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f}, {}, true);
  for (int i = 0; i < 40; ++i) {
    const float x = float(i % 8), z = float(i / 8);
    b.addQuad("tile", {x, 0, z}, {x, 0, z + 0.9f}, {x + 0.9f, 0, z + 0.9f}, {x + 0.9f, 0, z}, grey);
    b.addQuad("roof", {x, 2 + 0.1f * float(i % 3), z}, {x + 0.9f, 2, z}, {x + 0.9f, 2, z + 0.9f},
              {x, 2, z + 0.9f}, grey);
  }
  b.addPointLight({4, 1, 2.5f}, 100);
  const std::vector<uint8_t> one = litBacks(b.scene(), 1);
  EXPECT_EQ(one, litBacks(b.scene(), 2));
  EXPECT_GT(litCount(one), 0u);
}

}  // namespace
}  // namespace svit::baker

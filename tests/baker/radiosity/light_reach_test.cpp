// The leak guard's voxel flood (light_reach.h) on scenes built in code: a
// lamp inside a closed room reaches every inner face, corners included, and
// nothing outside; a lamp outside a flat level's grid floods from outside;
// a sealed space too small to be a room counts as reached; the guard is off
// past its voxel size. End to end through bakes: leak_test.cpp.

#include <gtest/gtest.h>

#include <vector>

#include "baker/test_scenes.h"
#include "radiosity/light_reach.h"
#include "radiosity/light_sources.h"
#include "svit/baker/bake_geometry.h"

namespace svit::baker {
namespace {

using test::SceneBuilder;

struct Built {
  BakeGeometry geometry;
  LightReach reach;
};

Built build(const Scene& scene, double max_voxel_m = 0.25) {
  Built b;
  Expected<BakeGeometry> geometry = flattenStaticGeometry(scene);
  EXPECT_TRUE(geometry.ok()) << geometry.status().message();
  b.geometry = std::move(geometry).value();
  Expected<std::vector<LightSource>> lights = makeLightSources(scene, b.geometry);
  EXPECT_TRUE(lights.ok()) << lights.status().message();
  b.reach = LightReach::build(b.geometry, *lights, max_voxel_m);
  return b;
}

// A 3 x 2.5 x 4 m inward room with a lamp in it, on a 12 m ground outside.
Scene lampInRoom() {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addQuad("ground", {-4, -0.01f, -4}, {-4, -0.01f, 8}, {8, -0.01f, 8}, {8, -0.01f, -4}, grey);
  b.addRoom("room", {0, 0, 0}, {3, 2.5f, 4}, grey);
  b.addPointLight({1.5f, 1.2f, 2}, 100);
  return b.scene();
}

TEST(LightReach, ALampInAClosedRoomReachesItsInsideAndCornersButNotOutside) {
  const Built b = build(lampInRoom());
  ASSERT_TRUE(b.reach.stats().enabled);
  const glm::dvec3 up(0, 1, 0), down(0, -1, 0);
  EXPECT_TRUE(b.reach.reaches({1.5, 0, 2}, up)) << "the floor's middle";
  EXPECT_TRUE(b.reach.reaches({1.5, 2.5, 2}, down)) << "the ceiling";
  // Outside: the ground beside the room and the room's outer faces.
  EXPECT_FALSE(b.reach.reaches({6, -0.01, 6}, up));
  EXPECT_FALSE(b.reach.reaches({-0.0, 1.2, 2}, {-1, 0, 0}));
  EXPECT_GT(b.reach.stats().reached_fraction, 0.0);
  EXPECT_LT(b.reach.stats().reached_fraction, 0.5);
}

// The room alone: its corner is the grid's, so its walls lie on voxel
// boundaries and fill the voxels in front of the corner and the walls' feet.
TEST(LightReach, RoomCornersAndWallFeetWalledInByVoxelsCountAsReached) {
  SceneBuilder b;
  b.addRoom("room", {0, 0, 0}, {3, 2.5f, 4}, b.material({0.5f, 0.5f, 0.5f}));
  b.addPointLight({0.4f, 0.5f, 1}, 100);
  const Built built = build(b.scene());
  ASSERT_TRUE(built.reach.stats().enabled);
  EXPECT_TRUE(built.reach.reaches({0, 0, 0}, {0, 1, 0})) << "the floor's corner";
  EXPECT_TRUE(built.reach.reaches({0, 0, 0}, {1, 0, 0})) << "the -x wall's corner";
  EXPECT_TRUE(built.reach.reaches({0, 0.005, 2}, {1, 0, 0})) << "a wall's foot";
}

// A closed crate hanging 3 cm over the lit floor (less than this level's
// 3.3 cm voxel; its bottom fills the voxel over the floor's): the floor
// under it looks into the crate's bottom, not through it into the crate's
// sealed inside.
TEST(LightReach, TheFloorUnderACrateHangingWithinAVoxelCountsAsReached) {
  Scene scene = lampInRoom();
  SceneBuilder b;
  b.scene() = std::move(scene);
  b.addRoom("crate", {0.6f, 0.03f, 0.6f}, {1.2f, 0.63f, 1.2f}, b.material({0.5f, 0.5f, 0.5f}));
  const Built built = build(b.scene());
  ASSERT_TRUE(built.reach.stats().enabled);
  EXPECT_FALSE(built.reach.reaches({0.9, 0.3, 0.9}, {0, 1, 0})) << "inside the crate: sealed";
  EXPECT_TRUE(built.reach.reaches({0.9, 0, 0.9}, {0, 1, 0})) << "the floor under the crate";
  EXPECT_TRUE(built.reach.reaches({0.9, 0.03, 1.25}, {0, 0, 1})) << "the room side of its wall";
}

TEST(LightReach, ALampAboveAFlatLevelFloodsFromOutsideItsGrid) {
  SceneBuilder b;
  b.addQuad("floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2},
            b.material({0.5f, 0.5f, 0.5f}));
  b.addPointLight({0, 3, 0}, 1000);  // the grid is centimetres thick: the lamp is outside it
  const Built built = build(b.scene());
  ASSERT_TRUE(built.reach.stats().enabled);
  EXPECT_TRUE(built.reach.reaches({0.5, 0, 0.5}, {0, 1, 0}));
}

TEST(LightReach, ASealedSpaceTooSmallToBeARoomCountsAsReached) {
  Scene scene = lampInRoom();
  SceneBuilder b;
  b.scene() = std::move(scene);
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  // A closed 10 cm crate (three voxels of this level's 3.3 cm: a pocket of
  // a few free voxels) and a closed 1 m crate, both inside the lit room.
  b.addRoom("tiny crate", {0.5f, 0.5f, 0.5f}, {0.6f, 0.6f, 0.6f}, grey);
  b.addRoom("crate", {1.8f, 0.2f, 2.5f}, {2.8f, 1.2f, 3.5f}, grey);
  const Built built = build(b.scene());
  EXPECT_GT(built.reach.stats().sealed_pockets_opened, 0u);
  EXPECT_TRUE(built.reach.reaches({0.55, 0.5, 0.55}, {0, 1, 0}));
  EXPECT_FALSE(built.reach.reaches({2.3, 0.2, 3.0}, {0, 1, 0}))
      << "inside the 1 m crate: a sealed room";
}

TEST(LightReach, OffWhereItsVoxelWouldBeCoarserThanAllowed) {
  const Built b = build(lampInRoom(), 1e-3);
  EXPECT_FALSE(b.reach.stats().enabled);
  EXPECT_TRUE(b.reach.reaches({6, -0.01, 6}, {0, 1, 0}));
}

}  // namespace
}  // namespace svit::baker

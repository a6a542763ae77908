// Occlusion culling of index maps and of the view pass (index_map_occlusion.h)
// on a row of closed rooms, the first two joined by a hole: the same shares,
// seen bits and view pixels as drawing everything, for far fewer triangles.

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "index_map_test_util.h"
#include "runtime/gl_test_context.h"

namespace svit::test {
namespace {

using gl::IndexMapRenderer;
using gl::IndexMapSettings;
using gl::Lobe;
using gl::PointSample;

constexpr int kRooms = 8;
constexpr double kPitch = 4.0, kInside = 3.8, kHeight = 3.0, kDepth = 4.0;
constexpr int kCells = 8;  // quads per wall edge: 128 triangles a wall

// One wall piece at x, y in [y0, y1], z in [z0, z1], front toward +x
// (`toward_plus`) or -x.
void wallPiece(gl::MapTriangles& t, double x, double y0, double y1, double z0, double z1,
               bool toward_plus, uint32_t receiver) {
  const glm::dvec3 o(x, y0, z0), dy(0, y1 - y0, 0), dz(0, 0, z1 - z0);
  if (toward_plus) {
    addQuad(t, o, dy, dz, receiver, gl::kNoReceiver, kCells);
  } else {
    addQuad(t, o, dz, dy, receiver, gl::kNoReceiver, kCells);
  }
}

// An x wall, with a 1 x 1 m hole in its middle when `hole`.
void xWall(gl::MapTriangles& t, double x, bool toward_plus, bool hole, uint32_t receiver) {
  if (!hole) return wallPiece(t, x, 0, kHeight, 0, kDepth, toward_plus, receiver);
  wallPiece(t, x, 0, 1, 0, kDepth, toward_plus, receiver);
  wallPiece(t, x, 2, kHeight, 0, kDepth, toward_plus, receiver);
  wallPiece(t, x, 1, 2, 0, 1.5, toward_plus, receiver);
  wallPiece(t, x, 1, 2, 2.5, kDepth, toward_plus, receiver);
}

// Rooms along +x, each the inside of a box (6 receivers per room); rooms 0
// and 1 see each other through a hole in their shared walls.
gl::MapTriangles rowOfRooms() {
  gl::MapTriangles t;
  for (int i = 0; i < kRooms; ++i) {
    const double x0 = kPitch * i, x1 = x0 + kInside;
    const uint32_t r = uint32_t(6 * i);
    const glm::dvec3 dx(kInside, 0, 0), dy(0, kHeight, 0), dz(0, 0, kDepth);
    addQuad(t, {x0, 0, 0}, dz, dx, r, gl::kNoReceiver, kCells);            // floor, up
    addQuad(t, {x0, kHeight, 0}, dx, dz, r + 1, gl::kNoReceiver, kCells);  // ceiling, down
    addQuad(t, {x0, 0, 0}, dx, dy, r + 2, gl::kNoReceiver, kCells);        // z = 0, toward +z
    addQuad(t, {x0, 0, kDepth}, dy, dx, r + 3, gl::kNoReceiver, kCells);   // z = depth, toward -z
    xWall(t, x0, true, i == 1, r + 4);
    xWall(t, x1, false, i == 0, r + 5);
  }
  return t;
}

std::unique_ptr<IndexMapRenderer> makeRenderer(bool occlusion) {
  IndexMapSettings settings;
  settings.occlusion_culling = occlusion;
  Expected<std::unique_ptr<IndexMapRenderer>> r = IndexMapRenderer::create(settings);
  EXPECT_TRUE(r.ok()) << r.status().message();
  if (!r.ok()) return nullptr;
  std::unique_ptr<IndexMapRenderer> renderer = std::move(r).value();
  renderer->setStaticTriangles(rowOfRooms());
  renderer->setReceiverCount(6 * kRooms);
  return renderer;
}

std::vector<PointSample> samples() {
  std::vector<PointSample> out;
  auto add = [&](Lobe lobe, glm::dvec3 p, glm::dvec3 axis, uint32_t slot) {
    PointSample s;
    s.lobe = lobe;
    s.position = vec(p);
    s.axis = vec(glm::normalize(axis));
    s.roll_rad = 0.3f;
    s.slot = slot;
    out.push_back(s);
  };
  add(Lobe::kIsotropic, {1.0, 2.7, 1.2}, {0, -1, 0}, 0);          // a lamp in room 0
  add(Lobe::kCosine, {3.7, 1.5, 2.0}, {-1, 0.1, 0}, 1);           // room 0's holed wall, facing in
  add(Lobe::kCosine, {6.0, 0.001, 2.0}, {0, 1, 0}, 2);            // room 1's floor
  add(Lobe::kIsotropic, {4 * kPitch + 2, 1.5, 2}, {0, 1, 0}, 3);  // a lamp in a closed room
  return out;
}

TEST(IndexMapOcclusionRender, MapsAreThoseOfDrawingEverything) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  std::unique_ptr<IndexMapRenderer> all = makeRenderer(false), culled = makeRenderer(true);
  ASSERT_TRUE(all && culled);
  const std::vector<PointSample> list = samples();
  std::vector<float> shares_all, shares_culled;
  std::vector<uint32_t> seen_all, seen_culled;
  gl::GatherStats stats_all, stats_culled;
  ASSERT_TRUE(all->gather(list, 4, shares_all, &stats_all, &seen_all).ok());
  ASSERT_TRUE(culled->gather(list, 4, shares_culled, &stats_culled, &seen_culled).ok());
  std::printf(
      "occlusion: %llu triangles drawn against %llu (%llu hidden); fallback credits %u against "
      "%u\n",
      (unsigned long long)stats_culled.triangles_drawn,
      (unsigned long long)stats_all.triangles_drawn,
      (unsigned long long)stats_culled.triangles_hidden, stats_culled.fallback_triangles,
      stats_all.fallback_triangles);
  // No coincident surfaces here, so no depth ties: exactly the same.
  EXPECT_EQ(shares_culled, shares_all);
  EXPECT_EQ(seen_culled, seen_all);
  EXPECT_EQ(stats_culled.fallback_triangles, stats_all.fallback_triangles);
  EXPECT_EQ(stats_all.triangles_hidden, 0u);
  // Each sample sees one room, or two through the hole, of eight; chunk
  // boxes are coarser than that (measured: 56 % of the triangles drawn).
  EXPECT_GT(stats_culled.triangles_hidden, 0u);
  EXPECT_LT(double(stats_culled.triangles_drawn), 0.7 * double(stats_all.triangles_drawn));
  // Room 1 is lit from room 0 through the hole, and its floor lights room 0.
  EXPECT_GT(shares_all[0 * 6 * kRooms + 6 + 5], 0.0f);  // the lamp: room 1's far wall
  EXPECT_GT(shares_all[2 * 6 * kRooms + 1], 0.0f);      // room 1's floor: room 0's ceiling
}

TEST(IndexMapOcclusionRender, ViewPixelsAreThoseOfDrawingEverything) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  std::unique_ptr<IndexMapRenderer> all = makeRenderer(false), culled = makeRenderer(true);
  ASSERT_TRUE(all && culled);
  // From room 0 toward the hole, and from a closed room.
  for (const glm::dvec3& eye :
       {glm::dvec3(0.5, 1.5, 2.0), glm::dvec3(4 * kPitch + 0.5, 1.5, 2.0)}) {
    gl::ViewFrame view;
    view.eye = vec(eye);
    view.forward = {1, 0, 0};
    view.right = {0, 0, 1};
    view.up = {0, 1, 0};
    view.tan_half_x = 1.2f;
    view.tan_half_y = 0.7f;
    std::vector<uint32_t> pixels_all, pixels_culled;
    ASSERT_TRUE(all->countViewPixels(view, 160, 90, pixels_all).ok());
    ASSERT_TRUE(culled->countViewPixels(view, 160, 90, pixels_culled).ok());
    EXPECT_EQ(pixels_culled, pixels_all);
    uint32_t seen_rooms = 0;
    for (int room = 0; room < kRooms; ++room) {
      uint32_t sum = 0;
      for (int f = 0; f < 6; ++f) sum += pixels_all[size_t(6 * room + f)];
      if (sum > 0) ++seen_rooms;
    }
    EXPECT_EQ(seen_rooms, eye.x < kPitch ? 2u : 1u);
  }
}

}  // namespace
}  // namespace svit::test

// Importance caching (thesis 5.9-5.10) on the generated 2 x 2
// house: the view decides which out-of-date emitters refresh, a door that
// opens promotes the next room's lamps, a lamp behind a shade still counts
// through its cached factors, a switched lamp shows in the next frame, an
// object entering an emitter's reach invalidates it and nothing else, and
// the schedule replays exactly. Behaviour only; timings are in
// tests/bench/importance_bench.cpp.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "runtime/gl_test_context.h"
#include "runtime/runtime_house_util.h"
#include "runtime/runtime_test_util.h"
#include "svit/runtime.h"

namespace svit {
namespace {

using test::cachingSettings;
using test::house;
using test::makeRuntime;
using test::nodeIndex;
using test::settle;
using test::translated;

int lightIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    if (scene.lights[i].name == name || scene.nodes[size_t(scene.lights[i].node)].name == name)
      return int(i);
  }
  ADD_FAILURE() << "no light " << name;
  return -1;
}

uint32_t bakeEmitterOfLight(const BakeData& bake, int light) {
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    if (bake.emitters[i].kind == BakeEmitter::Kind::kLight && int(bake.emitters[i].index) == light)
      return i;
  }
  ADD_FAILURE() << "no bake emitter for light " << light;
  return kInvalidId;
}

/// The lamps of the house by node name ("lamp_0_0_a" ...): their emitterStates() index.
struct Lamps {
  std::map<std::string, uint32_t> bake_emitter;
  uint32_t state(const Runtime& runtime, const std::string& lamp) const {
    const std::vector<EmitterState> states = runtime.emitterStates();
    for (uint32_t i = 0; i < states.size(); ++i) {
      if (states[i].type == EmitterType::kBakedLight &&
          states[i].bake_emitter == bake_emitter.at(lamp))
        return i;
    }
    ADD_FAILURE() << "no emitter state for " << lamp;
    return 0;
  }
  double importance(const Runtime& runtime, const std::string& lamp) const {
    return runtime.emitterStates()[state(runtime, lamp)].importance;
  }
};

Lamps houseLamps(const test::BakedLevel& level) {
  Lamps lamps;
  for (const char* room : {"0_0", "1_0", "0_1", "1_1"}) {
    for (const char* which : {"a", "b"}) {
      const std::string name = std::string("lamp_") + room + "_" + which;
      lamps.bake_emitter[name] = bakeEmitterOfLight(level.bake, lightIndex(level.scene, name));
    }
  }
  return lamps;
}

/// Room (0, 0), looking along +z at the doorway into room (0, 1).
RuntimeView viewInRoom00() {
  RuntimeView view;
  view.position = {2.1f, 1.6f, 0.6f};
  view.look_at = {1.8f, 1.0f, 4.2f};
  view.yfov_rad = 1.2f;
  view.aspect = 16.0f / 9.0f;
  return view;
}

Mat4 withYRotation(const Mat4& placed, float angle_rad) {
  glm::mat4 m = glm::make_mat4(placed.m.data());
  const glm::vec3 t(m[3]);
  const float c = std::cos(angle_rad), s = std::sin(angle_rad);
  glm::mat4 r(1.0f);
  r[0] = glm::vec4(c, 0, -s, 0);
  r[2] = glm::vec4(s, 0, c, 0);
  r[3] = glm::vec4(t, 1);
  Mat4 out;
  for (int i = 0; i < 16; ++i) out.m[size_t(i)] = glm::value_ptr(r)[i];
  return out;
}

/// Slides every table a little (a different offset each frame): every lamp
/// whose light reaches a table goes out of date.
void nudgeTables(Runtime& runtime, const std::map<ObjectId, Mat4>& start, int frame) {
  for (const auto& [id, placed] : start) {
    ASSERT_TRUE(
        runtime.setObjectTransform(id, translated(placed, 0.05f * float(frame % 4), 0.0f)).ok());
  }
}

/// The tables of the viewed room (0, 0) and of the far room (1, 1).
std::map<ObjectId, Mat4> tables(const Runtime& runtime, const Scene& scene) {
  std::map<ObjectId, Mat4> out;
  for (const char* name : {"table_0_0", "table_1_1"}) {
    const ObjectId id = runtime.objectForNode(nodeIndex(scene, name));
    EXPECT_NE(id, kInvalidId) << name;
    Expected<ObjectInfo> info = runtime.objectInfo(id);
    if (info.ok()) out[id] = info->world_from_object;
  }
  return out;
}

/// One refresh in a log: frame, emitter, reason.
using RefreshLog = std::vector<std::tuple<int, uint32_t, RefreshReason>>;

/// Sixteen frames of tables sliding in rooms (0, 0) and (1, 1), seen from room (0, 0).
/// No sample budget: the schedule is the intervals alone (the budget's
/// share-out is tested in tests/runtime/facade/refresh_scheduler_test.cpp).
RefreshLog slideTablesAndLog(const test::BakedLevel& level, std::unique_ptr<Runtime>& runtime) {
  RuntimeSettings settings = cachingSettings();
  settings.max_samples_per_frame = 0;
  runtime = makeRuntime(level, settings);
  if (!runtime) return {};
  EXPECT_TRUE(runtime->setView(viewInRoom00()).ok());
  settle(*runtime, 0);
  const std::map<ObjectId, Mat4> start = tables(*runtime, level.scene);
  RefreshLog log;
  for (int frame = 1; frame <= 16; ++frame) {
    nudgeTables(*runtime, start, frame);
    const FrameStats stats = runtime->update(0);
    EXPECT_TRUE(stats.error.empty()) << stats.error;
    for (const EmitterRefresh& r : stats.refreshes) log.emplace_back(frame, r.emitter, r.reason);
  }
  return log;
}

TEST(RuntimeImportance, SetViewRejectsBadViews) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  std::unique_ptr<Runtime> runtime = makeRuntime(house(), cachingSettings());
  ASSERT_TRUE(runtime);
  RuntimeView view = viewInRoom00();
  view.look_at = view.position;
  EXPECT_NE(runtime->setView(view).message().find("is the position"), std::string::npos);
  view = viewInRoom00();
  view.yfov_rad = 3.5f;
  EXPECT_NE(runtime->setView(view).message().find("yfov_rad"), std::string::npos);
  view = viewInRoom00();
  view.position.x = std::nanf("");
  EXPECT_NE(runtime->setView(view).message().find("not finite"), std::string::npos);
  view = viewInRoom00();
  view.up = {0, 0, 0};
  EXPECT_NE(runtime->setView(view).message().find("up (0, 0, 0) is zero"), std::string::npos);
  EXPECT_TRUE(runtime->setView(viewInRoom00()).ok());
  RuntimeSettings bad = cachingSettings();
  bad.max_refresh_interval = 0;
  Expected<std::unique_ptr<Runtime>> rejected =
      Runtime::create(house().scene, house().bake, house().dir, bad);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(rejected.status().message().find("max_refresh_interval"), std::string::npos);
}

TEST(RuntimeImportance, TheViewedRoomsLampsMatterMostAndRefreshEveryFrame) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = house();
  const Lamps lamps = houseLamps(level);
  std::unique_ptr<Runtime> runtime;
  const RefreshLog log = slideTablesAndLog(level, runtime);
  ASSERT_TRUE(runtime);
  const double near_a = lamps.importance(*runtime, "lamp_0_0_a"),
               near_b = lamps.importance(*runtime, "lamp_0_0_b");
  const double far_a = lamps.importance(*runtime, "lamp_1_1_a"),
               far_b = lamps.importance(*runtime, "lamp_1_1_b");
  std::printf("importance: room 0_0 lamps %.4g %.4g, room 1_1 lamps %.4g %.4g\n", near_a, near_b,
              far_a, far_b);
  EXPECT_GT(std::min(near_a, near_b), 4.0 * std::max(far_a, far_b));
  std::map<uint32_t, std::set<int>> frames_of;
  std::map<uint32_t, std::set<RefreshReason>> reasons_of;
  for (const auto& [frame, emitter, reason] : log) {
    frames_of[emitter].insert(frame);
    reasons_of[emitter].insert(reason);
  }
  for (const char* lamp : {"lamp_0_0_a", "lamp_0_0_b"}) {
    const uint32_t id = lamps.state(*runtime, lamp);
    EXPECT_EQ(frames_of[id].size(), 16u) << lamp << " should refresh every frame";
    EXPECT_TRUE(reasons_of[id].count(RefreshReason::kImportant)) << lamp;
  }
  for (const char* lamp : {"lamp_1_1_a", "lamp_1_1_b"}) {
    const uint32_t id = lamps.state(*runtime, lamp);
    std::printf("%s refreshed in %zu of 16 frames (interval %u)\n", lamp, frames_of[id].size(),
                runtime->emitterStates()[id].interval);
    EXPECT_GE(frames_of[id].size(), 1u) << lamp << " must not starve";
    EXPECT_LE(frames_of[id].size(), 6u) << lamp << " is unimportant and should wait";
    EXPECT_TRUE(reasons_of[id].count(RefreshReason::kRoundRobin)) << lamp;
  }
}

TEST(RuntimeImportance, TheScheduleReplaysExactly) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  std::unique_ptr<Runtime> first, second;
  const RefreshLog a = slideTablesAndLog(house(), first);
  const RefreshLog b = slideTablesAndLog(house(), second);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  ASSERT_EQ(first->patchDeltas().size(), second->patchDeltas().size());
  for (size_t i = 0; i < first->patchDeltas().size(); ++i) {
    ASSERT_EQ(first->patchDeltas()[i].r, second->patchDeltas()[i].r) << "patch " << i;
    ASSERT_EQ(first->patchDeltas()[i].g, second->patchDeltas()[i].g) << "patch " << i;
  }
}

TEST(RuntimeImportance, OpeningADoorPromotesTheNextRoomsLamps) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = house();
  const Lamps lamps = houseLamps(level);
  std::unique_ptr<Runtime> runtime = makeRuntime(level, cachingSettings());
  ASSERT_TRUE(runtime);
  ASSERT_TRUE(runtime->setView(viewInRoom00()).ok());
  // door_z1_0 joins rooms (0, 0) and (0, 1); the level stands it open
  // (rotation 0 about its hinge), closed is a quarter turn.
  const ObjectId door = runtime->objectForNode(nodeIndex(level.scene, "door_z1_0"));
  ASSERT_NE(door, kInvalidId);
  const Mat4 open = runtime->objectInfo(door)->world_from_object;
  ASSERT_TRUE(runtime->setObjectTransform(door, withYRotation(open, 1.5707963f)).ok());
  settle(*runtime);
  // One more moved table in room (0, 0) so the closed-door importances are measured.
  const std::map<ObjectId, Mat4> start = tables(*runtime, level.scene);
  nudgeTables(*runtime, start, 1);
  runtime->update(0);
  const double closed_a = lamps.importance(*runtime, "lamp_0_1_a"),
               closed_b = lamps.importance(*runtime, "lamp_0_1_b");
  const uint32_t next_a = lamps.state(*runtime, "lamp_0_1_a"),
                 next_b = lamps.state(*runtime, "lamp_0_1_b");
  ASSERT_TRUE(runtime->setObjectTransform(door, open).ok());
  std::set<uint32_t> refreshed;
  int frames = 0;
  for (; frames < 3 && (!refreshed.count(next_a) || !refreshed.count(next_b)); ++frames) {
    const FrameStats stats = runtime->update(0);
    ASSERT_TRUE(stats.error.empty()) << stats.error;
    for (const EmitterRefresh& r : stats.refreshes) refreshed.insert(r.emitter);
  }
  const double open_a = lamps.importance(*runtime, "lamp_0_1_a"),
               open_b = lamps.importance(*runtime, "lamp_0_1_b");
  std::printf(
      "room 0_1 lamps: importance with the door closed %.4g %.4g, opening %.4g %.4g; refreshed "
      "within %d frames\n",
      closed_a, closed_b, open_a, open_b, frames);
  EXPECT_TRUE(refreshed.count(next_a))
      << "lamp_0_1_a not refreshed within 3 frames of the door opening";
  EXPECT_TRUE(refreshed.count(next_b))
      << "lamp_0_1_b not refreshed within 3 frames of the door opening";
  EXPECT_GT(open_a + open_b, 2.0 * (closed_a + closed_b));
}

/// An open-bottomed box (top and four sides, both sides reflecting) around a point.
DynamicMesh shadeAround(const Vec3& lamp, float half_width, float below, float above) {
  DynamicMesh mesh;
  mesh.name = "shade";
  mesh.double_sided = true;
  const float x0 = lamp.x - half_width, x1 = lamp.x + half_width, z0 = lamp.z - half_width,
              z1 = lamp.z + half_width;
  const float y0 = lamp.y - below, y1 = lamp.y + above;
  auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    const uint32_t base = uint32_t(mesh.positions.size());
    for (const Vec3& p : {a, b, c, d}) mesh.positions.push_back(p);
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
  };
  quad({x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1});
  quad({x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0});
  quad({x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1});
  quad({x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1});
  quad({x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0});
  return mesh;
}

TEST(RuntimeImportance, AShadedLampStillCountsAndSwitchingItOffShowsNextFrame) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = house();
  const Lamps lamps = houseLamps(level);
  std::unique_ptr<Runtime> runtime = makeRuntime(level, cachingSettings());
  ASSERT_TRUE(runtime);
  const Light& lamp = level.scene.lights[size_t(lightIndex(level.scene, "lamp_0_0_a"))];
  // The shade hides the lamp from every view below the ceiling; its light
  // still reaches the floor under it (a 45-degree cone).
  ASSERT_TRUE(runtime->addObject(shadeAround(lamp.position, 0.25f, 0.25f, 0.2f), Mat4{}).ok());
  ASSERT_TRUE(runtime->setView(viewInRoom00()).ok());
  settle(*runtime);
  const std::map<ObjectId, Mat4> start = tables(*runtime, level.scene);
  nudgeTables(*runtime, start, 1);
  runtime->update(0);
  const double shaded = lamps.importance(*runtime, "lamp_0_0_a"),
               open = lamps.importance(*runtime, "lamp_0_0_b");
  const double far =
      std::max(lamps.importance(*runtime, "lamp_1_1_a"), lamps.importance(*runtime, "lamp_1_1_b"));
  std::printf("importance: shaded lamp %.4g, unshaded lamp %.4g, far lamps <= %.4g\n", shaded, open,
              far);
  EXPECT_GT(shaded, 0.1 * open);
  EXPECT_GT(shaded, 4.0 * far);
  settle(*runtime);
  const Vec3 floor_under{lamp.position.x, 0.0f, lamp.position.z}, up{0, 1, 0};
  const float lit = runtime->irradianceAt(floor_under, up).g;
  ASSERT_TRUE(runtime->setBakedEmitterScale(lamps.bake_emitter.at("lamp_0_0_a"), 0.0f).ok());
  const FrameStats next = runtime->update(0);
  ASSERT_TRUE(next.error.empty()) << next.error;
  const float next_frame = runtime->irradianceAt(floor_under, up).g;
  settle(*runtime);
  const float settled = runtime->irradianceAt(floor_under, up).g;
  // The lamp alone puts I / h^2 = 120 / 2.7^2 = 16.5 lux on the floor under it.
  std::printf(
      "floor under the shaded lamp: %.3f lux lit, %.3f the frame after switching off, %.3f "
      "settled\n",
      lit, next_frame, settled);
  EXPECT_LT(next_frame, lit - 0.8f * 16.5f);
  EXPECT_NEAR(next_frame, settled, 0.02f * lit);
}

TEST(RuntimeImportance, AnObjectEnteringAnEmittersReachInvalidatesOnlyThatEmitter) {
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const test::BakedLevel& level = house();
  const Lamps lamps = houseLamps(level);
  std::unique_ptr<Runtime> runtime = makeRuntime(level, cachingSettings());
  ASSERT_TRUE(runtime);
  ASSERT_TRUE(runtime->setView(viewInRoom00()).ok());
  settle(*runtime);
  // A crate far from every doorway in room (1, 1): only that room's lamps
  // (and the patches they light) can see it.
  DynamicMesh crate = shadeAround({7.6f, 0.2f, 7.6f}, 0.2f, 0.2f, 0.2f);
  crate.name = "crate";
  const Expected<ObjectId> id = runtime->addObject(crate, Mat4{});
  ASSERT_TRUE(id.ok());
  // Invalidated: refreshed in this update or waiting for its turn.
  auto invalidated = [&](const FrameStats& stats, const std::string& lamp) {
    const uint32_t state = lamps.state(*runtime, lamp);
    for (const EmitterRefresh& r : stats.refreshes) {
      if (r.emitter == state) return true;
    }
    return runtime->emitterStates()[state].out_of_date;
  };
  const FrameStats stats = runtime->update(0);
  for (const char* lamp : {"lamp_1_1_a", "lamp_1_1_b"})
    EXPECT_TRUE(invalidated(stats, lamp)) << lamp << " should see the crate";
  for (const char* lamp : {"lamp_0_0_a", "lamp_0_0_b"}) {
    EXPECT_FALSE(invalidated(stats, lamp)) << lamp << " cannot reach room (1, 1)'s far corner";
  }
  settle(*runtime);
  // Carried into room (0, 0): now those lamps go out of date too.
  ASSERT_TRUE(runtime->setObjectTransform(*id, translated(Mat4{}, -5.5f, -5.5f)).ok());
  const FrameStats moved = runtime->update(0);
  for (const char* lamp : {"lamp_0_0_a", "lamp_0_0_b", "lamp_1_1_a", "lamp_1_1_b"}) {
    EXPECT_TRUE(invalidated(moved, lamp)) << lamp << " (the crate left or entered its reach)";
  }
}

}  // namespace
}  // namespace svit

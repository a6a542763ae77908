// Importance caching (thesis 5.9-5.10, issue 7) on the generated 2 x 2
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

#include "gl_test_context.h"
#include "runtime_test_util.h"
#include "svit/runtime.h"

namespace svit {
namespace {

using test::bakedLevel;

const test::BakedLevel& house() {
  return bakedLevel("house", std::string(SVIT_SOURCE_DIR) + "/samples/levels/house/level.json", 0.2);
}

int nodeIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].name == name) return int(i);
  }
  ADD_FAILURE() << "no node " << name;
  return -1;
}

int lightIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    if (scene.lights[i].name == name || scene.nodes[size_t(scene.lights[i].node)].name == name) return int(i);
  }
  ADD_FAILURE() << "no light " << name;
  return -1;
}

uint32_t bakeEmitterOfLight(const BakeData& bake, int light) {
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    if (bake.emitters[i].kind == BakeEmitter::Kind::kLight && int(bake.emitters[i].index) == light) return i;
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
      if (states[i].type == EmitterType::kBakedLight && states[i].bake_emitter == bake_emitter.at(lamp)) return i;
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

RuntimeSettings cachingSettings() {
  RuntimeSettings settings;
  settings.target_patches = 512;
  settings.target_shooters = 64;
  settings.map_resolution = 64;
  settings.max_samples_per_emitter = 4;
  settings.max_samples_per_frame = 16;
  settings.max_refresh_interval = 8;
  settings.view_pass_width = 96;
  return settings;
}

std::unique_ptr<Runtime> makeRuntime(const test::BakedLevel& level, const RuntimeSettings& settings) {
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(level.scene, level.bake, level.dir, settings);
  EXPECT_TRUE(runtime.ok()) << runtime.status().message();
  return runtime.ok() ? std::move(runtime).value() : nullptr;
}

/// Updates without a sample budget until nothing is out of date (bounded),
/// then sets `budget` (samples per frame).
void settle(Runtime& runtime, int budget = cachingSettings().max_samples_per_frame) {
  ASSERT_TRUE(runtime.setSampleBudget(0).ok());
  bool settled = false;
  for (int frame = 0; frame < 16 && !settled; ++frame) {
    const FrameStats stats = runtime.update(0);
    ASSERT_TRUE(stats.error.empty()) << stats.error;
    settled = stats.idle || stats.emitters_pending == 0;
  }
  ASSERT_TRUE(runtime.setSampleBudget(budget).ok());
  ASSERT_TRUE(settled) << "the runtime did not settle in 16 updates";
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

Mat4 translated(const Mat4& placed, float dx, float dz) {
  Mat4 out = placed;
  out.m[12] += dx;
  out.m[14] += dz;
  return out;
}

/// Slides every table a little (a different offset each frame): every lamp
/// whose light reaches a table goes out of date.
void nudgeTables(Runtime& runtime, const std::map<ObjectId, Mat4>& start, int frame) {
  for (const auto& [id, placed] : start) {
    ASSERT_TRUE(runtime.setObjectTransform(id, translated(placed, 0.05f * float(frame % 4), 0.0f)).ok());
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
/// share-out is tested in tests/runtime/refresh_scheduler_test.cpp).
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
  EXPECT_NE(runtime->setView(view).message().find("position equals look_at"), std::string::npos);
  view = viewInRoom00();
  view.yfov_rad = 3.5f;
  EXPECT_NE(runtime->setView(view).message().find("yfov_rad"), std::string::npos);
  view = viewInRoom00();
  view.position.x = std::nanf("");
  EXPECT_NE(runtime->setView(view).message().find("not finite"), std::string::npos);
  view = viewInRoom00();
  view.up = {0, 0, 0};
  EXPECT_NE(runtime->setView(view).message().find("up is zero"), std::string::npos);
  EXPECT_TRUE(runtime->setView(viewInRoom00()).ok());
  RuntimeSettings bad = cachingSettings();
  bad.max_refresh_interval = 0;
  Expected<std::unique_ptr<Runtime>> rejected = Runtime::create(house().scene, house().bake, house().dir, bad);
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
  const double near_a = lamps.importance(*runtime, "lamp_0_0_a"), near_b = lamps.importance(*runtime, "lamp_0_0_b");
  const double far_a = lamps.importance(*runtime, "lamp_1_1_a"), far_b = lamps.importance(*runtime, "lamp_1_1_b");
  std::printf("importance: room 0_0 lamps %.4g %.4g, room 1_1 lamps %.4g %.4g\n", near_a, near_b, far_a, far_b);
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
  const double closed_a = lamps.importance(*runtime, "lamp_0_1_a"), closed_b = lamps.importance(*runtime, "lamp_0_1_b");
  const uint32_t next_a = lamps.state(*runtime, "lamp_0_1_a"), next_b = lamps.state(*runtime, "lamp_0_1_b");
  ASSERT_TRUE(runtime->setObjectTransform(door, open).ok());
  std::set<uint32_t> refreshed;
  int frames = 0;
  for (; frames < 3 && (!refreshed.count(next_a) || !refreshed.count(next_b)); ++frames) {
    const FrameStats stats = runtime->update(0);
    ASSERT_TRUE(stats.error.empty()) << stats.error;
    for (const EmitterRefresh& r : stats.refreshes) refreshed.insert(r.emitter);
  }
  const double open_a = lamps.importance(*runtime, "lamp_0_1_a"), open_b = lamps.importance(*runtime, "lamp_0_1_b");
  std::printf("room 0_1 lamps: importance with the door closed %.4g %.4g, opening %.4g %.4g; refreshed within %d frames\n",
              closed_a, closed_b, open_a, open_b, frames);
  EXPECT_TRUE(refreshed.count(next_a)) << "lamp_0_1_a not refreshed within 3 frames of the door opening";
  EXPECT_TRUE(refreshed.count(next_b)) << "lamp_0_1_b not refreshed within 3 frames of the door opening";
  EXPECT_GT(open_a + open_b, 2.0 * (closed_a + closed_b));
}

/// An open-bottomed box (top and four sides, both sides reflecting) around a point.
DynamicMesh shadeAround(const Vec3& lamp, float half_width, float below, float above) {
  DynamicMesh mesh;
  mesh.name = "shade";
  mesh.double_sided = true;
  const float x0 = lamp.x - half_width, x1 = lamp.x + half_width, z0 = lamp.z - half_width, z1 = lamp.z + half_width;
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
  const double shaded = lamps.importance(*runtime, "lamp_0_0_a"), open = lamps.importance(*runtime, "lamp_0_0_b");
  const double far = std::max(lamps.importance(*runtime, "lamp_1_1_a"), lamps.importance(*runtime, "lamp_1_1_b"));
  std::printf("importance: shaded lamp %.4g, unshaded lamp %.4g, far lamps <= %.4g\n", shaded, open, far);
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
  std::printf("floor under the shaded lamp: %.3f lux lit, %.3f the frame after switching off, %.3f settled\n", lit,
              next_frame, settled);
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
  for (const char* lamp : {"lamp_1_1_a", "lamp_1_1_b"}) EXPECT_TRUE(invalidated(stats, lamp)) << lamp << " should see the crate";
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


/// Settles a runtime of the house, moves table (0, 0) by 30 cm and brings
/// everything up to date again; the deltas then, and the triangles the
/// maps drew after the move.
struct MoveResult {
  std::vector<Rgb> deltas;
  uint64_t triangles_drawn = 0, triangles_hidden = 0;
  uint32_t samples = 0;
};
MoveResult moveTableAndSettle(bool lit_set_culling, bool occlusion_culling = true) {
  RuntimeSettings settings = cachingSettings();
  settings.lit_set_culling = lit_set_culling;
  settings.occlusion_culling = occlusion_culling;
  std::unique_ptr<Runtime> runtime = makeRuntime(house(), settings);
  if (!runtime) return {};
  settle(*runtime, 0);
  const ObjectId table = runtime->objectForNode(nodeIndex(house().scene, "table_0_0"));
  EXPECT_TRUE(runtime->setObjectTransform(table, translated(runtime->objectInfo(table)->world_from_object, 0.3f, 0.0f)).ok());
  MoveResult out;
  for (int frame = 0; frame < 16; ++frame) {
    const FrameStats stats = runtime->update(0);
    EXPECT_TRUE(stats.error.empty()) << stats.error;
    out.triangles_drawn += stats.triangles_drawn;
    out.triangles_hidden += stats.triangles_hidden;
    out.samples += stats.samples_rendered;
    if (stats.idle) break;
  }
  out.deltas = runtime->patchDeltas();
  return out;
}

// The largest |delta| of `reference` and the worst |difference| of `other`
// from it, in lux (luminance of the patch deltas).
std::pair<double, double> largestAndWorstDifference(const MoveResult& reference, const MoveResult& other) {
  double largest = 0, worst = 0;
  for (size_t i = 0; i < reference.deltas.size(); ++i) {
    largest = std::max(largest, double(std::abs(luminance(reference.deltas[i]))));
    worst = std::max(worst, double(std::abs(luminance(reference.deltas[i]) - luminance(other.deltas[i]))));
  }
  return {largest, worst};
}

TEST(RuntimeImportance, LitSetCullingDrawsLessAndChangesNothing) {
  // An emitter's later maps draw only the static runs its static-level maps
  // showed: the same result (objects only hide surfaces) for less drawing.
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const MoveResult box = moveTableAndSettle(false), lit = moveTableAndSettle(true);
  ASSERT_EQ(box.deltas.size(), lit.deltas.size());
  ASSERT_GT(box.samples, 0u);
  EXPECT_EQ(box.samples, lit.samples);
  const auto [largest, worst] = largestAndWorstDifference(box, lit);
  std::printf("lit set: %llu triangles drawn against %llu by boxes (%u samples); largest delta %.4g lux, worst "
              "difference %.3g lux\n",
              (unsigned long long)lit.triangles_drawn, (unsigned long long)box.triangles_drawn, lit.samples, largest,
              worst);
  ASSERT_GT(largest, 0.0);
  EXPECT_LE(worst, 1e-4 * largest);
  EXPECT_LT(double(lit.triangles_drawn), 0.9 * double(box.triangles_drawn));
}

TEST(RuntimeImportance, OcclusionCullingDrawsLessAndChangesNothing) {
  // Maps of samples with no lit set (here every sample: lit-set culling is
  // off) draw their nearest chunks first, then only what those do not hide:
  // the same maps (hidden chunks cannot win a texel, nor pass the fallback's
  // vertex tests) for less drawing. Depth ties may resolve in another
  // order, so the bound is a rounding one, not zero.
  test::GlTestContext gl;
  SVIT_REQUIRE_GL(gl);
  const MoveResult all = moveTableAndSettle(false, false), culled = moveTableAndSettle(false, true);
  ASSERT_EQ(all.deltas.size(), culled.deltas.size());
  ASSERT_GT(all.samples, 0u);
  EXPECT_EQ(all.samples, culled.samples);
  EXPECT_EQ(all.triangles_hidden, 0u);
  const auto [largest, worst] = largestAndWorstDifference(all, culled);
  std::printf("occlusion: %llu triangles drawn against %llu (%llu hidden; %u samples); largest delta %.4g lux, worst "
              "difference %.3g lux\n",
              (unsigned long long)culled.triangles_drawn, (unsigned long long)all.triangles_drawn,
              (unsigned long long)culled.triangles_hidden, culled.samples, largest, worst);
  ASSERT_GT(largest, 0.0);
  EXPECT_LE(worst, 1e-4 * largest);
  // Every sample here already draws only its reach box (its room), so
  // little is left to hide; bench_importance shows the 8 x 8 house.
  EXPECT_GT(culled.triangles_hidden, 0u);
  EXPECT_LT(culled.triangles_drawn, all.triangles_drawn);
}

}  // namespace
}  // namespace svit

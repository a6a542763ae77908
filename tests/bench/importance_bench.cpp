// Importance caching benchmark, headless under xvfb-run on
// whatever GL is there (Mesa llvmpipe on the CI machines). On a generated
// house (samples/levels/house/make_house.py, baked by importance_bench.sh):
//  1. a walk through four rooms while every table in the house slides (or,
//     with --moving walk, only the tables of the four rooms walked: the same
//     dynamic activity whatever the house's size), two
//     runtimes side by side in this process: refresh-all (every emitter a
//     moving table can reach re-rendered every frame) and importance
//     caching with a per-frame sample budget; per-frame cost of each and
//     the caching runtime's irradiance error against refresh-all at probe
//     points in the camera's room;
//  2. a door next to the camera's room opens: frames until the next room's
//     lamps have refreshed;
//  3. a lamp of the camera's room switched off: the irradiance under it the
//     very next frame against the settled value.
// usage: bench_importance LEVEL.json BAKE_DIR [--budget SAMPLES] [--stop-frames N] [--json OUT]
// [--no-reference]
//                         [--moving all|walk] [--no-lit-set] [--no-occlusion] [--also-budgets
//                         N,N,...]
// (--no-reference: caching alone, for its per-stage times; no error figures;
// --no-lit-set: RuntimeSettings::lit_set_culling off, maps culled by boxes;
// --no-occlusion: RuntimeSettings::occlusion_culling off; --also-budgets:
// more caching runtimes with these budgets walk alongside, each with its
// cost and its error against the same refresh-all, so costs compare at
// equal accuracy).
// Both runtimes shade as svit-walk does, from the patch delta buffer
// (RuntimeSettings::delta_textures off: the lightmap-space delta pages are
// for hosts that sample them, and cost a pass over the atlas per update).

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/gl_context.h"
#include "svit/level.h"
#include "svit/runtime.h"

namespace {

using namespace svit;

constexpr float kPitch = 4.2f;  // room + wall, make_house.py
constexpr float kRoom = 4.0f;

#define BENCH_CHECK(cond, message)                                                  \
  do {                                                                              \
    if (!(cond)) {                                                                  \
      std::fprintf(stderr, "bench_importance: %s\n", std::string(message).c_str()); \
      std::exit(1);                                                                 \
    }                                                                               \
  } while (0)

int nodeIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].name == name) return int(i);
  }
  return -1;
}

struct Room {
  int i = 0, j = 0;
  float x0() const { return float(i) * kPitch; }
  float z0() const { return float(j) * kPitch; }
};

/// Floor (3 x 3) and wall (two per wall, clear of the doorway in the middle) probes of a room.
std::vector<std::pair<Vec3, Vec3>> roomProbes(const Room& room) {
  std::vector<std::pair<Vec3, Vec3>> probes;
  for (float a : {1.0f, 2.0f, 3.0f}) {
    for (float b : {1.0f, 2.0f, 3.0f})
      probes.push_back({{room.x0() + a, 0.0f, room.z0() + b}, {0, 1, 0}});
  }
  for (float a : {0.8f, 3.2f}) {
    probes.push_back({{room.x0() + a, 1.5f, room.z0()}, {0, 0, 1}});
    probes.push_back({{room.x0() + a, 1.5f, room.z0() + kRoom}, {0, 0, -1}});
    probes.push_back({{room.x0(), 1.5f, room.z0() + a}, {1, 0, 0}});
    probes.push_back({{room.x0() + kRoom, 1.5f, room.z0() + a}, {-1, 0, 0}});
  }
  return probes;
}

/// Standing in `room` looking at the doorway towards `next`.
RuntimeView viewTowards(const Room& room, const Room& next) {
  RuntimeView view;
  view.position = {room.x0() + 2.0f, 1.6f, room.z0() + 2.0f};
  view.look_at = {0.5f * (room.x0() + next.x0()) + 2.0f, 1.3f,
                  0.5f * (room.z0() + next.z0()) + 2.0f};
  view.yfov_rad = 1.2f;
  view.aspect = 16.0f / 9.0f;
  return view;
}

Mat4 slid(const Mat4& placed, float dx) {
  Mat4 out = placed;
  out.m[12] += dx;
  return out;
}

Mat4 yRotated(const Mat4& placed, float angle) {
  Mat4 out = placed;
  const float c = std::cos(angle), s = std::sin(angle);
  out.m = {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, placed.m[12], placed.m[13], placed.m[14], 1};
  return out;
}

bool lit_set_culling = true;    // --no-lit-set
bool occlusion_culling = true;  // --no-occlusion

std::unique_ptr<Runtime> makeRuntime(const Scene& scene, const BakeData& bake,
                                     const std::string& dir, int rooms, bool refresh_all,
                                     int budget) {
  RuntimeSettings settings;
  settings.lit_set_culling = lit_set_culling;
  settings.occlusion_culling = occlusion_culling;
  settings.delta_textures = false;
  // Equal resolution per room whatever the house's size.
  settings.target_patches = 128 * rooms;
  settings.target_shooters = 16 * rooms;
  settings.map_resolution = 64;
  settings.max_samples_per_emitter = 4;
  settings.refresh_all = refresh_all;
  settings.max_samples_per_frame = refresh_all ? 0 : budget;
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(scene, bake, dir, settings);
  BENCH_CHECK(runtime.ok(), runtime.status().message());
  return std::move(runtime).value();
}

double lum(const Rgb& c) { return luminance(c); }

/// Brings every emitter up to date with no sample budget (a loading
/// screen's work; the unimportant ones still wait their intervals, at most
/// max_refresh_interval updates), then sets the per-frame `budget`.
void settle(Runtime& runtime, int budget) {
  BENCH_CHECK(runtime.setSampleBudget(0).ok(), "setSampleBudget");
  for (int f = 0; f < 100 && runtime.update(0).emitters_pending > 0; ++f) {}
  BENCH_CHECK(runtime.setSampleBudget(budget).ok(), "setSampleBudget");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: bench_importance LEVEL.json BAKE_DIR [--budget SAMPLES] [--stop-frames N] "
                 "[--json OUT]\n");
    return 2;
  }
  const std::string level_path = argv[1], bake_dir = argv[2];
  int budget = 48, stop_frames = 6;
  std::string json_path;
  bool reference = true;
  std::string moving = "all";
  std::vector<int> also_budgets;
  for (int i = 3; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--no-reference")) {
      reference = false;
      continue;
    }
    if (!std::strcmp(argv[i], "--no-lit-set")) {
      lit_set_culling = false;
      continue;
    }
    if (!std::strcmp(argv[i], "--no-occlusion")) {
      occlusion_culling = false;
      continue;
    }
    if (!std::strcmp(argv[i], "--budget") && i + 1 < argc) {
      budget = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--stop-frames") && i + 1 < argc) {
      stop_frames = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--also-budgets") && i + 1 < argc) {
      for (const char* p = argv[++i]; *p;) {
        char* end = nullptr;
        const long v = std::strtol(p, &end, 10);
        if (end == p || v < 1) {
          std::fprintf(
              stderr,
              "bench_importance: --also-budgets takes positive sample counts, as 32,24,16\n");
          return 2;
        }
        also_budgets.push_back(int(v));
        p = *end == ',' ? end + 1 : end;
      }
    } else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) {
      json_path = argv[++i];
    } else if (!std::strcmp(argv[i], "--moving") && i + 1 < argc) {
      moving = argv[++i];
      if (moving != "all" && moving != "walk") {
        std::fprintf(stderr, "bench_importance: --moving takes all or walk, not %s\n",
                     moving.c_str());
        return 2;
      }
    } else {
      std::fprintf(stderr, "bench_importance: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  Expected<Scene> loaded = loadLevel(level_path);
  BENCH_CHECK(loaded.ok(), loaded.status().message());
  const Scene scene = std::move(loaded).value();
  Expected<BakeData> read = readBakeFile(bake_dir + "/bake.svit");
  BENCH_CHECK(read.ok(), read.status().message());
  const BakeData bake = std::move(read).value();
  int rooms = 0;
  std::vector<std::string> tables;
  for (const Node& node : scene.nodes) {
    if (node.name.rfind("table_", 0) == 0) tables.push_back(node.name);
  }
  rooms = int(tables.size());
  BENCH_CHECK(rooms >= 4, "the level has fewer than 4 rooms (tables)");

  BENCH_CHECK(glfwInit() == GLFW_TRUE, "no display (run under xvfb-run -a)");
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "bench_importance", nullptr, nullptr);
  BENCH_CHECK(window != nullptr, "no OpenGL 4.5 core context");
  glfwMakeContextCurrent(window);
  const std::string renderer = checkGlContext()->renderer;
  std::printf("bench_importance: %s, %d rooms, %zu lamps, budget %d samples/frame, GL: %s\n",
              level_path.c_str(), rooms, scene.lights.size(), budget, renderer.c_str());

  // ---- 1. the walk: refresh-all against caching, side by side ----
  std::unique_ptr<Runtime> all =
      reference ? makeRuntime(scene, bake, bake_dir, rooms, true, budget) : nullptr;
  std::unique_ptr<Runtime> cached = makeRuntime(scene, bake, bake_dir, rooms, false, budget);
  struct OtherBudget {
    int budget;
    std::unique_ptr<Runtime> runtime;
    double time = 0, samples = 0, error_sum = 0;
  };
  std::vector<OtherBudget> others;
  for (int b : also_budgets)
    others.push_back({b, makeRuntime(scene, bake, bake_dir, rooms, false, b)});
  const std::vector<Room> walk = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<std::pair<ObjectId, Mat4>> table_ids;
  for (const std::string& name : tables) {
    const bool walked = std::any_of(walk.begin(), walk.end(), [&](const Room& r) {
      return name == "table_" + std::to_string(r.i) + "_" + std::to_string(r.j);
    });
    if (moving == "walk" && !walked) continue;
    const ObjectId id = cached->objectForNode(nodeIndex(scene, name));
    BENCH_CHECK(id != kInvalidId, "table " + name);
    table_ids.push_back({id, cached->objectInfo(id)->world_from_object});
  }
  // Both start settled on the level as placed.
  // Both start settled on the level as placed (a loading screen's work).
  if (all) all->update(0);
  settle(*cached, budget);
  for (OtherBudget& o : others) settle(*o.runtime, o.budget);
  double time_all = 0, time_cached = 0, error_sum = 0, samples_all = 0, samples_cached = 0;
  double stage_maps = 0, stage_reduction = 0, stage_bounce = 0, stage_upload = 0, stage_view = 0,
         triangles = 0;
  int frames = 0;
  nlohmann::json frame_log = nlohmann::json::array();
  for (size_t stop = 0; stop < walk.size(); ++stop) {
    const Room room = walk[stop], next = walk[(stop + 1) % walk.size()];
    BENCH_CHECK(cached->setView(viewTowards(room, next)).ok(), "setView");
    for (OtherBudget& o : others)
      BENCH_CHECK(o.runtime->setView(viewTowards(room, next)).ok(), "setView");
    for (int f = 0; f < stop_frames; ++f, ++frames) {
      const float dx = 0.3f * std::sin(0.7f * float(frames + 1));
      for (auto& [id, placed] : table_ids) {
        if (all) BENCH_CHECK(all->setObjectTransform(id, slid(placed, dx)).ok(), "move");
        BENCH_CHECK(cached->setObjectTransform(id, slid(placed, dx)).ok(), "move");
        for (OtherBudget& o : others)
          BENCH_CHECK(o.runtime->setObjectTransform(id, slid(placed, dx)).ok(), "move");
      }
      const FrameStats a = all ? all->update(0) : FrameStats{};
      const FrameStats c = cached->update(0);
      BENCH_CHECK(a.error.empty() && c.error.empty(), a.error + c.error);
      double diff = 0, ref = 0;
      for (const auto& [p, n] : roomProbes(room)) {
        if (!all) break;
        const double ea = lum(all->irradianceAt(p, n)), ec = lum(cached->irradianceAt(p, n));
        if (!std::isfinite(ea) || !std::isfinite(ec)) continue;
        diff += std::abs(ec - ea);
        ref += ea;
      }
      const double error = ref > 0 ? diff / ref : 0;
      for (OtherBudget& o : others) {
        const FrameStats stats = o.runtime->update(0);
        BENCH_CHECK(stats.error.empty(), stats.error);
        o.time += stats.total_ms;
        o.samples += stats.samples_rendered;
        double other_diff = 0;
        for (const auto& [p, n] : roomProbes(room)) {
          if (!all) break;
          const double ea = lum(all->irradianceAt(p, n)), eo = lum(o.runtime->irradianceAt(p, n));
          if (std::isfinite(ea) && std::isfinite(eo)) other_diff += std::abs(eo - ea);
        }
        o.error_sum += ref > 0 ? other_diff / ref : 0;
      }
      time_all += a.total_ms;
      time_cached += c.total_ms;
      stage_maps += c.maps_ms;
      stage_reduction += c.reduction_ms;
      stage_bounce += c.bounce_ms;
      stage_upload += c.upload_ms;
      stage_view += c.view_ms;
      triangles += double(c.triangles_drawn);
      samples_all += a.samples_rendered;
      samples_cached += c.samples_rendered;
      error_sum += error;
      std::map<std::string, int> reasons;
      for (const EmitterRefresh& r : c.refreshes) ++reasons[refreshReasonName(r.reason)];
      frame_log.push_back({{"frame", frames},
                           {"room", {room.i, room.j}},
                           {"all_ms", a.total_ms},
                           {"cached_ms", c.total_ms},
                           {"all_samples", a.samples_rendered},
                           {"cached_samples", c.samples_rendered},
                           {"cached_view_ms", c.view_ms},
                           {"error", error},
                           {"reasons", reasons}});
      std::printf(
          "frame %2d room %d,%d: refresh-all %8.1f ms (%5u samples), caching %7.1f ms (%4u "
          "samples, view %.1f ms), "
          "error %.2f%%\n",
          frames, room.i, room.j, a.total_ms, a.samples_rendered, c.total_ms, c.samples_rendered,
          c.view_ms, 100 * error);
      std::fflush(stdout);
    }
  }
  const double mean_all = time_all / frames, mean_cached = time_cached / frames,
               mean_error = error_sum / frames;
  const nlohmann::json stages = {
      {"maps_ms", stage_maps / frames},     {"reduction_ms", stage_reduction / frames},
      {"bounce_ms", stage_bounce / frames}, {"upload_ms", stage_upload / frames},
      {"view_ms", stage_view / frames},     {"map_triangles", triangles / frames}};
  std::fflush(stdout);
  std::printf(
      "caching per frame by stage: maps %.1f ms (%.0f triangles), reduction %.1f ms, bounce %.1f "
      "ms, "
      "upload %.1f ms, view %.1f ms\n",
      stage_maps / frames, triangles / frames, stage_reduction / frames, stage_bounce / frames,
      stage_upload / frames, stage_view / frames);
  std::printf(
      "walk: %d frames; per frame refresh-all %.1f ms (%.0f samples), caching %.1f ms (%.0f "
      "samples): "
      "ratio %.3f; error in the camera's room vs refresh-all %.2f%% (mean)\n",
      frames, mean_all, samples_all / frames, mean_cached, samples_cached / frames,
      mean_all > 0 ? mean_cached / mean_all : 0.0, 100 * mean_error);
  nlohmann::json other_log = nlohmann::json::array();
  for (OtherBudget& o : others) {
    std::printf(
        "budget %d: caching %.1f ms (%.0f samples) per frame, error in the camera's room vs "
        "refresh-all %.2f%%\n",
        o.budget, o.time / frames, o.samples / frames, 100 * o.error_sum / frames);
    other_log.push_back({{"budget_samples", o.budget},
                         {"caching_ms", o.time / frames},
                         {"caching_samples", o.samples / frames},
                         {"mean_error", o.error_sum / frames}});
    o.runtime.reset();
  }
  all.reset();

  // ---- 2. a door next to the camera's room opens ----
  // door_z1_0 joins rooms (0, 0) and (0, 1); closed is a quarter turn.
  std::unique_ptr<Runtime> runtime = makeRuntime(scene, bake, bake_dir, rooms, false, budget);
  BENCH_CHECK(runtime->setView(viewTowards({0, 0}, {0, 1})).ok(), "setView");
  const ObjectId door = runtime->objectForNode(nodeIndex(scene, "door_z1_0"));
  BENCH_CHECK(door != kInvalidId, "door_z1_0");
  const Mat4 open = runtime->objectInfo(door)->world_from_object;
  BENCH_CHECK(runtime->setObjectTransform(door, yRotated(open, 1.5707963f)).ok(), "close");
  settle(*runtime, budget);
  std::set<uint32_t> next_lamps;
  const std::vector<EmitterState> states = runtime->emitterStates();
  for (uint32_t e = 0; e < states.size(); ++e) {
    if (states[e].type != EmitterType::kBakedLight) continue;
    const Light& light = scene.lights[bake.emitters[states[e].bake_emitter].index];
    if (light.position.x < kPitch && light.position.z > kPitch && light.position.z < 2 * kPitch)
      next_lamps.insert(e);
  }
  BENCH_CHECK(next_lamps.size() == 2, "room (0, 1) should have two lamps");
  BENCH_CHECK(runtime->setObjectTransform(door, open).ok(), "open");
  int door_frames = 0;
  std::set<uint32_t> refreshed;
  while (door_frames < 32) {
    ++door_frames;
    for (const EmitterRefresh& r : runtime->update(0).refreshes) {
      if (next_lamps.count(r.emitter)) refreshed.insert(r.emitter);
    }
    if (refreshed.size() == next_lamps.size()) break;
  }
  std::printf("door: the next room's two lamps refreshed within %d frame(s) of the door opening\n",
              door_frames);

  // ---- 3. a lamp of the camera's room switched off ----
  uint32_t lamp_emitter = kInvalidId;
  Vec3 lamp_position{};
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    if (bake.emitters[i].kind != BakeEmitter::Kind::kLight) continue;
    const Light& light = scene.lights[bake.emitters[i].index];
    if (light.position.x < kPitch && light.position.z < kPitch) {
      lamp_emitter = i;
      lamp_position = light.position;
      break;
    }
  }
  BENCH_CHECK(lamp_emitter != kInvalidId, "no lamp in room (0, 0)");
  settle(*runtime, budget);
  const Vec3 under{lamp_position.x, 0.0f, lamp_position.z}, up{0, 1, 0};
  const double lit = lum(runtime->irradianceAt(under, up));
  BENCH_CHECK(runtime->setBakedEmitterScale(lamp_emitter, 0.0f).ok(), "switch off");
  runtime->update(0);
  const double next_frame = lum(runtime->irradianceAt(under, up));
  settle(*runtime, budget);
  const double settled = lum(runtime->irradianceAt(under, up));
  std::printf(
      "lamp off: floor under it %.2f lux lit, %.2f the next frame, %.2f settled (next frame off by "
      "%.2f%% of lit)\n",
      lit, next_frame, settled, 100 * std::abs(next_frame - settled) / lit);

  if (!json_path.empty()) {
    nlohmann::json out = {{"level", level_path},
                          {"rooms", rooms},
                          {"moving", moving},
                          {"lit_set_culling", lit_set_culling},
                          {"occlusion_culling", occlusion_culling},
                          {"moving_tables", table_ids.size()},
                          {"lamps", scene.lights.size()},
                          {"gl", renderer},
                          {"budget_samples", budget},
                          {"frames", frames},
                          {"refresh_all_ms", mean_all},
                          {"caching_ms", mean_cached},
                          {"caching_stages", stages},
                          {"cost_ratio", mean_all > 0 ? mean_cached / mean_all : 0.0},
                          {"refresh_all_samples", samples_all / frames},
                          {"caching_samples", samples_cached / frames},
                          {"mean_error", mean_error},
                          {"door_frames", door_frames},
                          {"lamp_off_lit", lit},
                          {"lamp_off_next_frame", next_frame},
                          {"lamp_off_settled", settled},
                          {"walk", frame_log},
                          {"other_budgets", other_log}};
    std::ofstream(json_path) << out.dump(1) << "\n";
  }
  runtime.reset();
  cached.reset();
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

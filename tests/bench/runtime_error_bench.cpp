// The runtime's error after a dynamic object moves, against a bake of the
// level with the object static at its new place (error against
// time; driven by error_vs_time.sh). For each per-frame budget: a fresh
// runtime settled with the object at its start, the object teleported, then
// `frames` updates of update(budget); after each, the RMS difference of
// luminance at probe points relative to the reference's mean, against the
// cumulative wall time of the updates. Frame 0 is the error before any
// update (the runtime still showing the old place).
// usage: bench_runtime_error --level cornell|house|sponza --work DIR --json OUT
//        [--budgets 10,50,200,0] [--frames 16] [--quality 0.2] [--one-settle]
//        [--proxies | --full-geometry] [--target-patches N] [--map-resolution N] [--max-samples N]
//        [--secondary-share S]
//        [--settle-budget MS]
// --one-settle (for levels whose settle takes many minutes on llvmpipe, i.e.
// Sponza): one runtime, settled once, measured at rest, then the first
// budget's frames, then update(0) to settled as the "none" end point.
// The settings flags set RuntimeSettings (use_proxies, target_patches,
// map_resolution, max_samples_per_emitter, secondary_emitter_share), e.g.
// for a cheaper runtime on llvmpipe; the JSON records them. --settle-budget settles in frames of
// update(MS) until idle instead of update(0), printing progress.
// Runs headless under xvfb-run; bakes (quality Q, seed 7) go to DIR and are
// reused when their stamp matches.

#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_bake.h"
#include "moved_level.h"
#include "svit/gl_context.h"
#include "svit/runtime.h"

namespace {

using namespace svit;
using namespace svit::test;

struct Case {
  std::string name, level, node;
  Vec3 start_translation;  ///< where the level has it (the runtime starts there)
  Quat start_rotation;
  Vec3 moved_translation;
  Quat moved_rotation;
  float probe_margin_m;  ///< floor probes: how far around the object
  int probe_grid = 10;   ///< floor probes: n x n
};

// The moved places come from each level's own path (a key of it), except
// Sponza's: its ball rolls under a nearly overhead sun, so its shadow lies
// under its own footprint (probes there are dropped) and the move changes
// nothing the probes see beyond the bakes' noise. The moved ball is lifted
// 1.2 m (mid-bounce), so its sun shadow falls on open floor beside it, and
// the grid is finer (16 x 16 over the objects +- 1 m) to sample it.
std::vector<Case> cases() {
  const std::string levels = std::string(SVIT_SOURCE_DIR) + "/samples/levels/";
  return {{"cornell",
           levels + "cornell/level.json",
           "tallBox",
           {0, 0, 0},
           {},
           {0.25f, 0, 0.1f},
           {0, 0.2588190f, 0, 0.9659258f},
           0},
          {"house",
           levels + "house/level.json",
           "table_0_0",
           {3.1f, 0, 1.1f},
           {},
           {2.4f, 0, 1.1f},
           {},
           1.0f},
          {"sponza",
           levels + "sponza/level.json",
           "ball",
           {-11.5f, 4.28f, -1.8f},
           {},
           {-9.615f, 5.48f, -1.8f},
           {},
           1.0f,
           16}};
}

// A runtime of the base level, its runtime lights off (the bakes leave
// dynamic lights out; irradianceAt would add their bounce), settled with
// every object at its start.
std::unique_ptr<Runtime> settledRuntime(const BakedLevel& base, const RuntimeSettings& settings,
                                        double settle_budget_ms) {
  Expected<std::unique_ptr<Runtime>> created =
      Runtime::create(base.scene, base.bake, base.dir, settings);
  SVIT_SETUP_CHECK(created.ok(), created.status().message());
  std::unique_ptr<Runtime> runtime = std::move(created).value();
  for (LightId light : runtime->lights()) (void)runtime->setLightEnabled(light, false);
  // settle(), with progress: Sponza's first settle runs for many minutes on
  // llvmpipe, so it may go in budgeted frames (until idle) to show it.
  const auto t0 = std::chrono::steady_clock::now();
  for (int frame = 0; settle_budget_ms > 0 || frame < 32; ++frame) {
    const FrameStats s = runtime->update(settle_budget_ms);
    SVIT_SETUP_CHECK(s.error.empty(), s.error);
    std::printf("settle frame %d: %u emitters, %u samples, %u pending, %.0f s\n", frame,
                s.emitters_refreshed, s.samples_rendered, s.emitters_pending,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::fflush(stdout);
    if (s.idle) break;
  }
  return runtime;
}

std::vector<double> parseList(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string level_name, work, json_path, budgets_text = "10,50,200,0";
  int frames = 16;
  double quality = 0.2;
  bool one_settle = false;
  RuntimeSettings settings;
  double settle_budget_ms = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--level" && i + 1 < argc)
      level_name = argv[++i];
    else if (arg == "--work" && i + 1 < argc)
      work = argv[++i];
    else if (arg == "--json" && i + 1 < argc)
      json_path = argv[++i];
    else if (arg == "--budgets" && i + 1 < argc)
      budgets_text = argv[++i];
    else if (arg == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (arg == "--quality" && i + 1 < argc)
      quality = std::atof(argv[++i]);
    else if (arg == "--one-settle")
      one_settle = true;
    else if (arg == "--settle-budget" && i + 1 < argc)
      settle_budget_ms = std::atof(argv[++i]);
    else if (arg == "--proxies")
      settings.use_proxies = true;
    else if (arg == "--full-geometry")
      settings.use_proxies = false;
    else if (arg == "--target-patches" && i + 1 < argc)
      settings.target_patches = std::atoi(argv[++i]);
    else if (arg == "--map-resolution" && i + 1 < argc)
      settings.map_resolution = std::atoi(argv[++i]);
    else if (arg == "--max-samples" && i + 1 < argc)
      settings.max_samples_per_emitter = std::atoi(argv[++i]);
    else if (arg == "--secondary-share" && i + 1 < argc)
      settings.secondary_emitter_share = std::atof(argv[++i]);
    else
      level_name.clear(), i = argc;
  }
  const std::vector<Case> all = cases();
  const Case* chosen = nullptr;
  for (const Case& c : all) {
    if (c.name == level_name) chosen = &c;
  }
  if (!chosen || work.empty() || json_path.empty() || frames < 1) {
    std::fprintf(
        stderr,
        "usage: bench_runtime_error --level cornell|house|sponza --work DIR --json OUT "
        "[--budgets 10,50,200,0] [--frames 16] [--quality 0.2] [--one-settle] [--proxies | "
        "--full-geometry] "
        "[--target-patches N] [--map-resolution N] [--max-samples N] [--secondary-share S] "
        "[--settle-budget MS]\n");
    return 2;
  }
  const Case& c = *chosen;
  if (glfwInit() != GLFW_TRUE) {
    std::fprintf(stderr, "bench_runtime_error: no display (run under xvfb-run -a)\n");
    return 1;
  }
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "bench_runtime_error", nullptr, nullptr);
  if (!window) return 1;
  glfwMakeContextCurrent(window);
  const std::string renderer = checkGlContext()->renderer;
  std::printf("GL renderer: %s\n", renderer.c_str());

  const BakedLevel base = bakeOnce(c.level, work + "/" + c.name + "-base", quality);
  const std::string moved_level = writeLevelWithNodeStatic(
      c.level, c.node, c.moved_translation, c.moved_rotation, work, c.name + "-moved-level");
  const BakedLevel reference = bakeOnce(moved_level, work + "/" + c.name + "-moved", quality);
  // The same with the object static where it starts: what the settled runtime should show before
  // the move.
  const std::string start_level = writeLevelWithNodeStatic(
      c.level, c.node, c.start_translation, c.start_rotation, work, c.name + "-start-level");
  const BakedLevel start_reference = bakeOnce(start_level, work + "/" + c.name + "-start", quality);
  const Mat4 moved = placeAt(c.moved_translation, c.moved_rotation);

  // Probes from the object's two places, and the settled runtime's values there before the move.
  std::vector<Probe> probes, candidates;
  std::vector<Rgb> at_rest_all;
  // --one-settle: the settled runtime, object moved, not yet updated
  std::unique_ptr<Runtime> kept;
  {
    std::unique_ptr<Runtime> runtime = settledRuntime(base, settings, settle_budget_ms);
    const ObjectId object = runtime->objectForNode(base.scene.findNode(c.node));
    SVIT_SETUP_CHECK(object != kInvalidId, c.node + " is not a dynamic object");
    const ObjectInfo start = *runtime->objectInfo(object);
    (void)runtime->setObjectTransform(object, moved);
    const ObjectInfo after = *runtime->objectInfo(object);
    const std::vector<Probe> grid =
        c.name == "cornell"
            ? cornellProbes({boundsOf(start.world_positions), boundsOf(after.world_positions)})
            : floorProbes({start.world_positions, after.world_positions}, c.probe_margin_m,
                          c.probe_grid);
    for (const Probe& probe : grid) {  // on static geometry (within 5 cm): not outside a wall
      const Rgb at_rest = runtime->irradianceAt(probe.p, probe.n);
      if (!std::isfinite(luminance(at_rest))) continue;
      candidates.push_back(probe);
      at_rest_all.push_back(at_rest);
    }
    if (one_settle) kept = std::move(runtime);
  }
  // Only points both bakes cover (a probe over a hole or under another object is dropped).
  const std::vector<Rgb> at_base = bakedAt(base, candidates),
                         at_reference = bakedAt(reference, candidates);
  std::vector<Rgb> expected, at_rest;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (luminance(at_base[i]) > 0 && luminance(at_reference[i]) > 0) {
      probes.push_back(candidates[i]);
      expected.push_back(at_reference[i]);
      at_rest.push_back(at_rest_all[i]);
    }
  }
  std::printf("%s: %zu probes (%zu candidates)\n", c.name.c_str(), probes.size(),
              candidates.size());
  SVIT_SETUP_CHECK(probes.size() >= 20, "too few probes");

  nlohmann::json out = {{"level", c.name},
                        {"level_path", c.level},
                        {"node", c.node},
                        {"renderer", renderer},
                        {"quality", quality},
                        {"frames", frames},
                        {"probes", probes.size()},
                        {"settings",
                         {{"use_proxies", settings.use_proxies},
                          {"target_patches", settings.target_patches},
                          {"map_resolution", settings.map_resolution},
                          {"max_samples_per_emitter", settings.max_samples_per_emitter},
                          {"secondary_emitter_share", settings.secondary_emitter_share}}}};
  {
    std::vector<Rgb> base_values;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (luminance(at_base[i]) > 0 && luminance(at_reference[i]) > 0)
        base_values.push_back(at_base[i]);
    }
    // How far apart the two bakes are at the probes (the object's whole effect plus bake noise).
    out["bake_vs_moved_bake"] = normalizedRms(base_values, expected);
    // The settled runtime at the start against the bake with the object static there.
    out["rest_vs_start_bake"] = normalizedRms(at_rest, bakedAt(start_reference, probes));
    // The two static bakes against each other: the object's move as the baker sees it.
    out["start_bake_vs_moved_bake"] = normalizedRms(bakedAt(start_reference, probes), expected);
    std::printf("at rest vs the start bake %.2f%%, start bake vs moved bake %.2f%%\n",
                100 * out["rest_vs_start_bake"].get<double>(),
                100 * out["start_bake_vs_moved_bake"].get<double>());
  }
  std::vector<double> budgets = parseList(budgets_text);
  if (one_settle) budgets.resize(1);
  for (double budget : budgets) {
    std::unique_ptr<Runtime> runtime =
        one_settle ? std::move(kept) : settledRuntime(base, settings, settle_budget_ms);
    const ObjectId object = runtime->objectForNode(base.scene.findNode(c.node));
    nlohmann::json row = {{"budget_ms", budget}};
    (void)runtime->setObjectTransform(object, moved);
    double seconds = 0;
    row["t_s"].push_back(0.0);
    row["rms_rel_error"].push_back(normalizedRms(runtimeAt(*runtime, probes), expected));
    std::printf("budget %6s ms: frame 0 %6.2f%%",
                budget > 0 ? std::to_string(int(budget)).c_str() : "none",
                100 * row["rms_rel_error"][0].get<double>());
    for (int f = 1; f <= frames; ++f) {
      const auto t0 = std::chrono::steady_clock::now();
      const FrameStats s = runtime->update(budget);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      SVIT_SETUP_CHECK(s.error.empty(), s.error);
      const double rms = normalizedRms(runtimeAt(*runtime, probes), expected);
      row["t_s"].push_back(seconds);
      row["rms_rel_error"].push_back(rms);
      row["frame_ms"].push_back(s.total_ms);
      row["emitters_pending"].push_back(s.emitters_pending);
      std::printf(" | %d %.2f%% %.0fms", f, 100 * rms, s.total_ms);
      std::fflush(stdout);
    }
    std::printf("\n");
    out["runs"].push_back(row);
    if (one_settle) {
      // The same runtime brought fully up to date: the settled end point.
      const auto t0 = std::chrono::steady_clock::now();
      const FrameStats s = runtime->update(0);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      SVIT_SETUP_CHECK(s.error.empty(), s.error);
      const double rms = normalizedRms(runtimeAt(*runtime, probes), expected);
      out["settled_after_budget"] = {{"t_s", seconds}, {"rms_rel_error", rms}};
      std::printf("then update(0): %.2f%% after %.1f s of updates\n", 100 * rms, seconds);
    }
  }
  std::ofstream(json_path) << out.dump(1) << "\n";
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

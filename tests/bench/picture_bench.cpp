// Picture error against time along a level's walk: the level's
// dynamic objects follow their paths and the camera its path, as svit-walk
// plays them headless, with a deterministic sample budget per frame. At the
// reference frames, the runtime view and the baked-only view (doing
// nothing) are compared in linear radiance (tests/runtime/picture_metric.h)
// with the baked view of a bake in which every dynamic object is static
// where it is at that frame. Also time to the first frame and per-frame
// times. Runtime lights are switched off (neither bake has them).
// usage: bench_picture --level LEVEL.json --work DIR --json OUT [--frames 90] [--samples 32]
//        [--reference-frames 0,10,30] [--quality 0.1] [--time 8] [--width 320 --height 180]
//        [--exposure 1] [--png-prefix P] [--shadow-masks 0|1]
// Runs under xvfb-run; bakes go to DIR and are reused while their stamp matches.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_bake.h"
#include "moved_level.h"
#include "runtime/gl_test_context.h"
#include "runtime/picture_comparison_png.h"
#include "runtime/picture_metric.h"
#include "svit/gl_context.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"
#include "walk_camera.h"
#include "walk_motion.h"

namespace {

using namespace svit;
using namespace svit::test;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string level, work, json, png_prefix;
  int frames = 90, samples = 32, width = 320, height = 180;
  std::set<int> reference_frames{0, 10, 30};
  double quality = 0.1, time_s = 8;
  float exposure = 1;
  bool shadow_masks = true;  ///< --shadow-masks 0: the base bake without (before issue 21)
};

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// A level with every dynamic object static where `motion` has it now.
std::string writePosedLevel(const Options& o, const Scene& scene, const walk::LevelMotion& motion,
                            int frame) {
  std::string level = o.level;
  for (int node : motion.objectNodes()) {
    const walk::Trs& trs = motion.localTrs(node);
    level = writeLevelWithNodeStatic(
        level, scene.nodes[size_t(node)].name, trs.translation, trs.rotation, o.work,
        "posed-" + std::to_string(frame) + "-" + scene.nodes[size_t(node)].name);
  }
  return level;
}

// The reference picture at `frame`: the posed level baked (seed 8), its baked view.
LinearFrame referencePicture(const Options& o, const Scene& scene, const walk::LevelMotion& motion,
                             int frame, const Camera& camera,
                             const SceneRendererSettings& settings) {
  const std::string level = writePosedLevel(o, scene, motion, frame);
  const BakedLevel ref =
      bakeOnce(level, o.work + "/ref-" + std::to_string(frame), o.quality, 8, o.time_s);
  auto renderer = SceneRenderer::create(ref.scene, ref.bake, ref.dir, nullptr, settings);
  SVIT_SETUP_CHECK(renderer.ok(), renderer.status().message());
  SVIT_SETUP_CHECK((*renderer)->render(camera, ShadingView::kBakedOnly).ok(), "reference render");
  return readLinearFrame(**renderer);
}

nlohmann::json errorJson(const PictureError& e) {
  return {{"static_rel_rms", e.static_rel_rms},
          {"static_pixels", e.static_pixels},
          {"dynamic_mean", e.dynamic_mean},
          {"dynamic_reference_mean", e.dynamic_reference_mean},
          {"dynamic_mean_error", e.dynamicMeanError()},
          {"dynamic_rel_rms", e.dynamic_rel_rms},
          {"dynamic_pixels", e.dynamic_pixels}};
}

std::set<int> parseFrames(const std::string& text) {
  std::set<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.insert(std::atoi(item.c_str()));
  return out;
}

bool parseArgs(int argc, char** argv, Options& o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i], v = argv[i + 1];
    if (arg == "--level")
      o.level = v;
    else if (arg == "--work")
      o.work = v;
    else if (arg == "--json")
      o.json = v;
    else if (arg == "--png-prefix")
      o.png_prefix = v;
    else if (arg == "--frames")
      o.frames = std::atoi(v.c_str());
    else if (arg == "--samples")
      o.samples = std::atoi(v.c_str());
    else if (arg == "--width")
      o.width = std::atoi(v.c_str());
    else if (arg == "--height")
      o.height = std::atoi(v.c_str());
    else if (arg == "--reference-frames")
      o.reference_frames = parseFrames(v);
    else if (arg == "--quality")
      o.quality = std::atof(v.c_str());
    else if (arg == "--time")
      o.time_s = std::atof(v.c_str());
    else if (arg == "--shadow-masks")
      o.shadow_masks = v != "0";
    else if (arg == "--exposure")
      o.exposure = float(std::atof(v.c_str()));
    else
      return false;
  }
  return argc % 2 == 1 && !o.level.empty() && !o.work.empty() && !o.json.empty() && o.frames > 0;
}

RuntimeView viewOf(const Camera& c, const SceneRendererSettings& s) {
  RuntimeView v;
  v.position = c.position;
  v.look_at = c.look_at;
  v.up = c.up;
  v.yfov_rad = c.yfov_rad;
  v.aspect = float(s.width) / float(s.height);
  v.near_m = c.near_m;
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parseArgs(argc, argv, o)) {
    std::fprintf(
        stderr,
        "usage: bench_picture --level LEVEL.json --work DIR --json OUT [--frames 90] [--samples "
        "32] "
        "[--reference-frames 0,10,30] [--quality 0.1] [--time 8] [--width 320 --height 180] "
        "[--exposure 1] [--png-prefix P]\n");
    return 2;
  }
  const GlTestContext context;
  if (!context.ok()) {
    std::fprintf(stderr, "bench_picture: no GL 4.5 context (run under xvfb-run -a)\n");
    return 1;
  }
  const std::string gl = checkGlContext()->renderer;
  std::filesystem::create_directories(o.work);
  const BakedLevel base =
      bakeOnce(o.level, o.work + "/base", o.quality, 7, o.time_s, o.shadow_masks);

  SceneRendererSettings settings;
  settings.width = o.width;
  settings.height = o.height;
  settings.auto_exposure = false;
  settings.exposure = o.exposure;
  // Start-up: what a game pays before its first frame.
  const auto t_start = Clock::now();
  RuntimeSettings runtime_settings;
  runtime_settings.max_samples_per_frame = o.samples;
  runtime_settings.delta_textures = false;
  auto created = Runtime::create(base.scene, base.bake, base.dir, runtime_settings);
  SVIT_SETUP_CHECK(created.ok(), created.status().message());
  std::unique_ptr<Runtime> runtime = std::move(created).value();
  for (LightId light : runtime->lights()) (void)runtime->setLightEnabled(light, false);
  auto made = SceneRenderer::create(base.scene, base.bake, base.dir, runtime.get(), settings);
  SVIT_SETUP_CHECK(made.ok(), made.status().message());
  std::unique_ptr<SceneRenderer> renderer = std::move(made).value();
  const double create_ms = msSince(t_start);

  walk::LevelMotion motion(base.scene);
  const Camera overview = walk::levelOverview(base.scene);
  const float fps = 30;
  nlohmann::json frames = nlohmann::json::array();
  double first_frame_ms = 0;
  for (int f = 0; f < o.frames; ++f) {
    const float t = float(f) / fps;
    const auto t0 = Clock::now();
    motion.advance(t);
    SVIT_SETUP_CHECK(motion.applyTo(*runtime).ok(), "placing the objects");
    const Camera camera = walk::cameraAt(base.scene, overview, {},
                                         *walk::chooseSceneCamera(base.scene, "", "", false), t);
    SVIT_SETUP_CHECK(runtime->setView(viewOf(camera, settings)).ok(), "view");
    const FrameStats stats = runtime->update(0);
    SVIT_SETUP_CHECK(stats.error.empty(), stats.error);
    Expected<RenderStats> drawn = renderer->render(camera, ShadingView::kRuntime);
    SVIT_SETUP_CHECK(drawn.ok(), drawn.status().message());
    const LinearFrame shown = readLinearFrame(*renderer);
    const double frame_ms = msSince(t0);
    if (f == 0) first_frame_ms = create_ms + frame_ms;
    nlohmann::json row = {{"frame", f},
                          {"t_s", t},
                          {"update_ms", stats.total_ms},
                          {"shading_ms", drawn->shading_ms},
                          {"frame_ms", frame_ms},
                          {"samples", stats.samples_rendered},
                          {"pending", stats.emitters_pending}};
    if (o.reference_frames.count(f) != 0) {
      SVIT_SETUP_CHECK(renderer->render(camera, ShadingView::kBakedOnly).ok(), "baked-only render");
      const LinearFrame baked_only = readLinearFrame(*renderer);
      const LinearFrame reference = referencePicture(o, base.scene, motion, f, camera, settings);
      const PictureError runtime_error = comparePictures(shown, reference);
      const PictureError baked_error = comparePictures(baked_only, reference);
      row["runtime"] = errorJson(runtime_error);
      row["baked_only"] = errorJson(baked_error);
      std::printf(
          "frame %3d: static %.4f (baked-only %.4f), objects %+.1f %% (baked-only %+.1f %%), %u "
          "pending\n",
          f, runtime_error.static_rel_rms, baked_error.static_rel_rms,
          100 * runtime_error.dynamicMeanError(), 100 * baked_error.dynamicMeanError(),
          stats.emitters_pending);
      if (!o.png_prefix.empty()) {
        (void)writeComparisonPng(o.png_prefix + "-" + std::to_string(f) + ".png", shown, reference,
                                 o.exposure);
      }
    }
    frames.push_back(row);
    std::fflush(stdout);
  }
  double sum_ms = 0;
  for (const nlohmann::json& row : frames) sum_ms += row["frame_ms"].get<double>();
  nlohmann::json out = {{"level", o.level},
                        {"renderer", gl},
                        {"samples_per_frame", o.samples},
                        {"bake_quality", o.quality},
                        {"bake_time_s", o.time_s},
                        {"shadow_masks", o.shadow_masks},
                        {"create_ms", create_ms},
                        {"first_frame_ms", first_frame_ms},
                        {"mean_frame_ms", sum_ms / double(frames.size())},
                        {"frames", frames}};
  std::ofstream(o.json) << out.dump(1) << "\n";
  std::printf("%s: ready in %.0f ms, first frame after %.0f ms, mean frame %.0f ms (%s)\n",
              o.level.c_str(), create_ms, first_frame_ms, sum_ms / double(frames.size()),
              gl.c_str());
  return 0;
}

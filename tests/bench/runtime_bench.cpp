// Runtime benchmark, run headless under xvfb-run on whatever GL is
// there (Mesa llvmpipe on the CI machines: a CPU rasteriser, so absolute
// times are far above a GPU's; the ratios are the figures):
//  1. per-stage frame time (maps, reduction, bounces, upload) for the Cornell
//     box and Sponza with 1, 4 and 16 moving objects: on the Cornell box
//     every emitter brought up to date each frame (budget 0); on Sponza,
//     where that takes minutes per frame on llvmpipe, a per-frame budget
//     of --sponza-budget point samples (64), from the first frame;
//  2. LOD proxies against full static geometry: time and the difference in
//     per-patch deltas;
//  3. the runtime's error against a bake with the moved tall box static, as
//     a function of frames and per-frame budget (Cornell).
// usage: bench_runtime [--frames N] [--json OUT] [--sponza LEVEL | --no-sponza]
//                      [--sponza-budget SAMPLES] [--sponza-frames N]
// Bakes what it needs into /tmp first (a few minutes for Sponza).

#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/cornell_probes.h"
#include "svit/gl_context.h"
#include "svit/runtime.h"

namespace {

using namespace svit;
using namespace svit::test;

DynamicMesh crate(float half) {
  DynamicMesh mesh;
  mesh.name = "crate";
  for (int i = 0; i < 8; ++i)
    mesh.positions.push_back(
        {(i & 1) ? half : -half, (i & 2) ? half : -half, (i & 4) ? half : -half});
  mesh.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  mesh.albedo = {0.7f, 0.6f, 0.5f};
  return mesh;
}

struct Stage {
  double maps = 0, reduction = 0, bounce = 0, upload = 0, total = 0;
  double samples = 0, faces = 0;
};

// Objects circling in a horizontal ring around `centre`; every emitter kept
// current (sample_budget 0), or `sample_budget` point samples per frame.
// Returns mean stats over `frames` frames after the first.
Stage movingObjects(const BakedLevel& level, bool proxies, int objects, int frames,
                    glm::vec3 centre, float radius, float size, int sample_budget,
                    std::vector<Rgb>* deltas_out) {
  RuntimeSettings settings;
  settings.use_proxies = proxies;
  settings.max_samples_per_frame = sample_budget;
  Expected<std::unique_ptr<Runtime>> created =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  SVIT_SETUP_CHECK(created.ok(), created.status().message());
  Runtime& runtime = **created;
  std::vector<ObjectId> ids;
  auto place = [&](int i, int frame) {
    const float a = 6.2831853f * (float(i) / float(objects)) + 0.15f * float(frame);
    return fromGlmMat(glm::translate(
        glm::mat4(1), centre + glm::vec3(radius * std::cos(a), 0, radius * std::sin(a))));
  };
  for (int i = 0; i < objects; ++i) ids.push_back(*runtime.addObject(crate(size), place(i, 0)));
  runtime.update(0);  // first frame: baselines (every emitter's, unless budgeted): start-up cost
  Stage mean;
  for (int f = 1; f <= frames; ++f) {
    for (int i = 0; i < objects; ++i) (void)runtime.setObjectTransform(ids[size_t(i)], place(i, f));
    const FrameStats s = runtime.update(0);
    SVIT_SETUP_CHECK(s.error.empty(), s.error);
    mean.maps += s.maps_ms / frames;
    mean.reduction += s.reduction_ms / frames;
    mean.bounce += s.bounce_ms / frames;
    mean.upload += s.upload_ms / frames;
    mean.total += s.total_ms / frames;
    mean.samples += double(s.samples_rendered) / frames;
    mean.faces += double(s.faces_rendered) / frames;
  }
  if (deltas_out) *deltas_out = runtime.patchDeltas();
  return mean;
}

double relativeL1(const std::vector<Rgb>& a, const std::vector<Rgb>& b, size_t n) {
  double diff = 0, norm = 0;
  for (size_t i = 0; i < n; ++i) {
    diff += std::abs(double(luminance(a[i])) - luminance(b[i]));
    norm += std::abs(double(luminance(b[i])));
  }
  return norm > 0 ? diff / norm : 0;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 10, sponza_budget = 64, sponza_frames = 4;
  std::string json_path,
      sponza_level = std::string(SVIT_SOURCE_DIR) + "/samples/levels/sponza/level.json";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc)
      json_path = argv[++i];
    else if (!std::strcmp(argv[i], "--sponza") && i + 1 < argc)
      sponza_level = argv[++i];
    else if (!std::strcmp(argv[i], "--no-sponza"))
      sponza_level.clear();
    else if (!std::strcmp(argv[i], "--sponza-budget") && i + 1 < argc)
      sponza_budget = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--sponza-frames") && i + 1 < argc)
      sponza_frames = std::atoi(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: bench_runtime [--frames N] [--json OUT] [--sponza LEVEL | --no-sponza] "
                   "[--sponza-budget SAMPLES] [--sponza-frames N]\n");
      return 2;
    }
  }
  if (glfwInit() != GLFW_TRUE) {
    std::fprintf(stderr, "bench_runtime: no display (run under xvfb-run -a)\n");
    return 1;
  }
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "bench_runtime", nullptr, nullptr);
  if (!window) return 1;
  glfwMakeContextCurrent(window);
  const std::string renderer = checkGlContext()->renderer;
  std::printf("GL renderer: %s\n", renderer.c_str());
  nlohmann::json out;
  out["renderer"] = renderer;
  out["frames"] = frames;

  struct LevelCase {
    std::string name, path;
    glm::vec3 centre;
    float radius, size;
  };
  std::vector<LevelCase> levels = {{"cornell", cornellLevel(), {0, 1.0f, 0.3f}, 0.4f, 0.08f},
                                   {"sponza", sponza_level, {0, 5.0f, 0}, 4.0f, 0.4f}};
  if (sponza_level.empty()) levels.pop_back();
  std::printf("\n1-2. frame time by stage (ms, mean of %d frames, every emitter current)\n",
              frames);
  std::printf("%-8s %-7s %4s | %8s %9s %7s %6s %8s | %7s %6s | %s\n", "level", "static", "objs",
              "maps", "reduction", "bounce", "upload", "total", "samples", "faces",
              "delta diff vs full");
  for (const LevelCase& lc : levels) {
    const BakedLevel& level = bakedLevel(lc.name, lc.path, lc.name == "cornell" ? 0.3 : 0.1);
    if (!level.bake.has_runtime_sections) {
      std::printf(
          "%-8s: the bake has no runtime sections (the level has no dynamic content): skipped\n",
          lc.name.c_str());
      continue;
    }
    const bool budgeted = lc.name == "sponza";
    const int budget = budgeted ? sponza_budget : 0,
              level_frames = budgeted ? sponza_frames : frames;
    if (budgeted) {
      std::printf(
          "(sponza: %d samples per frame, mean of %d frames after the first; the delta difference "
          "of two "
          "unsettled runtimes is not a figure, so none)\n",
          budget, level_frames);
    }
    for (int objects : {1, 4, 16}) {
      std::vector<Rgb> proxy_deltas, full_deltas;
      const Stage p = movingObjects(level, true, objects, level_frames, lc.centre, lc.radius,
                                    lc.size, budget, &proxy_deltas);
      const Stage f = movingObjects(level, false, objects, level_frames, lc.centre, lc.radius,
                                    lc.size, budget, &full_deltas);
      const double diff = budgeted
                              ? std::nan("")
                              : relativeL1(proxy_deltas, full_deltas, level.bake.patches.size());
      for (int k = 0; k < 2; ++k) {
        const Stage& s = k == 0 ? p : f;
        std::printf(
            "%-8s %-7s %4d | %8.1f %9.1f %7.2f %6.2f %8.1f | %7.0f %6.0f | %s\n", lc.name.c_str(),
            k == 0 ? "proxies" : "full", objects, s.maps, s.reduction, s.bounce, s.upload, s.total,
            s.samples, s.faces,
            k == 0 && !budgeted ? (std::to_string(100 * diff).substr(0, 5) + "%").c_str() : "");
        out["stages"].push_back(
            {{"level", lc.name},
             {"static", k == 0 ? "proxies" : "full"},
             {"objects", objects},
             {"maps_ms", s.maps},
             {"reduction_ms", s.reduction},
             {"bounce_ms", s.bounce},
             {"upload_ms", s.upload},
             {"total_ms", s.total},
             {"samples", s.samples},
             {"faces", s.faces},
             {"sample_budget", budget},
             {"proxy_vs_full_rel_l1", budgeted ? nlohmann::json() : nlohmann::json(diff)}});
      }
    }
  }

  std::printf(
      "\n3. Cornell: error against a bake with the moved box static, by per-frame budget\n");
  const BakedLevel& level = bakedLevel("cornell", cornellLevel());
  const glm::mat4 moved = glm::translate(glm::mat4(1), glm::vec3(0.25f, 0, 0.1f)) *
                          glm::mat4_cast(glm::quat(0.9659258f, 0, 0.2588190f, 0));
  const BakedLevel& reference =
      bakedLevel("cornell_moved", writeCornellWithBoxAt(moved, "bench"), 0.3);
  std::printf("%9s |", "budget ms");
  for (int f = 1; f <= 8; ++f) std::printf(" frame %d", f);
  std::printf(" | ms/frame\n");
  for (double budget : {5.0, 20.0, 50.0, 200.0, 0.0}) {
    Expected<std::unique_ptr<Runtime>> created =
        Runtime::create(level.scene, level.bake, level.dir);
    Runtime& runtime = **created;
    const ObjectId box = runtime.objectForNode(level.scene.findNode("tallBox"));
    settle(runtime);  // settled at the start place
    const ObjectInfo start = *runtime.objectInfo(box);
    (void)runtime.setObjectTransform(box, fromGlmMat(moved));
    const ObjectInfo after = *runtime.objectInfo(box);
    const std::vector<Probe> probes =
        cornellProbes({boundsOf(start.world_positions), boundsOf(after.world_positions)});
    const std::vector<Rgb> expected = bakedAt(reference, probes);
    std::printf("%9s |", budget > 0 ? std::to_string(int(budget)).c_str() : "none");
    nlohmann::json row = {{"budget_ms", budget}};
    double ms = 0;
    for (int f = 1; f <= 8; ++f) {
      const FrameStats s = runtime.update(budget);
      ms += s.total_ms / 8;
      const double rms = normalizedRms(runtimeAt(runtime, probes), expected);
      std::printf(" %6.2f%%", 100 * rms);
      row["rms_rel_error"].push_back(rms);
      row["frame_ms"].push_back(s.total_ms);
    }
    std::printf(" | %8.1f\n", ms);
    out["error_vs_budget"].push_back(row);
  }
  if (!json_path.empty()) std::ofstream(json_path) << out.dump(1) << "\n";
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

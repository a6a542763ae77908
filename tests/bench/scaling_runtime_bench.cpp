// Runtime scaling benchmark, one measurement per process so
// tests/bench/scaling.py can sweep a parameter across levels: mean per-stage
// frame time (maps, reduction, bounce, upload) of a baked level while N crates
// circle in a ring, every emitter brought up to date each frame (budget 0,
// no view), static geometry as full triangles or as the bake's LOD proxies.
// With --budget-samples S every update renders at most S point samples (one
// map each), so the frame time is S maps of this level's geometry: the cost
// per map against static triangles. Runs headless under xvfb-run on whatever
// GL is there (Mesa llvmpipe on the development machine: a CPU rasteriser,
// so the growth is the figure, not the milliseconds; --map-resolution below
// the default 128 keeps a settle-everything frame within seconds there).
// usage: bench_scaling_runtime LEVEL BAKE_DIR [--proxies 0|1] [--objects N]
//          [--frames F] [--budget-samples S] [--map-resolution R]
//          [--centre X Y Z] [--radius M] [--size M] [--json OUT]

#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/gl_context.h"
#include "svit/level.h"
#include "svit/runtime.h"

namespace {

using namespace svit;

#define BENCH_CHECK(cond, message)                                                       \
  do {                                                                                   \
    if (!(cond)) {                                                                       \
      std::fprintf(stderr, "bench_scaling_runtime: %s\n", std::string(message).c_str()); \
      std::exit(1);                                                                      \
    }                                                                                    \
  } while (0)

struct Options {
  std::string level, bake_dir, json_path;
  bool proxies = false;
  int objects = 4;
  int frames = 5;
  int budget_samples = 0;    // RuntimeSettings::max_samples_per_frame, 0 = none
  int map_resolution = 128;  // RuntimeSettings::map_resolution
  Vec3 centre{0, 1.5f, 0};
  float radius_m = 2.0f;
  float size_m = 0.3f;
};

// A closed cube of edge 2 * half metres, faces outward (12 triangles).
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

// Object i of n on the ring at `frame`: a pure translation (column-major).
Mat4 ringPlace(const Options& o, int i, int frame) {
  const float a = 6.2831853f * (float(i) / float(o.objects)) + 0.15f * float(frame);
  Mat4 m;  // identity
  m.m[12] = o.centre.x + o.radius_m * std::cos(a);
  m.m[13] = o.centre.y;
  m.m[14] = o.centre.z + o.radius_m * std::sin(a);
  return m;
}

Options parse(int argc, char** argv) {
  Options o;
  int positional = 0;
  for (int i = 1; i < argc; ++i) {
    auto next = [&]() -> const char* {
      BENCH_CHECK(i + 1 < argc, std::string(argv[i]) + " needs a value");
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--proxies"))
      o.proxies = std::atoi(next()) != 0;
    else if (!std::strcmp(argv[i], "--objects"))
      o.objects = std::atoi(next());
    else if (!std::strcmp(argv[i], "--frames"))
      o.frames = std::atoi(next());
    else if (!std::strcmp(argv[i], "--budget-samples"))
      o.budget_samples = std::atoi(next());
    else if (!std::strcmp(argv[i], "--map-resolution"))
      o.map_resolution = std::atoi(next());
    else if (!std::strcmp(argv[i], "--radius"))
      o.radius_m = float(std::atof(next()));
    else if (!std::strcmp(argv[i], "--size"))
      o.size_m = float(std::atof(next()));
    else if (!std::strcmp(argv[i], "--json"))
      o.json_path = next();
    else if (!std::strcmp(argv[i], "--centre")) {
      o.centre.x = float(std::atof(next()));
      o.centre.y = float(std::atof(next()));
      o.centre.z = float(std::atof(next()));
    } else if (argv[i][0] != '-' && positional < 2)
      (positional++ == 0 ? o.level : o.bake_dir) = argv[i];
    else
      BENCH_CHECK(false, std::string("unknown argument ") + argv[i]);
  }
  BENCH_CHECK(
      positional == 2,
      "usage: bench_scaling_runtime LEVEL BAKE_DIR [--proxies 0|1] [--objects N] [--frames F] "
      "[--budget-samples S] [--map-resolution R] [--centre X Y Z] [--radius M] [--size M] [--json "
      "OUT]");
  BENCH_CHECK(o.objects >= 0 && o.frames >= 1, "--objects must be >= 0 and --frames >= 1");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  Expected<Scene> scene = loadLevel(o.level);
  BENCH_CHECK(scene.ok(), scene.status().message());
  Expected<BakeData> bake = readBakeFile(o.bake_dir + "/bake.svit");
  BENCH_CHECK(bake.ok(), bake.status().message());
  BENCH_CHECK(bake->has_runtime_sections,
              "the bake has no runtime sections (the level has no dynamic content)");

  BENCH_CHECK(glfwInit() == GLFW_TRUE, "no display (run under xvfb-run -a)");
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "bench_scaling_runtime", nullptr, nullptr);
  BENCH_CHECK(window != nullptr, "no OpenGL 4.5 window");
  glfwMakeContextCurrent(window);
  const std::string renderer = checkGlContext()->renderer;

  RuntimeSettings settings;
  settings.use_proxies = o.proxies;
  settings.max_samples_per_frame = o.budget_samples;
  settings.map_resolution = o.map_resolution;
  const auto create_start = std::chrono::steady_clock::now();
  Expected<std::unique_ptr<Runtime>> created = Runtime::create(*scene, *bake, o.bake_dir, settings);
  BENCH_CHECK(created.ok(), created.status().message());
  Runtime& runtime = **created;
  std::vector<ObjectId> ids;
  for (int i = 0; i < o.objects; ++i) {
    Expected<ObjectId> id = runtime.addObject(crate(0.5f * o.size_m), ringPlace(o, i, 0));
    BENCH_CHECK(id.ok(), id.status().message());
    ids.push_back(*id);
  }
  // First update: emitters' baselines (start-up cost, reported apart; with a
  // sample budget only the first S of them).
  const FrameStats first = runtime.update(0);
  BENCH_CHECK(first.error.empty(), first.error);
  const double create_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - create_start)
          .count();

  double maps = 0, reduction = 0, bounce = 0, upload = 0, total = 0, samples = 0, faces = 0,
         refreshed = 0, pending = 0, fallback = 0, texels = 0;
  for (int f = 1; f <= o.frames; ++f) {
    for (int i = 0; i < o.objects; ++i)
      BENCH_CHECK(runtime.setObjectTransform(ids[size_t(i)], ringPlace(o, i, f)).ok(), "move");
    const FrameStats s = runtime.update(0);
    BENCH_CHECK(s.error.empty(), s.error);
    maps += s.maps_ms / o.frames;
    reduction += s.reduction_ms / o.frames;
    bounce += s.bounce_ms / o.frames;
    upload += s.upload_ms / o.frames;
    total += s.total_ms / o.frames;
    samples += double(s.samples_rendered) / o.frames;
    faces += double(s.faces_rendered) / o.frames;
    refreshed += double(s.emitters_refreshed) / o.frames;
    pending += double(s.emitters_pending) / o.frames;
    fallback += double(s.fallback_triangles) / o.frames;
    texels += double(s.texels_reduced) / o.frames;
  }
  const size_t emitters = runtime.emitterStates().size();
  std::printf(
      "%s | %s | proxies %d objects %d | maps %.1f reduction %.1f bounce %.2f upload %.2f total "
      "%.1f ms | "
      "samples %.0f faces %.0f refreshed %.0f (pending %.0f) of %zu emitters | fallback triangles "
      "%.0f | "
      "create+first %.0f ms | bake emitters %zu, proxy triangles %zu\n",
      o.level.c_str(), renderer.c_str(), int(o.proxies), o.objects, maps, reduction, bounce, upload,
      total, samples, faces, refreshed, pending, emitters, fallback, create_ms,
      bake->emitters.size(), bake->proxy.indices.size() / 3);
  if (!o.json_path.empty()) {
    const nlohmann::json out = {{"level", o.level},
                                {"renderer", renderer},
                                {"proxies", o.proxies},
                                {"objects", o.objects},
                                {"frames", o.frames},
                                {"budget_samples", o.budget_samples},
                                {"map_resolution", o.map_resolution},
                                {"pending_emitters", pending},
                                {"fallback_triangles", fallback},
                                {"texels_reduced", texels},
                                {"proxy_triangles", bake->proxy.indices.size() / 3},
                                {"maps_ms", maps},
                                {"reduction_ms", reduction},
                                {"bounce_ms", bounce},
                                {"upload_ms", upload},
                                {"total_ms", total},
                                {"samples", samples},
                                {"faces", faces},
                                {"emitters_refreshed", refreshed},
                                {"runtime_emitters", emitters},
                                {"bake_emitters", bake->emitters.size()},
                                {"bake_patches", bake->patches.size()},
                                {"create_and_first_update_ms", create_ms}};
    std::ofstream(o.json_path) << out.dump(1) << "\n";
  }
  created->reset();  // GL objects go while the context is still current
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

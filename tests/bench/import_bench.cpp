// Level import cost on the shared scenes, with and without texture decoding,
// side by side in one process (ratios, not absolute timings, are the figure).
// Prints a table and writes bench_import.json. Machine: note it with the run.
// usage: bench_import [OUT_JSON]

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "svit/level.h"
#include "svit/scene_summary.h"

namespace {

double secondsToLoad(const std::string& path, bool textures, size_t& triangles) {
  svit::LoadOptions options;
  options.load_textures = textures;
  const auto start = std::chrono::steady_clock::now();
  svit::Expected<svit::Scene> scene = svit::loadLevel(path, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().message().c_str());
    return -1;
  }
  const svit::SceneSummary summary = svit::summarize(*scene);
  triangles = summary.static_triangles + summary.dynamic_triangles;
  return seconds;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : "bench_import.json";
  const std::string scenes = SVIT_SHARED_SCENES_DIR;
  const std::vector<std::pair<std::string, std::string>> levels = {
      {"cornell_box_original",
       std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/CornellBox-Original.gltf"},
      {"cornell_box_vinc3r", scenes + "/cornell_box_vinc3r/cornellBox-2.80-Eevee-gltf.gltf"},
      {"virtual_city", scenes + "/virtual_city/VC.gltf"},
      {"sponza", scenes + "/sponza/Sponza.gltf"}};
  constexpr int kRepeats = 3;  // best of 3 against a busy 2-core machine
  std::printf("%-22s %10s %12s %12s %8s %14s\n", "level", "triangles", "no_tex_s", "tex_s", "ratio",
              "Mtri/s(no tex)");
  std::string json = "[\n";
  for (size_t i = 0; i < levels.size(); ++i) {
    size_t triangles = 0;
    double best_plain = 1e30, best_textured = 1e30;
    for (int r = 0; r < kRepeats; ++r) {
      best_plain = std::min(best_plain, secondsToLoad(levels[i].second, false, triangles));
      best_textured = std::min(best_textured, secondsToLoad(levels[i].second, true, triangles));
    }
    std::printf("%-22s %10zu %12.4f %12.4f %8.2f %14.2f\n", levels[i].first.c_str(), triangles,
                best_plain, best_textured, best_textured / best_plain,
                triangles / best_plain * 1e-6);
    char line[256];
    std::snprintf(line, sizeof line,
                  "  {\"level\": \"%s\", \"triangles\": %zu, \"load_s_no_textures\": %.6f, "
                  "\"load_s_textures\": %.6f}%s\n",
                  levels[i].first.c_str(), triangles, best_plain, best_textured,
                  i + 1 < levels.size() ? "," : "");
    json += line;
  }
  json += "]\n";
  std::ofstream(out) << json;
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

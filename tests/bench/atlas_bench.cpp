// Lightmap atlas cost and size on one level: buildLightmapAtlas alone (no
// radiosity, no lighting), timed, with what the atlas spends: pages, page
// size, charts and the texels its triangles cover (UV area), so a faster
// unwrap can be checked not to buy its speed with a bigger atlas.
// usage: bench_atlas LEVEL [--texels-per-m T] [--threads N] [--max-page-size P]
//                   [--piece-triangles K]   (AtlasSettings::chart_piece_triangles; 0: whole
//                   instances)
// Without --texels-per-m, the density svit-bake picks (about 256k texels).
// Prints one JSON object. Machine: note it with the run.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/level.h"

namespace {

/// Texels the triangles' UVs cover, summed (overlap-free atlas: the area).
double uvTexels(const svit::baker::LightmapAtlas& atlas) {
  double sum = 0;
  for (size_t t = 0; t < atlas.triangle_page.size(); ++t) {
    const svit::Vec2* uv = &atlas.triangle_uv[t * 3];
    const double ax = double(uv[1].x - uv[0].x) * atlas.page_width;
    const double ay = double(uv[1].y - uv[0].y) * atlas.page_height;
    const double bx = double(uv[2].x - uv[0].x) * atlas.page_width;
    const double by = double(uv[2].y - uv[0].y) * atlas.page_height;
    sum += 0.5 * std::fabs(ax * by - ay * bx);
  }
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_atlas LEVEL [--texels-per-m T] [--threads N] "
                 "[--max-page-size P] [--piece-triangles K]\n");
    return 2;
  }
  svit::baker::AtlasSettings settings;
  settings.texels_per_m = 0;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--texels-per-m"))
      settings.texels_per_m = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads"))
      settings.threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--max-page-size"))
      settings.max_page_size = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--piece-triangles"))
      settings.chart_piece_triangles = size_t(std::atol(argv[i + 1]));
    else {
      std::fprintf(stderr, "bench_atlas: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  svit::LoadOptions load;
  load.load_textures = false;
  svit::Expected<svit::Scene> scene = svit::loadLevel(argv[1], load);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().message().c_str());
    return 1;
  }
  svit::Expected<svit::baker::BakeGeometry> geometry = svit::baker::flattenStaticGeometry(*scene);
  if (!geometry.ok()) {
    std::fprintf(stderr, "%s\n", geometry.status().message().c_str());
    return 1;
  }
  if (!(settings.texels_per_m > 0)) {
    // As bake_plan.cpp's atlasTexelsPerM: 262144 texels, clamped to [1, 512] per metre.
    double area_m2 = 0;
    for (float a : geometry->areas_m2) area_m2 += a;
    settings.texels_per_m = std::clamp(std::sqrt(262144.0 / std::max(area_m2, 1e-9)), 1.0, 512.0);
  }
  const auto start = std::chrono::steady_clock::now();
  svit::Expected<svit::baker::LightmapAtlas> atlas =
      svit::baker::buildLightmapAtlas(*scene, *geometry, settings);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!atlas.ok()) {
    std::fprintf(stderr, "%s\n", atlas.status().message().c_str());
    return 1;
  }
  const std::set<uint32_t> charts(atlas->triangle_chart.begin(), atlas->triangle_chart.end());
  std::printf(
      "{\"level\": \"%s\", \"triangles\": %zu, \"texels_per_m\": %g, \"threads\": %d, "
      "\"piece_triangles\": %zu, "
      "\"atlas_s\": %.3f, \"pages\": %d, \"page_width\": %d, \"page_height\": %d, "
      "\"page_texels\": %.0f, \"charts\": %zu, \"uv_texels\": %.0f}\n",
      argv[1], geometry->triangleCount(), settings.texels_per_m, settings.threads,
      settings.chart_piece_triangles, seconds, atlas->page_count, atlas->page_width,
      atlas->page_height, double(atlas->page_count) * atlas->page_width * atlas->page_height,
      charts.size(), uvTexels(*atlas));
  return 0;
}

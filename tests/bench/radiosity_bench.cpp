// Radiosity benchmark: (1) rays per second of the whole shooter
// against Embree's raw throughput on rays of the same distribution (uniform
// surface points, cosine directions) over the same scene, side by side in
// one process — the ratio is the figure; (2) convergence: the estimated and
// the true error (against a long run with another seed) over time.
// usage: bench_radiosity [--seconds S] [--reference-seconds R] [--json OUT] [LEVEL NAME]...
// With no levels: the Cornell box and the Sponza sun/sky level.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "svit/baker/radiosity.h"
#include "svit/level.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace {

using namespace svit;
using namespace svit::baker;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Raw caster throughput on `count` rays leaving surfaces (area-uniform
// points, cosine directions, offset origins), cast in the solver's chunking.
double rawRaysPerSecond(const BakeGeometry& g, const RayCaster& caster, size_t count, int threads) {
  std::vector<double> cdf(g.triangleCount());
  double total = 0;
  for (size_t t = 0; t < g.triangleCount(); ++t) cdf[t] = (total += g.areas_m2[t]);
  std::vector<Ray> rays(count);
  Rng rng(hashIds(42, 7));
  for (Ray& ray : rays) {
    const double pick = rng.uniformDouble() * total;
    const size_t t = size_t(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin());
    const glm::dvec2 b = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
    const Vec3 &c0 = g.corner(t, 0), &c1 = g.corner(t, 1), &c2 = g.corner(t, 2);
    const Vec3 p{float(c0.x + b.x * (c1.x - c0.x) + b.y * (c2.x - c0.x)),
                 float(c0.y + b.x * (c1.y - c0.y) + b.y * (c2.y - c0.y)),
                 float(c0.z + b.x * (c1.z - c0.z) + b.y * (c2.z - c0.z))};
    const glm::dvec3 n(g.normals[t].x, g.normals[t].y, g.normals[t].z);
    const glm::dvec3 d = cosineHemisphere(n, rng.uniformDouble(), rng.uniformDouble());
    ray.origin = offsetRayOrigin(p, g.normals[t], cornerMagnitude(g, t));
    ray.direction = {float(d.x), float(d.y), float(d.z)};
  }
  std::vector<RayHit> hits(count);
  const auto start = Clock::now();
  parallelFor(count, 1024, threads, [&](size_t begin, size_t end) {
    caster.intersect(std::span<const Ray>(rays.data() + begin, end - begin),
                     std::span<RayHit>(hits.data() + begin, end - begin));
  });
  return double(count) / secondsSince(start);
}

struct Result {
  std::string name;
  size_t triangles = 0;
  double shooter_rays_per_s = 0, raw_rays_per_s = 0;
  std::vector<ErrorPoint> series;
  SolverStats stats;
};

Result runLevel(const std::string& path, const std::string& name, double seconds,
                double reference_seconds) {
  Result result;
  result.name = name;
  Expected<Scene> scene = loadLevel(path);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().message().c_str());
    return result;
  }
  Expected<BakeGeometry> geometry = flattenStaticGeometry(*scene);
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(*geometry);
  if (!geometry.ok() || !caster.ok()) return result;
  result.triangles = geometry->triangleCount();
  const int threads = resolveThreads(0);

  // Reference: a long run with another seed.
  RadiositySettings reference_settings;
  reference_settings.seed = 999;
  auto reference = RadiositySolver::create(*scene, *geometry, **caster, reference_settings);
  StopRule reference_stop;
  reference_stop.max_seconds = reference_seconds;
  (void)(*reference)->improve(reference_stop);
  const std::vector<Rgb> reference_irradiance = (*reference)->triangleIrradiance(true);

  RadiositySettings settings;
  auto solver = RadiositySolver::create(*scene, *geometry, **caster, settings);
  (*solver)->setReference(reference_irradiance);
  StopRule stop;
  stop.max_seconds = seconds;
  (void)(*solver)->improve(stop);
  result.stats = (*solver)->stats();
  result.series = (*solver)->errorSeries();
  result.shooter_rays_per_s = double(result.stats.rays) / result.stats.seconds;
  result.raw_rays_per_s = rawRaysPerSecond(*geometry, **caster, 1u << 20, threads);
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 20, reference_seconds = 120;
  std::string json_path = "bench_radiosity.json";
  std::vector<std::pair<std::string, std::string>> levels;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--reference-seconds") && i + 1 < argc) {
      reference_seconds = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) {
      json_path = argv[++i];
    } else if (i + 1 < argc) {
      levels.push_back({argv[i], argv[i + 1]});
      ++i;
    }
  }
  if (levels.empty()) {
    levels = {
        {std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/CornellBox-Original.gltf",
         "cornell_box_original"},
        {std::string(SVIT_SOURCE_DIR) + "/samples/levels/sponza/level.json", "sponza (sun + sky)"}};
  }
  std::string json = "[\n";
  for (size_t l = 0; l < levels.size(); ++l) {
    const Result r = runLevel(levels[l].first, levels[l].second, seconds, reference_seconds);
    std::printf("\n%s: %zu triangles, %d threads\n", r.name.c_str(), r.triangles,
                resolveThreads(0));
    std::printf("  shooter %.3g rays/s, raw Embree %.3g rays/s, ratio %.2f\n", r.shooter_rays_per_s,
                r.raw_rays_per_s, r.shooter_rays_per_s / r.raw_rays_per_s);
    std::printf("  generate + cast + locate: %.1f%% of solver time\n",
                100.0 * r.stats.cast_seconds / r.stats.seconds);
    std::printf("  passes %u, rays %llu, nodes %zu, leaves %zu, subdivisions %llu\n",
                r.stats.passes_completed, (unsigned long long)r.stats.rays, r.stats.nodes,
                r.stats.leaves, (unsigned long long)r.stats.subdivisions);
    std::printf("  %10s %12s %12s %14s\n", "t_s", "est_rel_err", "ref_rel_err", "rays");
    std::string series;
    double next_print = 0.0;
    for (const ErrorPoint& p : r.series) {
      if (p.t_s >= next_print || &p == &r.series.back()) {
        std::printf("  %10.3f %12.4f %12.4f %14llu\n", p.t_s, p.est_rel_error, p.ref_rel_error,
                    (unsigned long long)p.rays);
        next_print = std::max(next_print * 2.0, 0.05);
      }
      char item[160];
      std::snprintf(item, sizeof item,
                    "%s{\"t_s\": %.4f, \"est_rel_error\": %.6f, \"ref_rel_error\": %.6f}",
                    series.empty() ? "" : ", ", p.t_s, p.est_rel_error, p.ref_rel_error);
      series += item;
    }
    char head[512];
    std::snprintf(head, sizeof head,
                  "  {\"level\": \"%s\", \"triangles\": %zu, \"shooter_rays_per_s\": %.1f, "
                  "\"raw_rays_per_s\": %.1f, "
                  "\"ratio\": %.4f, \"series\": [",
                  r.name.c_str(), r.triangles, r.shooter_rays_per_s, r.raw_rays_per_s,
                  r.shooter_rays_per_s / r.raw_rays_per_s);
    json += head + series + "]}" + (l + 1 < levels.size() ? ",\n" : "\n");
  }
  json += "]\n";
  std::ofstream(json_path) << json;
  std::printf("\nwrote %s\n", json_path.c_str());
  return 0;
}

// Cross-check (docs/architecture/runtime-indexmaps.md "Cross-check"): the per-receiver
// flux an index map gives a point sample must match Embree rays shot from
// the same sample with the same lobe, on the Cornell box and, when ../shared/scenes is there,
// Sponza.
//
// Receivers: a deterministic partition of the static triangles by instance x
// coarse spatial cell x dominant normal axis (each side its own receiver on
// double-sided materials), a few hundred groups, like the bake's patches.
//
// Tolerance: 2% relative on every receiver getting >= 1% of the flux. The
// rays are 2^20 on a jittered grid: a 1% receiver covers ~10^4 strata, only
// the ~4 sqrt(10^4) on its outline vary (each by <= 1/2 a ray), so the
// rays' error is ~0.1%. The map at 512^2 per face errs on texel edges: a 1%
// region is ~80 texels across, +-1/4 texel per row on its outline averages
// to well under 1%. The small-polygon fallback (vertex visibility) and float
// texel weights add less. The worst difference is printed for the record.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>

#include "index_map_test_util.h"
#include "runtime/gl_test_context.h"
#include "shared_scene.h"
#include "svit/level.h"

namespace svit::test {
namespace {

using gl::Lobe;
using gl::PointSample;

struct Level {
  baker::BakeGeometry geometry;
  gl::MapTriangles map;
  uint32_t receivers = 0;
  std::unique_ptr<baker::RayCaster> caster;
};

// Receiver of each side of each triangle: groups keyed by (instance, cell of
// the centroid on a cells^3 grid over the bounds, dominant normal axis and
// sign, side), numbered in triangle order (deterministic).
void partition(Level& level, int cells) {
  const baker::BakeGeometry& g = level.geometry;
  std::map<std::tuple<uint32_t, int, int, int, int, int>, uint32_t> ids;
  auto id = [&](const std::tuple<uint32_t, int, int, int, int, int>& key) {
    auto [it, added] = ids.emplace(key, uint32_t(ids.size()));
    return it->second;
  };
  const glm::dvec3 lo = dvec(g.bounds.min), extent = dvec(g.bounds.max) - lo;
  level.map.positions = g.positions;
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    const glm::dvec3 c = (dvec(g.corner(t, 0)) + dvec(g.corner(t, 1)) + dvec(g.corner(t, 2))) / 3.0;
    int cell[3];
    for (int k = 0; k < 3; ++k) {
      cell[k] = std::clamp(int((c[k] - lo[k]) / std::max(extent[k], 1e-9) * cells), 0, cells - 1);
    }
    const glm::dvec3 n = dvec(g.normals[t]);
    int axis = 0;
    for (int k = 1; k < 3; ++k) {
      if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
    }
    const int dominant = 2 * axis + (n[axis] < 0 ? 1 : 0);
    level.map.front_receiver.push_back(id({g.instance[t], cell[0], cell[1], cell[2], dominant, 0}));
    level.map.back_receiver.push_back(
        g.double_sided[t] ? id({g.instance[t], cell[0], cell[1], cell[2], dominant, 1})
                          : gl::kNoReceiver);
  }
  level.receivers = uint32_t(ids.size());
}

Level loadFlattened(const std::string& path, int cells) {
  Level level;
  LoadOptions options;
  options.load_textures = false;  // geometry only
  Expected<Scene> scene = loadLevel(path, options);
  EXPECT_TRUE(scene.ok()) << scene.status().message();
  if (!scene.ok()) return level;
  Expected<baker::BakeGeometry> geometry = baker::flattenStaticGeometry(*scene);
  EXPECT_TRUE(geometry.ok()) << geometry.status().message();
  if (!geometry.ok()) return level;
  level.geometry = std::move(geometry).value();
  partition(level, cells);
  Expected<std::unique_ptr<baker::RayCaster>> caster = baker::makeEmbreeCaster(level.geometry);
  EXPECT_TRUE(caster.ok()) << caster.status().message();
  if (caster.ok()) level.caster = std::move(caster).value();
  return level;
}

// A cosine sample on the surface a ray from `from` along `dir` hits, lifted
// 5e-4 x the scene diagonal off it (the near plane is 1e-4 x).
PointSample surfaceSample(const Level& level, glm::dvec3 from, glm::dvec3 dir) {
  baker::Ray ray;
  ray.origin = vec(from);
  ray.direction = vec(dir);
  baker::RayHit hit;
  level.caster->intersect({&ray, 1}, {&hit, 1});
  PointSample s;
  EXPECT_TRUE(hit.hit());
  if (!hit.hit()) return s;
  glm::dvec3 n = dvec(level.geometry.normals[hit.triangle]);
  if (!hit.front) n = -n;
  s.lobe = Lobe::kCosine;
  s.axis = vec(n);
  s.position = vec(from + dir * double(hit.t) + n * (5e-4 * diagonal(level.geometry.bounds)));
  s.own_triangle = hit.triangle;
  return s;
}

PointSample pointSample(Lobe lobe, glm::dvec3 p, glm::dvec3 axis) {
  PointSample s;
  s.lobe = lobe;
  s.position = vec(p);
  s.axis = vec(glm::normalize(axis));
  return s;
}

// Renders every sample at `resolution`, shoots 2^20 rays from each, and
// checks the receivers with >= 1% of the flux; returns the worst difference.
double crossCheck(Level& level, std::vector<PointSample> samples, const char* name,
                  int resolution) {
  gl::IndexMapSettings settings;
  settings.resolution = resolution;
  settings.max_batch_samples = 4;
  Expected<std::unique_ptr<gl::IndexMapRenderer>> created = gl::IndexMapRenderer::create(settings);
  EXPECT_TRUE(created.ok()) << created.status().message();
  if (!created.ok()) return 1;
  gl::IndexMapRenderer& renderer = **created;
  renderer.setStaticTriangles(level.map);
  renderer.setReceiverCount(level.receivers);
  for (size_t i = 0; i < samples.size(); ++i) {
    samples[i].slot = uint32_t(i);
    samples[i].roll_rad = 0.37f + 1.3f * float(i);  // off the scene's axes
  }
  std::vector<float> shares;
  gl::GatherStats stats;
  const Status status = renderer.gather(samples, uint32_t(samples.size()), shares, &stats);
  EXPECT_TRUE(status.ok()) << status.message();
  if (!status.ok()) return 1;
  std::printf(
      "%s: %zu triangles, %u receivers, %zu samples at %d^2: %u faces, render %.0f ms, reduce %.0f "
      "ms "
      "(fallback %u), readback %.1f ms\n",
      name, level.map.triangleCount(), level.receivers, samples.size(), resolution,
      stats.faces_rendered, stats.render_ms, stats.reduce_ms, stats.fallback_triangles,
      stats.readback_ms);
  const double diag = diagonal(level.geometry.bounds);
  double worst = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<double> rays =
        rayShares(*level.caster, level.map, samples[i], level.receivers, 1024,
                  nearPlane(samples[i], diag), 1000 + i);
    const double ray_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    double sample_worst = 0, map_total = 0, ray_total = 0;
    uint32_t worst_receiver = 0, checked = 0;
    for (uint32_t r = 0; r < level.receivers; ++r) {
      const double map = shares[i * level.receivers + r];
      map_total += map;
      ray_total += rays[r];
      if (rays[r] < 0.01) continue;
      ++checked;
      const double rel = std::abs(map - rays[r]) / rays[r];
      EXPECT_LE(rel, 0.02) << name << " sample " << i << " receiver " << r << ": map " << map
                           << " rays " << rays[r];
      if (rel > sample_worst) {
        sample_worst = rel;
        worst_receiver = r;
      }
    }
    std::printf(
        "  sample %zu (lobe %u, layout %u): %u receivers >= 1%%, worst %.2f%% (receiver %u: map "
        "%.5f rays "
        "%.5f); totals map %.4f rays %.4f; 2^20 rays %.0f ms\n",
        i, unsigned(samples[i].lobe), unsigned(renderer.chooseLayout(samples[i])), checked,
        100 * sample_worst, worst_receiver, shares[i * level.receivers + worst_receiver],
        rays[worst_receiver], map_total, ray_total, ray_ms);
    EXPECT_NEAR(map_total, ray_total, 0.01 * ray_total + 1e-4) << name << " sample " << i;
    worst = std::max(worst, sample_worst);
  }
  std::printf("%s: worst relative difference %.2f%%\n", name, 100 * worst);
  return worst;
}

TEST(IndexMapCrossCheck, CornellBoxAgainstEmbree) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  Level level = loadFlattened(SVIT_CORNELL_GLTF, 4);
  ASSERT_TRUE(level.caster);
  const glm::dvec3 lo = dvec(level.geometry.bounds.min), hi = dvec(level.geometry.bounds.max);
  const glm::dvec3 c = 0.5 * (lo + hi), e = hi - lo;
  std::vector<PointSample> samples;
  // floor
  samples.push_back(surfaceSample(level, c + glm::dvec3(0.1, 0, 0.3) * e, {0, -1, 0}));
  // left wall
  samples.push_back(surfaceSample(level, c + glm::dvec3(0, 0.1, 0.05) * e, {-1, 0.05, 0.1}));
  samples.push_back(pointSample(Lobe::kIsotropic, c + glm::dvec3(0.05, 0.15, 0.1) * e, {0, 1, 0}));
  PointSample spot =
      pointSample(Lobe::kSpot, c + glm::dvec3(-0.1, 0.45, 0.05) * e, {0.15, -1, 0.1});
  spot.cos_inner = float(std::cos(25 * kTestPi / 180));
  spot.cos_outer = float(std::cos(40 * kTestPi / 180));
  samples.push_back(spot);
  // A wide spot (60 degrees) takes the triple layout.
  PointSample wide = pointSample(Lobe::kSpot, c + glm::dvec3(0.15, 0.3, -0.1) * e, {-0.3, -1, 0.2});
  wide.cos_inner = float(std::cos(30 * kTestPi / 180));
  wide.cos_outer = float(std::cos(60 * kTestPi / 180));
  samples.push_back(wide);
  crossCheck(level, samples, "Cornell box", 512);
}

TEST(IndexMapCrossCheck, SponzaAgainstEmbree) {
  GlTestContext ctx;
  SVIT_REQUIRE_GL(ctx);
  SVIT_SKIP_WITHOUT_SHARED_SCENE("sponza/Sponza.gltf");
  Level level = loadFlattened(sharedScenePath("sponza/Sponza.gltf"), 6);
  ASSERT_TRUE(level.caster);
  const glm::dvec3 lo = dvec(level.geometry.bounds.min), hi = dvec(level.geometry.bounds.max);
  const glm::dvec3 c = 0.5 * (lo + hi), e = hi - lo;
  std::printf("Sponza bounds (%.1f %.1f %.1f) - (%.1f %.1f %.1f)\n", lo.x, lo.y, lo.z, hi.x, hi.y,
              hi.z);
  std::vector<PointSample> samples;
  const glm::dvec3 atrium = glm::dvec3(c.x, lo.y + 0.25 * e.y, c.z);
  samples.push_back(pointSample(Lobe::kIsotropic, atrium, {0, 1, 0}));
  // floor
  samples.push_back(
      surfaceSample(level, atrium + glm::dvec3(0.1 * e.x, 0, 0.02 * e.z), {0, -1, 0}));
  // Under the arcade: 2/3 of the way from the atrium's axis to the first
  // surface across it, 2.5 m above the floor.
  const PointSample floor = samples.back();
  const glm::dvec3 low = dvec(floor.position) + glm::dvec3(-0.15 * e.x, 2.5, 0);
  baker::Ray across;
  across.origin = vec(low);
  across.direction = {0, 0, 1};
  baker::RayHit wall;
  level.caster->intersect({&across, 1}, {&wall, 1});
  ASSERT_TRUE(wall.hit());
  samples.push_back(
      pointSample(Lobe::kIsotropic, low + glm::dvec3(0, 0, 0.67 * wall.t), {0, 1, 0}));
  PointSample sun = pointSample(Lobe::kParallel, {}, {0.25, -1, 0.15});
  const double radius = 0.5 * diagonal(level.geometry.bounds);
  sun.position = vec(c - dvec(sun.axis) * radius * 1.01);
  sun.half_extent_m = float(radius);
  samples.push_back(sun);
  crossCheck(level, samples, "Sponza", 512);
}

}  // namespace
}  // namespace svit::test

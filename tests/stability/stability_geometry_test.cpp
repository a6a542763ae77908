// Extreme geometry: ray origins at every scale, sliver triangles of aspect
// 1e5, one triangle covering a million lightmap texels, coincident coplanar
// surfaces, and 100,000 tiny emitters. Each case checks finite output,
// energy, and a bound measured here and stated beside it.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "stability_util.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/texel_lighting.h"
#include "util/random.h"

namespace svit::baker {
namespace {

using test::kPi;
using test::reportFigure;
using test::SceneBuilder;
using test::Solved;

// Sum over triangle sides of (1 - albedo) * E * A (absorbed flux, lm).
double absorbedFlux(const RadiositySolver& solver, const BakeGeometry& g) {
  double absorbed = 0;
  for (bool front : {true, false}) {
    const std::vector<Rgb> e = solver.triangleIrradiance(front);
    for (size_t t = 0; t < g.triangleCount(); ++t) {
      if (!front && !g.double_sided[t]) continue;
      const Rgb& a = g.albedo[t];
      absorbed += double(luminance({(1 - a.r) * e[t].r, (1 - a.g) * e[t].g, (1 - a.b) * e[t].b})) *
                  g.areas_m2[t];
    }
  }
  return absorbed;
}

double emittedFlux(const Scene& scene, const BakeGeometry& g) {
  double emitted = 0;
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    emitted +=
        kPi * double(luminance(g.emission[t])) * g.areas_m2[t] * (g.double_sided[t] ? 2.0 : 1.0);
  }
  for (const Light& light : scene.lights)
    emitted += 4.0 * kPi * double(light.intensity) * double(luminance(light.color));
  return emitted;
}

// ---------------------------------------------------------------------------
// Ray origins: the offset of baker/src/rays/ray_offset.cpp never self-intersects.

void addTriangle(BakeGeometry& g, const Vec3& a, const Vec3& b, const Vec3& c) {
  g.positions.insert(g.positions.end(), {a, b, c});
  const glm::dvec3 pa(a.x, a.y, a.z), pb(b.x, b.y, b.z), pc(c.x, c.y, c.z);
  const glm::dvec3 cross = glm::cross(pb - pa, pc - pa);
  const double length = glm::length(cross);
  g.normals.push_back({float(cross.x / length), float(cross.y / length), float(cross.z / length)});
  g.areas_m2.push_back(float(0.5 * length));
  g.albedo.push_back({0.5f, 0.5f, 0.5f});
  g.emission.push_back({0, 0, 0});
  g.double_sided.push_back(0);
  g.instance.push_back(0);
  g.mesh_triangle.push_back(uint32_t(g.mesh_triangle.size()));
}

// Origins on triangle 0 of `g` (float-arithmetic barycentric points, as a
// hit point would be), moved by `offset`, rays uniform over the front
// hemisphere (grazing ones included); returns how many hit anything (every
// hit is a self-intersection: nothing lies in front of triangle 0's plane).
template <typename Offset>
int selfHits(const BakeGeometry& g, const Offset& offset, uint64_t seed, int rays) {
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(g);
  EXPECT_TRUE(caster.ok());
  if (!caster.ok()) return -1;
  const glm::dvec3 n(g.normals[0].x, g.normals[0].y, g.normals[0].z);
  const glm::dvec3 t1 = glm::normalize(
      glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 t2 = glm::cross(n, t1);
  Rng rng(hashIds(seed, 0x5e1f));
  std::vector<Ray> batch(static_cast<size_t>(rays));
  for (Ray& ray : batch) {
    float u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0f) {
      u = 1.0f - u;
      v = 1.0f - v;
    }
    const float w = 1.0f - u - v;
    const Vec3 &a = g.corner(0, 0), &b = g.corner(0, 1), &c = g.corner(0, 2);
    const Vec3 p{a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v,
                 a.z * w + b.z * u + c.z * v};
    const double cos_theta = 1.0 - rng.uniformDouble();  // (0, 1]
    const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta),
                 phi = 2.0 * kPi * rng.uniformDouble();
    const glm::dvec3 d =
        sin_theta * std::cos(phi) * t1 + sin_theta * std::sin(phi) * t2 + cos_theta * n;
    ray.origin = offset(p, g.normals[0], cornerMagnitude(g, 0));
    ray.direction = {float(d.x), float(d.y), float(d.z)};
  }
  std::vector<RayHit> hits(batch.size());
  caster.value()->intersect(batch, hits);
  int count = 0;
  for (const RayHit& h : hits) count += h.hit() ? 1 : 0;
  return count;
}

TEST(Offsets, NoSelfIntersectionAtAnyScaleOrDistance) {
  test::StabilityTimer timer;
  // A tilted plane (no coordinate exactly representable).
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.81));
  const glm::dvec3 t1 = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1))), t2 = glm::cross(n, t1);
  auto at = [&](const glm::dvec3& centre, double a, double b) {
    const glm::dvec3 p = centre + a * t1 + b * t2;
    return Vec3{float(p.x), float(p.y), float(p.z)};
  };
  // Offsets of 2 ULPs (1/8 of what offsetRayOrigin uses), for the margin.
  auto two_ulps = [](const Vec3& p, const Vec3& normal, float magnitude) {
    const float m = std::max({magnitude, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    const float step = 2.0f * std::ldexp(1.0f, std::ilogb(m) - 23);
    return Vec3{p.x + normal.x * step, p.y + normal.y * step, p.z + normal.z * step};
  };
  auto real = [](const Vec3& p, const Vec3& normal, float magnitude) {
    return offsetRayOrigin(p, normal, magnitude);
  };
  constexpr int kRays = 32768;
  int cases = 0, hits_real = 0, hits_two = 0;
  uint64_t seed = 1;
  // Squares of half-size h at distance d from the origin (d = 0: through it).
  for (double d : {0.0, 1e-3, 1.0, 1e4, 1e5}) {
    for (double h : {1e-3, 1.0, 1e4}) {
      if (d > 0 && h > d) continue;
      const glm::dvec3 centre = d * glm::normalize(glm::dvec3(0.48, 0.6, 0.64));
      const double s = d > 0 ? 0.25 * h : h;
      BakeGeometry g;
      addTriangle(g, at(centre, -s, -s), at(centre, s, -s), at(centre, s, s));
      addTriangle(g, at(centre, -s, -s), at(centre, s, s), at(centre, -s, s));
      hits_real += selfHits(g, real, ++seed, kRays);
      hits_two += selfHits(g, two_ulps, seed, kRays);
      ++cases;
    }
  }
  // A 1 mm triangle at the origin between coplanar neighbours up to 1e5 m.
  for (double big : {1.0, 1e3, 1e5}) {
    BakeGeometry g;
    const Vec3 o = at({0, 0, 0}, 1e-4, 1e-4), a = at({0, 0, 0}, 1e-3, 0),
               b = at({0, 0, 0}, 0, 1e-3);
    addTriangle(g, o, a, b);
    addTriangle(g, o, b, at({0, 0, 0}, -big, 0.3 * big));
    addTriangle(g, a, o, at({0, 0, 0}, 0.3 * big, -big));
    addTriangle(g, b, a, at({0, 0, 0}, big, big));
    hits_real += selfHits(g, real, ++seed, kRays);
    hits_two += selfHits(g, two_ulps, seed, kRays);
    ++cases;
  }
  reportFigure("rays checked", double(cases) * kRays);
  reportFigure("self-intersections at 16 ULPs (offsetRayOrigin)", hits_real);
  reportFigure("self-intersections at 2 ULPs (for the margin)", hits_two);
  EXPECT_EQ(hits_real, 0);
}

// ---------------------------------------------------------------------------
// Slivers of aspect 1e5.

TEST(Slivers, AspectRatio1e5InTheFloorAndStandingFree) {
  test::StabilityTimer timer;
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int blade = b.material({0.7f, 0.7f, 0.7f}, {0, 0, 0}, true);
  // Room 4 x 3 x 5 m; its floor is a fan around the corner (0, 0, 0) whose
  // two middle triangles are slivers: 4 m long, 4e-5 m wide (aspect 1e5).
  b.addQuad("ceiling", {0, 3, 0}, {4, 3, 0}, {4, 3, 5}, {0, 3, 5}, grey);
  b.addQuad("wall -x", {0, 0, 0}, {0, 3, 0}, {0, 3, 5}, {0, 0, 5}, grey);
  b.addQuad("wall +x", {4, 0, 0}, {4, 0, 5}, {4, 3, 5}, {4, 3, 0}, grey);
  b.addQuad("wall -z", {0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, grey);
  b.addQuad("wall +z", {0, 0, 5}, {0, 3, 5}, {4, 3, 5}, {4, 0, 5}, grey);
  const float w = 4e-5f;
  b.addMesh("floor",
            {{0, 0, 0},
             {0, 0, 5},
             {4, 0, 5},  // big
             {0, 0, 0},
             {4, 0, 5},
             {4, 0, 5 - w},  // sliver
             {0, 0, 0},
             {4, 0, 5 - w},
             {4, 0, 5 - 2 * w},  // sliver
             {0, 0, 0},
             {4, 0, 5 - 2 * w},
             {4, 0, 0}},  // big
            grey);
  // A free-standing double-sided blade 1 m tall and 1e-5 m wide.
  b.addMesh("blade", {{2, 0.5f, 2}, {2, 1.5f, 2}, {2 + 1e-5f, 1.0f, 2}}, blade);
  b.addPointLight({2, 2.5f, 2.5f}, 100.0f);
  const Scene& scene = b.scene();
  RadiositySettings settings;
  settings.first_pass_rays = 1u << 15;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  StopRule stop;
  stop.max_passes = 3;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const RadiositySolver& solver = *solved->solver;
  const BakeGeometry& g = solved->geometry;
  ASSERT_EQ(g.triangleCount(), 10u + 4u + 1u);  // nothing skipped as degenerate
  for (bool front : {true, false}) {
    for (const Rgb& e : solver.triangleIrradiance(front)) ASSERT_TRUE(test::finiteNonNegative(e));
  }
  Rng rng(hashIds(3, 3));
  for (uint32_t t = 0; t < g.triangleCount(); ++t) {
    for (int i = 0; i < 32; ++i) {
      double u = rng.uniformDouble(), v = rng.uniformDouble();
      if (u + v > 1) u = 1 - u, v = 1 - v;
      for (InterpolationMode mode :
           {InterpolationMode::kVertex, InterpolationMode::kElementCentre}) {
        ASSERT_TRUE(test::finiteNonNegative(solver.irradianceAt(t, true, u, v, mode)))
            << "triangle " << t;
      }
    }
  }
  // Energy: a closed room conserves flux (ambient closes the balance).
  const double balance = absorbedFlux(solver, g) / emittedFlux(scene, g) - 1.0;
  // Accuracy is the lightmap's job (below): a sliver of 8e-5 m2 expects
  // ~1 of the ~0.5M rays, so its own mean is 0, 1 or 2 hits' worth (one hit
  // is ~34 lx over the pair, against ~25 lx true) plus ambient: unbiased but
  // coarse, reported, not bounded. Vertex interpolation weights it by area,
  // so it does not disturb its neighbours.
  const std::vector<Rgb> e = solver.triangleIrradiance(true);
  const Light& lamp = scene.lights[0];
  auto direct = [&](const glm::dvec3& p) {
    const glm::dvec3 to(lamp.position.x - p.x, lamp.position.y - p.y, lamp.position.z - p.z);
    const double d2 = glm::dot(to, to);
    return double(lamp.intensity) * to.y / std::sqrt(d2) / d2;  // floor normal +y
  };
  const size_t floor_first = 10;  // 5 quads before the floor
  reportFigure("absorbed / emitted flux - 1", balance);
  reportFigure("big floor triangles' mean irradiance, lx",
               0.5 * (luminance(e[floor_first]) + luminance(e[floor_first + 3])));
  reportFigure("sliver 1 mean irradiance, lx", luminance(e[floor_first + 1]));
  reportFigure("sliver 2 mean irradiance, lx", luminance(e[floor_first + 2]));
  reportFigure("blade (1e-5 m wide) mean irradiance, lx", luminance(e[floor_first + 4]));
  EXPECT_LT(std::abs(balance), 0.01);

  // Lightmap: xatlas, exact rasterization and texel lighting over slivers.
  AtlasSettings atlas_settings;
  atlas_settings.texels_per_m = 8;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, g, atlas_settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  Expected<TexelSet> texels = rasterizeTexels(g, *atlas, *solved->caster, RasterSettings{});
  ASSERT_TRUE(texels.ok()) << texels.status().message();
  TexelLightingSettings lighting;
  lighting.gather_rays = 16;
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexels(scene, g, *solved->caster, solver, *texels, lighting);
  ASSERT_TRUE(lit.ok()) << lit.status().message();
  size_t floor_texels = 0, sliver_texels = 0;
  double worst_direct = 0;
  for (size_t i = 0; i < texels->samples.size(); ++i) {
    const TexelSample& s = texels->samples[i];
    ASSERT_TRUE(test::finiteNonNegative((*lit)[i].direct) &&
                test::finiteNonNegative((*lit)[i].indirect));
    if (s.triangle < floor_first || s.triangle > floor_first + 3) continue;
    ++floor_texels;
    if (s.triangle == floor_first + 1 || s.triangle == floor_first + 2) ++sliver_texels;
    // Nothing stands between the floor and the lamp but the 1e-5 m blade:
    // the direct light is exact (E = I cos / d^2) wherever it does not shadow.
    const glm::dvec3 p(s.position.x, s.position.y, s.position.z);
    const double exact = direct(p);
    const double got = luminance((*lit)[i].direct);
    if (got > 0) worst_direct = std::max(worst_direct, std::abs(got / exact - 1.0));
  }
  reportFigure("floor texels", double(floor_texels));
  reportFigure("texels won by a sliver", double(sliver_texels));
  reportFigure("floor texels: direct light vs I cos / d^2, max rel. difference", worst_direct);
  EXPECT_GT(floor_texels, 1000u);
  // Float positions and intensities: a few 1e-7.
  EXPECT_LT(worst_direct, 1e-5);
}

// ---------------------------------------------------------------------------
// One triangle covering a million texels.

TEST(HugeTriangle, OneTriangleCoversAMillionTexels) {
  test::StabilityTimer timer;
  // A tilted right triangle with legs (0, 6, 8) and (8, -3.6, 2.7) (45.9
  // m2, normal (45, 64, -48) / 91.8) under a 100 cd lamp 4 m off its
  // centroid; xatlas at 151 texels/m gives it ~1.05 million texels.
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addMesh("slab", {{0, 0, 0}, {0, 6, 8}, {8, -3.6f, 2.7f}}, grey);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(45, 64, -48));
  const glm::dvec3 lamp_at = glm::dvec3(8.0 / 3, 2.4 / 3, 10.7 / 3) + 4.0 * normal;
  b.addPointLight({float(lamp_at.x), float(lamp_at.y), float(lamp_at.z)}, 100.0f);
  const Scene& scene = b.scene();
  RadiositySettings settings;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  StopRule stop;
  stop.max_passes = 2;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const BakeGeometry& g = solved->geometry;
  AtlasSettings atlas_settings;
  atlas_settings.texels_per_m = 151;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, g, atlas_settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  Expected<TexelSet> texels = rasterizeTexels(g, *atlas, *solved->caster, RasterSettings{});
  ASSERT_TRUE(texels.ok()) << texels.status().message();
  TexelLightingSettings lighting;
  lighting.gather_rays = 1;  // nothing to gather from; one ray checks the path
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexels(scene, g, *solved->caster, *solved->solver, *texels, lighting);
  ASSERT_TRUE(lit.ok()) << lit.status().message();

  // Coverage sums to the triangle's area in texels (exact clipping).
  const Vec2* uv = &atlas->triangle_uv[0];
  const double uv_area = 0.5 *
                         std::abs(double(uv[1].x - uv[0].x) * (uv[2].y - uv[0].y) -
                                  double(uv[2].x - uv[0].x) * (uv[1].y - uv[0].y)) *
                         atlas->page_width * atlas->page_height;
  double coverage = 0, worst_direct = 0, worst_plane_m = 0, indirect = 0;
  const Light& lamp = scene.lights[0];
  for (size_t i = 0; i < texels->samples.size(); ++i) {
    const TexelSample& s = texels->samples[i];
    coverage += s.coverage;
    const TexelIrradiance& e = (*lit)[i];
    ASSERT_TRUE(test::finiteNonNegative(e.direct) && test::finiteNonNegative(e.indirect))
        << "texel " << i;
    const glm::dvec3 p(s.position.x, s.position.y, s.position.z);
    worst_plane_m = std::max(worst_plane_m, std::abs(glm::dot(p, normal)));
    // Inside: barycentrics along the orthogonal legs within [0, 1].
    const double u = glm::dot(p, glm::dvec3(0, 6, 8)) / 100.0,
                 v = glm::dot(p, glm::dvec3(8, -3.6, 2.7)) / 84.25;
    ASSERT_TRUE(u >= -1e-6 && v >= -1e-6 && u + v <= 1.0 + 1e-6)
        << "texel " << i << ": " << u << ", " << v;
    const glm::dvec3 to(lamp.position.x - p.x, lamp.position.y - p.y, lamp.position.z - p.z);
    const double d2 = glm::dot(to, to);
    const double exact = double(lamp.intensity) * glm::dot(to, normal) / std::sqrt(d2) / d2;
    worst_direct = std::max(worst_direct, std::abs(double(luminance(e.direct)) / exact - 1.0));
    indirect = std::max(indirect, double(luminance(e.indirect)));
  }
  reportFigure("texels", double(texels->samples.size()));
  reportFigure("page size", double(atlas->page_width));
  reportFigure("coverage sum / UV area - 1", coverage / uv_area - 1.0);
  reportFigure("sample points off the plane, max m", worst_plane_m);
  reportFigure("direct light vs I cos / d^2, max rel. difference", worst_direct);
  reportFigure("indirect light, max lx (nothing reflects)", indirect);
  EXPECT_GT(texels->samples.size(), 1000000u);
  // Float coverage sums over a million texels: 1e-6 relative.
  EXPECT_NEAR(coverage / uv_area, 1.0, 1e-4);
  // Float sample points of coordinates up to 10 m: within a few ULPs (1e-6 m).
  EXPECT_LT(worst_plane_m, 1e-5);
  EXPECT_LT(worst_direct, 1e-5);
  EXPECT_EQ(indirect, 0.0);
}

// ---------------------------------------------------------------------------
// Coincident coplanar surfaces.

// Lights `scene` with the solver (2^14 rays, 3 passes) and returns it.
std::unique_ptr<Solved> solveScene(const Scene& scene, uint32_t first_pass_rays = 1u << 14,
                                   uint32_t passes = 3) {
  RadiositySettings settings;
  settings.first_pass_rays = first_pass_rays;
  auto solved = test::prepareSolver(scene, settings);
  if (!solved->solver) return solved;
  StopRule stop;
  stop.max_passes = passes;
  EXPECT_TRUE(solved->solver->improve(stop).ok());
  return solved;
}

TEST(Coincident, ZeroThicknessWallBetweenTwoRooms) {
  test::StabilityTimer timer;
  // Rooms A [0,4] and B [4,8] x [0,3] x [0,5], each closed, so the wall at
  // x = 4 is two coincident quads facing away from each other. A holds a
  // 100 cd lamp and a 1 m2 panel of 50 cd/m2; B is dark. On A's floor lies
  // a rug coplanar with it, facing the same way (albedo 0.2 over 0.6).
  SceneBuilder b;
  const int grey = b.material({0.6f, 0.6f, 0.6f});
  const int rug = b.material({0.2f, 0.2f, 0.2f});
  const int lamp = b.material({0, 0, 0}, {50, 50, 50});
  b.addRoom("A", {0, 0, 0}, {4, 3, 5}, grey);
  b.addRoom("B", {4, 0, 0}, {8, 3, 5}, grey);
  b.addQuad("rug", {1, 0, 1}, {1, 0, 3}, {3, 0, 3}, {3, 0, 1}, rug);
  b.addQuad("panel", {1.5f, 2.99f, 2}, {2.5f, 2.99f, 2}, {2.5f, 2.99f, 3}, {1.5f, 2.99f, 3}, lamp);
  b.addPointLight({3.5f, 2.0f, 4.0f}, 100.0f);
  const Scene& scene = b.scene();
  auto solved = solveScene(scene);
  ASSERT_TRUE(solved->solver);
  const RadiositySolver& solver = *solved->solver;
  const BakeGeometry& g = solved->geometry;
  const std::vector<Rgb> e = solver.triangleIrradiance(true);
  // Instances: A's 6 quads, B's 6 quads, the rug, the panel.
  double flux_a = 0, flux_b = 0, shared_a = 0, far_a = 0, b_min = 1e300, b_max_solver = 0;
  for (size_t t = 0; t < g.triangleCount(); ++t) {
    ASSERT_TRUE(test::finiteNonNegative(e[t]));
    const double f = double(luminance(e[t])) * g.areas_m2[t];
    (g.instance[t] >= 6 && g.instance[t] < 12 ? flux_b : flux_a) += f;
    if (g.instance[t] >= 6 && g.instance[t] < 12) {
      b_min = std::min(b_min, double(luminance(e[t])));
      b_max_solver = std::max(b_max_solver, double(luminance(e[t])));
    }
    if (g.instance[t] == 3) shared_a += f / 15.0;  // A's +x wall (the shared one), 15 m2
    if (g.instance[t] == 2) far_a += f / 15.0;     // A's -x wall
  }
  const double emitted = emittedFlux(scene, g);
  const double balance = absorbedFlux(solver, g) / emitted - 1.0;
  reportFigure("flux reaching room B / flux reaching room A", flux_b / flux_a);
  reportFigure("absorbed / emitted flux - 1", balance);
  reportFigure("rays absorbed by back faces", double(solver.stats().back_absorbed));
  reportFigure("A's shared wall / A's opposite wall, mean irradiance", shared_a / far_a);
  // No ray crosses the wall: every ray leaving A starts on A's side of it
  // (origins move off their surface into A) and Embree's watertight robust
  // mode lets nothing through the quads' shared diagonal. What B holds is
  // the ambient term alone (thesis 5.5: unshot flux spread over every
  // surface, connected or not), the same on every triangle, and as small
  // as the last pass's remainder: pass_end_rays / (4 N) of the flux.
  EXPECT_EQ(b_min, b_max_solver);
  EXPECT_LT(flux_b / flux_a, 1e-3);
  // Hits at the shared wall land on A's quad (front) or on B's (its black
  // back, absorbed): whichever Embree reports first at equal distance.
  // Measured: Embree reports A's, so nothing is lost; 1% would allow
  // back hits on ~5% of the shared wall's share of A's light.
  EXPECT_LT(std::abs(balance), 0.01);

  // The lightmap of room B stays black, A's shared wall is lit.
  AtlasSettings atlas_settings;
  atlas_settings.texels_per_m = 6;
  Expected<LightmapAtlas> atlas = buildLightmapAtlas(scene, g, atlas_settings);
  ASSERT_TRUE(atlas.ok()) << atlas.status().message();
  Expected<TexelSet> texels = rasterizeTexels(g, *atlas, *solved->caster, RasterSettings{});
  ASSERT_TRUE(texels.ok()) << texels.status().message();
  TexelLightingSettings lighting;
  lighting.gather_rays = 16;
  lighting.area_light_samples = 4;
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexels(scene, g, *solved->caster, solver, *texels, lighting);
  ASSERT_TRUE(lit.ok()) << lit.status().message();
  double b_max = 0, b_sum = 0, a_sum = 0, shared_sum = 0;
  size_t a_count = 0, shared_count = 0, b_count = 0;
  for (size_t i = 0; i < texels->samples.size(); ++i) {
    const uint32_t instance = g.instance[texels->samples[i].triangle];
    const double value = luminance((*lit)[i].direct) + luminance((*lit)[i].indirect);
    ASSERT_TRUE(std::isfinite(value));
    if (instance >= 6 && instance < 12) {
      b_max = std::max(b_max, value);
      b_sum += value;
      ++b_count;
    } else {
      a_sum += value;
      ++a_count;
      if (instance == 3) {
        shared_sum += value;
        ++shared_count;
      }
    }
  }
  const double a_mean = a_sum / double(a_count);
  reportFigure("room B texels", double(b_count));
  reportFigure("room B brightest texel / room A mean texel", b_max / a_mean);
  reportFigure("room B mean texel / room A mean texel", b_sum / double(b_count) / a_mean);
  reportFigure("A's shared wall texels' mean / room A mean",
               (shared_sum / double(shared_count)) / a_mean);
  EXPECT_GT(b_count, 500u);
  EXPECT_GT(shared_count, 300u);
  // A KNOWN LEAK, measured, not fixed: B's texels gather from B's ceiling
  // and walls, and the solver interpolates those through vertex radiosities
  // that average every leaf around a welded vertex with a similar normal;
  // the rooms' ceilings, floors and end walls meet at x = 4 and share
  // their vertices there, so B's surfaces along the wall read A's light.
  // Direct light never leaks (shadow rays stop at the wall). Measured: the
  // brightest B texel (on B's side of the wall, by the ceiling) gets 25% of
  // A's mean, B's mean texel 1.1%; bounded at ~1.6x that to catch growth.
  EXPECT_LT(b_max / a_mean, 0.4);
  EXPECT_LT(b_sum / double(b_count) / a_mean, 0.02);
}

TEST(Coincident, ClosedBoxStandingOnTheFloorLeaksThroughItsBottom) {
  test::StabilityTimer timer;
  // A closed 1 m box whose bottom face lies on the floor, facing it: a
  // coincident pair facing each other. Flux the solver spreads over the
  // box (sparse hits deposited at the box's cluster) reaches the bottom,
  // whose rays start just below the floor and escape the closed room. This
  // is the one leak left: reported as the share of the flux that goes.
  for (float rho : {0.5f, 0.9f, 0.999f}) {
    SceneBuilder b;
    const int wall = b.material({rho, rho, rho});
    const int panel = b.material({0, 0, 0}, {20, 20, 20}, true);
    b.addRoom("room", {0, 0, 0}, {4, 3, 5}, wall);
    std::vector<Vec3> box;
    for (const Vec3& p : std::vector<Vec3>{// top
                                           {2.5f, 1, 1},
                                           {2.5f, 1, 2},
                                           {3.5f, 1, 2},
                                           {2.5f, 1, 1},
                                           {3.5f, 1, 2},
                                           {3.5f, 1, 1},
                                           // -x
                                           {2.5f, 0, 1},
                                           {2.5f, 0, 2},
                                           {2.5f, 1, 2},
                                           {2.5f, 0, 1},
                                           {2.5f, 1, 2},
                                           {2.5f, 1, 1},
                                           // +x
                                           {3.5f, 0, 1},
                                           {3.5f, 1, 1},
                                           {3.5f, 1, 2},
                                           {3.5f, 0, 1},
                                           {3.5f, 1, 2},
                                           {3.5f, 0, 2},
                                           // -z
                                           {2.5f, 0, 1},
                                           {2.5f, 1, 1},
                                           {3.5f, 1, 1},
                                           {2.5f, 0, 1},
                                           {3.5f, 1, 1},
                                           {3.5f, 0, 1},
                                           // +z
                                           {2.5f, 0, 2},
                                           {3.5f, 0, 2},
                                           {3.5f, 1, 2},
                                           {2.5f, 0, 2},
                                           {3.5f, 1, 2},
                                           {2.5f, 1, 2},
                                           // bottom
                                           {2.5f, 0, 1},
                                           {3.5f, 0, 1},
                                           {3.5f, 0, 2},
                                           {2.5f, 0, 1},
                                           {3.5f, 0, 2},
                                           {2.5f, 0, 2}}) {
      box.push_back(p);
    }
    b.addMesh("box", box, wall);
    b.addQuad("panel", {1.5f, 2.5f, 2}, {2.5f, 2.5f, 2}, {2.5f, 2.5f, 3}, {1.5f, 2.5f, 3}, panel);
    const Scene& scene = b.scene();
    // Stiffer rooms take ~1/(1 - rho) rays per emitted one: fewer of those.
    auto solved = rho > 0.99f ? solveScene(scene, 1024, 2) : solveScene(scene);
    ASSERT_TRUE(solved->solver);
    for (const Rgb& e : solved->solver->triangleIrradiance(true))
      ASSERT_TRUE(test::finiteNonNegative(e));
    const double balance =
        absorbedFlux(*solved->solver, solved->geometry) / emittedFlux(scene, solved->geometry) -
        1.0;
    char tag_text[32];
    std::snprintf(tag_text, sizeof tag_text, "albedo %g", double(rho));
    const std::string tag = tag_text;
    reportFigure(tag + ": absorbed / emitted flux - 1", balance);
    reportFigure(tag + ": captured fraction of surface rays",
                 solved->solver->stats().captured_fraction);
    // A KNOWN LEAK, measured, not fixed. The loss per bounce is ~1e-4 of
    // the reflected flux, amplified ~1/(1 - rho): measured -0.009% at
    // albedo 0.5, -0.14% at 0.9 (2^14 rays, 3 passes) and -19% at 0.999
    // (2^10 rays, 2 passes; -0.9% with 2^14 rays and 3 passes, since the
    // bottom gets flux only while hits are too sparse to stay on the sides).
    // Bounds at ~1.3x the measurement. Open-bottomed boxes, as game assets
    // usually are, do not leak (Stiff.ClosedRoomWithABoxOnTheFloor...).
    EXPECT_LT(std::abs(balance), rho < 0.7f ? 0.001 : rho < 0.99f ? 0.01 : 0.25) << tag;
  }
}

// ---------------------------------------------------------------------------
// 100,000 tiny emitters.

TEST(ManyEmitters, OneHundredThousandTinyEmittersInOneCeiling) {
  test::StabilityTimer timer;
  // A closed 4 x 3 x 5 m room (albedo 0.5); 1 cm below its ceiling, a grid
  // of 250 x 400 emissive right triangles with 4 mm legs (8e-6 m2 each,
  // 0.8 m2 in all), 1000 cd/m2 on both sides (black, double-sided, so the
  // light they take from the ceiling is counted as absorbed): 5027 lm, as
  // one mesh.
  constexpr int kNx = 250, kNz = 400;
  constexpr float kLeg = 0.004f, kLuminance = 1000.0f, kHeight = 2.99f;
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int led = b.material({0, 0, 0}, {kLuminance, kLuminance, kLuminance}, true);
  b.addRoom("room", {0, 0, 0}, {4, 3, 5}, grey);
  std::vector<Vec3> corners;
  corners.reserve(size_t(kNx) * kNz * 3);
  for (int i = 0; i < kNx; ++i) {
    for (int k = 0; k < kNz; ++k) {
      const float x = 0.5f + 0.012f * float(i), z = 0.5f + 0.01f * float(k);
      // Counter-clockwise seen from below: faces -y.
      corners.insert(corners.end(),
                     {{x, kHeight, z}, {x + kLeg, kHeight, z}, {x, kHeight, z + kLeg}});
    }
  }
  b.addMesh("leds", corners, led);
  const Scene& scene = b.scene();
  const auto build_start = std::chrono::steady_clock::now();
  RadiositySettings settings;
  settings.first_pass_rays = 1u << 14;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  StopRule stop;
  stop.max_passes = 3;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const RadiositySolver& solver = *solved->solver;
  const BakeGeometry& g = solved->geometry;
  ASSERT_EQ(g.triangleCount(), 12u + size_t(kNx) * kNz);
  for (bool front : {true, false}) {
    for (const Rgb& e : solver.triangleIrradiance(front)) ASSERT_TRUE(test::finiteNonNegative(e));
  }
  const double emitted = emittedFlux(scene, g);
  const double balance = absorbedFlux(solver, g) / emitted - 1.0;
  reportFigure("emitted flux, lm (exact 5026.55)", emitted);
  reportFigure("setup seconds (flatten, Embree, element tree)", build_s);
  reportFigure("absorbed / emitted flux - 1", balance);
  EXPECT_NEAR(emitted, 2.0 * kPi * kLuminance * 0.5 * kLeg * kLeg * kNx * kNz, 1e-3 * emitted);
  EXPECT_LT(std::abs(balance), 0.01);

  // Direct light picked among the 100,000 emitters by flux (16 shadow rays
  // per texel) at 1024 floor points, against the exact sum over all of them
  // (each a point source L A cos cos / d^2: 4 mm at 3 m is exact to 1e-6).
  TexelSet texels;
  texels.page_width = texels.page_height = 32;
  texels.page_count = 1;
  for (uint32_t y = 0; y < 32; ++y) {
    for (uint32_t x = 0; x < 32; ++x) {
      TexelSample s;
      s.x = x;
      s.y = y;
      s.position = {4.0f * (float(x) + 0.5f) / 32.0f, 0.0f, 5.0f * (float(y) + 0.5f) / 32.0f};
      // addRoom's floor: triangle 0 holds z >= 1.25 x, triangle 1 the rest.
      s.triangle = s.position.z >= 1.25f * s.position.x ? 0u : 1u;
      s.normal = {0, 1, 0};
      s.coverage = 1;
      texels.samples.push_back(s);
    }
  }
  TexelLightingSettings lighting;
  lighting.gather_rays = 0;
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexels(scene, g, *solved->caster, solver, texels, lighting);
  ASSERT_TRUE(lit.ok()) << lit.status().message();
  double sum_got = 0, sum_exact = 0, sq = 0;
  const size_t first_led = 12;
  for (size_t i = 0; i < texels.samples.size(); ++i) {
    const Vec3& p = texels.samples[i].position;
    double exact = 0;
    for (size_t t = first_led; t < g.triangleCount(); ++t) {
      const Vec3 &a = g.corner(t, 0), &bb = g.corner(t, 1), &c = g.corner(t, 2);
      const double cx = (a.x + bb.x + c.x) / 3.0 - p.x, cy = (a.y + bb.y + c.y) / 3.0 - p.y,
                   cz = (a.z + bb.z + c.z) / 3.0 - p.z;
      const double d2 = cx * cx + cy * cy + cz * cz;
      exact += double(kLuminance) * g.areas_m2[t] * cy * cy / (d2 * d2);
    }
    const double got = luminance((*lit)[i].direct);
    ASSERT_TRUE(std::isfinite(got));
    sum_got += got;
    sum_exact += exact;
    sq += (got / exact - 1.0) * (got / exact - 1.0);
  }
  const double mean_error = sum_got / sum_exact - 1.0,
               rms = std::sqrt(sq / double(texels.samples.size()));
  reportFigure("floor direct light, mean of 1024 points vs exact - 1", mean_error);
  reportFigure("floor direct light, per-point RMS rel. error (16 samples)", rms);
  // 16 picks among emitters of equal flux whose contribution to a point
  // varies ~3x over the ceiling leave ~11% noise per point (measured), so
  // the mean over 1024 points has ~0.35%: 1% is ~3 sigma. A bias (a lost or
  // doubled emitter, a bad CDF) would show as a mean error; 15% bounds the
  // per-point noise.
  EXPECT_LT(std::abs(mean_error), 0.01);
  EXPECT_LT(rms, 0.15);
}

TEST(ManyEmitters, OneHundredThousandPointLights) {
  test::StabilityTimer timer;
  // The same room lit by a 250 x 400 grid of 0.01 cd point lights 0.5 m
  // below the ceiling (0.126 lm each, 12,566 lm in all).
  constexpr int kNx = 250, kNz = 400;
  constexpr float kCandela = 0.01f, kHeight = 2.5f;
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addRoom("room", {0, 0, 0}, {4, 3, 5}, grey);
  for (int i = 0; i < kNx; ++i) {
    for (int k = 0; k < kNz; ++k)
      b.addPointLight({0.5f + 0.012f * float(i), kHeight, 0.5f + 0.01f * float(k)}, kCandela);
  }
  const Scene& scene = b.scene();
  RadiositySettings settings;
  settings.first_pass_rays = 1u << 14;
  auto solved = test::prepareSolver(scene, settings);
  ASSERT_TRUE(solved->solver);
  StopRule stop;
  stop.max_passes = 3;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const BakeGeometry& g = solved->geometry;
  for (const Rgb& e : solved->solver->triangleIrradiance(true))
    ASSERT_TRUE(test::finiteNonNegative(e));
  const double emitted = emittedFlux(scene, g);
  const double balance = absorbedFlux(*solved->solver, g) / emitted - 1.0;
  reportFigure("emitted flux, lm (exact 12566.4)", emitted);
  reportFigure("absorbed / emitted flux - 1", balance);
  EXPECT_LT(std::abs(balance), 0.01);

  // Texel lighting samples 16 of the 100,000 lights per texel by their
  // unshadowed irradiance: against the exact sum at 256 floor points.
  TexelSet texels;
  texels.page_width = texels.page_height = 16;
  texels.page_count = 1;
  for (uint32_t y = 0; y < 16; ++y) {
    for (uint32_t x = 0; x < 16; ++x) {
      TexelSample s;
      s.x = x;
      s.y = y;
      s.position = {4.0f * (float(x) + 0.5f) / 16.0f, 0.0f, 5.0f * (float(y) + 0.5f) / 16.0f};
      s.triangle = s.position.z >= 1.25f * s.position.x ? 0u : 1u;
      s.normal = {0, 1, 0};
      s.coverage = 1;
      texels.samples.push_back(s);
    }
  }
  TexelLightingSettings lighting;
  lighting.gather_rays = 0;
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexels(scene, g, *solved->caster, *solved->solver, texels, lighting);
  ASSERT_TRUE(lit.ok()) << lit.status().message();
  double sum_got = 0, sum_exact = 0, sq = 0;
  for (size_t i = 0; i < texels.samples.size(); ++i) {
    const Vec3& p = texels.samples[i].position;
    double exact = 0;
    for (const Light& light : scene.lights) {
      const double dx = light.position.x - p.x, dy = light.position.y - p.y,
                   dz = light.position.z - p.z;
      const double d2 = dx * dx + dy * dy + dz * dz;
      exact += double(light.intensity) * dy / (std::sqrt(d2) * d2);
    }
    const double got = luminance((*lit)[i].direct);
    ASSERT_TRUE(std::isfinite(got));
    sum_got += got;
    sum_exact += exact;
    sq += (got / exact - 1.0) * (got / exact - 1.0);
  }
  const double mean_error = sum_got / sum_exact - 1.0,
               rms = std::sqrt(sq / double(texels.samples.size()));
  reportFigure("floor direct light, mean of 256 points vs exact - 1", mean_error);
  reportFigure("floor direct light, per-point RMS rel. error (16 of 100,000 lights)", rms);
  // Importance sampling by exact unshadowed irradiance: with nothing in the
  // way every sample weighs the same, so the estimate is exact up to float
  // sums over 100,000 lights (measured ~1e-6).
  EXPECT_LT(std::abs(mean_error), 1e-3);
  EXPECT_LT(rms, 1e-3);
}

}  // namespace
}  // namespace svit::baker

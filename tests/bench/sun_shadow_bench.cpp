// The ball's shadow in the sun on Sponza, before and after shadow masks
// (issue 21). The level's dynamic ball is moved to a sunlit spot of the
// atrium floor; the runtime settles there (as far as a sample budget
// allows: settledRuntimeView); its picture is compared with the baked view
// of a bake in which the ball is static at that spot (the reference, seed
// 8), for two runtime bakes of the dynamic level: without shadow masks
// (`--no-shadow-masks`, the bake as it was before: the moved ball's shadow
// only as per-patch deltas) and with them (the sun shaded per pixel with
// the texels' static visibility times a caster map of the dynamic objects).
// A second reference (seed 9) against the first gives the noise floor.
//
// (a) Picture error (tests/runtime/picture_metric.h: RMS of the luminance
//     difference over static pixels relative to the reference's mean
//     there), split by the shadow's footprint: the static pixels where the
//     reference is darker than the "without" picture by more than
//     kFootprintDarkening. "Without" is the baked view of the no-masks
//     runtime bake, whose ball lies far away at the level's start (a
//     reference without that shadow, from another seed).
// (b) The shadow edge's position error: the floor around the shadow is
//     sampled on a grid of kGridStep_m cells, each point projected into the
//     picture (bilinear, linear radiance), so distances are metres on the
//     floor whatever the camera's angle. Each picture is divided by the
//     "without" picture (the floor texture cancels) and thresholded half way
//     between its lit level (median over a ring just outside the geometric
//     shadow) and its shadowed level (median inside the geometric shadow's
//     core). Edge error = area of the XOR of the picture's and the
//     reference's shadow regions / length of the reference region's
//     contour (marching squares), in cm. Points the ball hides are left out
//     of both. A picture whose shadow contrast is under a third of the
//     reference's has no shadow: its region is empty. Also each against the
//     geometric shadow (a ray to the sun's centre meets the ball).
// (c) The light at the shadow's centre and on the sunlit floor beside it
//     (Runtime::irradianceAt, lux): the masked runtime's before its first
//     update (its lightmap alone: the sky and bounce, as baked without the
//     ball there) and settled, the no-masks runtime's settled, and the
//     reference's lightmap (svit-probe). The bakes' texel size says what
//     a lightmap can show of a shadow the ball's size.
//
// usage: bench_sun_shadow --level LEVEL.json --work DIR --json OUT [--time 150]
//        [--quality 1] [--ball-x -3.0177 --ball-z -1.8] [--width 1280 --height 720]
//        [--exposure 0.0001] [--settle-samples 256 --settle-updates 12] [--png-prefix P]
//        [--overview PNG]
// Runs under xvfb-run; bakes go to DIR and are reused while their stamp
// matches (tests/bench/bench_bake.h). `--overview PNG` writes a top-down
// baked view of the atrium (the no-masks bake) and stops: for choosing a
// sunlit spot.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_bake.h"
#include "moved_level.h"
#include "runtime/gl_test_context.h"
#include "runtime/picture_comparison_png.h"
#include "runtime/picture_metric.h"
#include "svit/baker/probe.h"
#include "svit/gl_context.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace {

using namespace svit;
using namespace svit::test;

// A footprint pixel is at least this much darker in the reference than
// without the shadow: above the two bakes' own per-pixel noise on the sunlit
// floor (a few %), below the sun's share of the light there (~85 %).
constexpr double kFootprintDarkening = 0.25;
// The floor grid of (b): 5 mm cells (about a pixel of the default view)
// over 1.3 m x 1.3 m around the geometric shadow's centre.
constexpr double kGridStep_m = 0.005;
constexpr double kGridHalf_m = 0.65;
// Lit ring and shadow core, as the distance from the ball's centre to the
// sun ray through a floor point: [R + 8 cm, R + 25 cm] and [0, R - 6 cm]
// (clear of the reference's texel-wide blur, about 5 cm).
constexpr double kRingFrom_m = 0.08, kRingTo_m = 0.25, kCoreInset_m = 0.06;
// A picture with less than this share of the reference's shadow contrast
// shows no shadow.
constexpr double kNoShadowShare = 1.0 / 3.0;

struct Options {
  std::string level, work, json, png_prefix, overview;
  double quality = 1, time_s = 150;
  float ball_x = -3.0177f, ball_z = -1.8f;
  int width = 1280, height = 720;
  float exposure = 0.0001f;
  // The view: from the side away from the sun, this far from the shadow's
  // centre, this high above the floor's horizon.
  float distance_m = 2.2f, elevation_rad = 1.0472f, yfov_rad = 0.55f;
  int settle_samples = 256, settle_updates = 12;  ///< samples per update (0: none), updates
};

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
    else if (arg == "--overview")
      o.overview = v;
    else if (arg == "--quality")
      o.quality = std::atof(v.c_str());
    else if (arg == "--time")
      o.time_s = std::atof(v.c_str());
    else if (arg == "--ball-x")
      o.ball_x = float(std::atof(v.c_str()));
    else if (arg == "--ball-z")
      o.ball_z = float(std::atof(v.c_str()));
    else if (arg == "--width")
      o.width = std::atoi(v.c_str());
    else if (arg == "--height")
      o.height = std::atoi(v.c_str());
    else if (arg == "--settle-samples")
      o.settle_samples = std::atoi(v.c_str());
    else if (arg == "--settle-updates")
      o.settle_updates = std::atoi(v.c_str());
    else if (arg == "--exposure")
      o.exposure = float(std::atof(v.c_str()));
    else
      return false;
  }
  return argc % 2 == 1 && !o.level.empty() && !o.work.empty() &&
         (!o.json.empty() || !o.overview.empty()) && o.width > 0 && o.height > 0;
}

// ---- small vector helpers (metres, world space) ----
Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 normalized(Vec3 a) { return (1.0f / std::sqrt(dot(a, a))) * a; }
Vec3 transformPoint(const Mat4& m, Vec3 p) {
  return {m.m[0] * p.x + m.m[4] * p.y + m.m[8] * p.z + m.m[12],
          m.m[1] * p.x + m.m[5] * p.y + m.m[9] * p.z + m.m[13],
          m.m[2] * p.x + m.m[6] * p.y + m.m[10] * p.z + m.m[14]};
}

// The static triangles in world space (brute-force rays: a few per run).
std::vector<Vec3> staticTriangles(const Scene& scene) {
  std::vector<Vec3> out;
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic) continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    for (uint32_t index : mesh.indices)
      out.push_back(transformPoint(instance.world_from_object, mesh.positions[index]));
  }
  return out;
}

// Nearest hit distance along `dir` (unit) from `origin`, or infinity
// (Moller-Trumbore, both sides).
double nearestHit(const std::vector<Vec3>& triangles, Vec3 origin, Vec3 dir) {
  double best = INFINITY;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Vec3 e1 = triangles[t + 1] - triangles[t], e2 = triangles[t + 2] - triangles[t];
    const Vec3 p = cross(dir, e2);
    const float det = dot(e1, p);
    if (std::abs(det) < 1e-12f) continue;  // parallel (m^2 scale: triangles are > 1 mm)
    const Vec3 s = origin - triangles[t];
    const float u = dot(s, p) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 q = cross(s, e1);
    const float v = dot(dir, q) / det;
    if (v < 0 || u + v > 1) continue;
    const float h = dot(e2, q) / det;
    if (h > 1e-4f && h < best) best = h;  // 0.1 mm: past the surface the ray starts on
  }
  return best;
}

// The ball's radius: its mesh's farthest vertex from the object origin.
float meshRadius(const Scene& scene, int node) {
  float r = 0;
  for (const Instance& instance : scene.instances) {
    if (instance.node != node) continue;
    for (const Vec3& p : scene.meshes[size_t(instance.mesh)].positions)
      r = std::max(r, std::sqrt(dot(p, p)));
  }
  return r;
}

SceneRendererSettings rendererSettings(const Options& o) {
  SceneRendererSettings s;
  s.width = o.width;
  s.height = o.height;
  s.auto_exposure = false;
  s.exposure = o.exposure;
  return s;
}

LinearFrame bakedView(const BakedLevel& level, const Camera& camera, const Options& o) {
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, rendererSettings(o));
  SVIT_SETUP_CHECK(renderer.ok(), renderer.status().message());
  SVIT_SETUP_CHECK((*renderer)->render(camera, ShadingView::kBakedOnly).ok(), "baked render");
  return readLinearFrame(**renderer);
}

// Luminance of the irradiance at a floor point (facing up), lux.
double floorLux(const Runtime& runtime, Vec3 point) {
  const Rgb e = runtime.irradianceAt(point, Vec3{0, 1, 0});
  return 0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b;
}

struct Shown {
  LinearFrame runtime, baked_only;
  double centre_unsettled_lux = 0, centre_lux = 0, lit_lux = 0;  ///< floorLux
  int updates = 0;
  uint32_t pending = 0;
  double settle_ms = 0;
};

// The runtime of `level` with the ball at `ball`, settled as far as
// `o.settle_updates` updates of `o.settle_samples` samples allow (for this
// view, most important first), stopping early when one is idle or leaves
// nothing pending. Unbounded, Sponza's ~15,000 emitters the ball reaches
// take over 10 minutes on llvmpipe; what is left pending is reported.
// Runtime lights off (no bake has them).
Shown settledRuntimeView(const BakedLevel& level, Vec3 ball, const Camera& camera, Vec3 centre,
                         Vec3 lit, const Options& o) {
  RuntimeSettings settings;
  settings.max_samples_per_frame = o.settle_samples;
  settings.delta_textures = false;
  auto runtime = Runtime::create(level.scene, level.bake, level.dir, settings);
  SVIT_SETUP_CHECK(runtime.ok(), runtime.status().message());
  for (LightId light : (*runtime)->lights()) (void)(*runtime)->setLightEnabled(light, false);
  auto renderer = SceneRenderer::create(level.scene, level.bake, level.dir, runtime->get(),
                                        rendererSettings(o));
  SVIT_SETUP_CHECK(renderer.ok(), renderer.status().message());
  const ObjectId object = (*runtime)->objectForNode(level.scene.findNode("ball"));
  SVIT_SETUP_CHECK(object != kInvalidId, "the level has no dynamic object 'ball'");
  SVIT_SETUP_CHECK((*runtime)->setObjectTransform(object, placeAt(ball, Quat{})).ok(), "ball");
  RuntimeView view;
  view.position = camera.position;
  view.look_at = camera.look_at;
  view.up = camera.up;
  view.yfov_rad = camera.yfov_rad;
  view.aspect = float(o.width) / float(o.height);
  view.near_m = camera.near_m;
  SVIT_SETUP_CHECK((*runtime)->setView(view).ok(), "view");
  Shown out;
  out.centre_unsettled_lux = floorLux(**runtime, centre);
  const auto t0 = std::chrono::steady_clock::now();
  for (int frame = 0; frame < o.settle_updates; ++frame) {
    const FrameStats stats = (*runtime)->update(0);
    SVIT_SETUP_CHECK(stats.error.empty(), stats.error);
    ++out.updates;
    out.pending = stats.emitters_pending;
    if (stats.idle || stats.emitters_pending == 0) break;
  }
  out.settle_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  out.centre_lux = floorLux(**runtime, centre);
  out.lit_lux = floorLux(**runtime, lit);
  SVIT_SETUP_CHECK((*renderer)->render(camera, ShadingView::kRuntime).ok(), "runtime render");
  out.runtime = readLinearFrame(**renderer);
  SVIT_SETUP_CHECK((*renderer)->render(camera, ShadingView::kBakedOnly).ok(), "baked-only");
  out.baked_only = readLinearFrame(**renderer);
  return out;
}

// ---- (a) picture error inside and outside the footprint ----
struct Split {
  PictureError inside, outside, all;
};

// `shown` against `reference` over the static pixels where `in` is (or is not) set.
PictureError compareWhere(const LinearFrame& shown, const LinearFrame& reference,
                          const std::vector<uint8_t>& in, bool wanted) {
  LinearFrame masked = shown;
  for (size_t i = 0; i < in.size(); ++i) {
    if ((in[i] != 0) != wanted) masked.surface[i] = uint8_t(SurfaceKind::kNothing);
  }
  return comparePictures(masked, reference);
}

Split splitError(const LinearFrame& shown, const LinearFrame& reference,
                 const std::vector<uint8_t>& footprint) {
  return {compareWhere(shown, reference, footprint, true),
          compareWhere(shown, reference, footprint, false), comparePictures(shown, reference)};
}

// ---- (b) the shadow's edge on a floor grid ----
struct Projector {
  Vec3 position, forward, right, up;
  float tan_half = 0, aspect = 1;
  int width = 0, height = 0;
  // Pixel coordinates (x right, y down, pixel centres at +0.5), false behind the camera.
  bool project(Vec3 p, double& px, double& py) const {
    const Vec3 d = p - position;
    const float z = dot(d, forward);
    if (z <= 0) return false;
    const double ndc_x = dot(d, right) / (z * tan_half * aspect);
    const double ndc_y = dot(d, up) / (z * tan_half);
    px = (ndc_x + 1) * 0.5 * width;
    py = (1 - ndc_y) * 0.5 * height;
    return true;
  }
};

Projector projectorOf(const Camera& c, int width, int height) {
  Projector p;
  p.position = c.position;
  p.forward = normalized(c.look_at - c.position);
  p.right = normalized(cross(p.forward, c.up));
  p.up = cross(p.right, p.forward);
  p.tan_half = std::tan(0.5f * c.yfov_rad);
  p.aspect = float(width) / float(height);
  p.width = width;
  p.height = height;
  return p;
}

struct FloorGrid {
  int n = 0;                            ///< points per side
  std::vector<uint8_t> valid;           ///< seen, no neighbour pixel shows the ball or nothing
  std::vector<double> ball_distance_m;  ///< ball centre to the sun ray through the point
  std::vector<double> x0, y0;           ///< bilinear pixel coordinates
};

FloorGrid floorGrid(const Projector& view, Vec3 centre, Vec3 ball, float radius, Vec3 to_sun,
                    const std::vector<const LinearFrame*>& masks) {
  FloorGrid g;
  g.n = int(std::lround(2 * kGridHalf_m / kGridStep_m)) + 1;
  const size_t count = size_t(g.n) * size_t(g.n);
  g.valid.assign(count, 0);
  g.ball_distance_m.resize(count);
  g.x0.resize(count);
  g.y0.resize(count);
  (void)radius;
  for (int j = 0; j < g.n; ++j) {
    for (int i = 0; i < g.n; ++i) {
      const size_t k = size_t(j) * size_t(g.n) + size_t(i);
      const Vec3 p{centre.x + float(-kGridHalf_m + i * kGridStep_m), centre.y,
                   centre.z + float(-kGridHalf_m + j * kGridStep_m)};
      const Vec3 v = ball - p;
      const float t = dot(v, to_sun);
      g.ball_distance_m[k] = t > 0 ? std::sqrt(std::max(0.0f, dot(v, v) - t * t)) : INFINITY;
      double px = 0, py = 0;
      if (!view.project(p, px, py)) continue;
      px -= 0.5;
      py -= 0.5;
      const int xi = int(std::floor(px)), yi = int(std::floor(py));
      if (xi < 0 || yi < 0 || xi + 1 >= view.width || yi + 1 >= view.height) continue;
      bool ok = true;
      for (const LinearFrame* m : masks) {
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const size_t pixel = size_t(yi + dy) * size_t(view.width) + size_t(xi + dx);
            ok = ok && m->surface[pixel] == uint8_t(SurfaceKind::kStatic);
          }
        }
      }
      g.valid[k] = ok ? 1 : 0;
      g.x0[k] = px;
      g.y0[k] = py;
    }
  }
  return g;
}

double luminanceAt(const LinearFrame& f, double px, double py) {
  const int xi = int(std::floor(px)), yi = int(std::floor(py));
  const double fx = px - xi, fy = py - yi;
  auto at = [&](int x, int y) {
    return rec709Luminance(&f.rgb[(size_t(y) * size_t(f.width) + size_t(x)) * 3]);
  };
  return (1 - fy) * ((1 - fx) * at(xi, yi) + fx * at(xi + 1, yi)) +
         fy * ((1 - fx) * at(xi, yi + 1) + fx * at(xi + 1, yi + 1));
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

struct Shadow {
  std::vector<double> ratio;  ///< picture / without, per grid point
  double lit = 0, shadowed = 0, threshold = 0;
  double contrast = 0;  ///< 1 - shadowed / lit
  bool found = true;
  std::vector<uint8_t> region;  ///< per grid point: in the shadow
  double area_m2 = 0;
};

Shadow thresholdShadow(const FloorGrid& g, const LinearFrame& picture, const LinearFrame& without,
                       float radius) {
  Shadow s;
  s.ratio.assign(g.valid.size(), 0);
  std::vector<double> ring, core;
  for (size_t k = 0; k < g.valid.size(); ++k) {
    if (!g.valid[k]) continue;
    const double w = luminanceAt(without, g.x0[k], g.y0[k]);
    s.ratio[k] = w > 0 ? luminanceAt(picture, g.x0[k], g.y0[k]) / w : 0;
    const double d = g.ball_distance_m[k];
    if (d >= radius + kRingFrom_m && d <= radius + kRingTo_m) ring.push_back(s.ratio[k]);
    if (d <= radius - kCoreInset_m) core.push_back(s.ratio[k]);
  }
  SVIT_SETUP_CHECK(ring.size() > 100 && core.size() > 100,
                   "too few floor points seen in the lit ring or the shadow core");
  s.lit = median(ring);
  s.shadowed = median(core);
  s.threshold = 0.5 * (s.lit + s.shadowed);
  s.contrast = s.lit > 0 ? 1 - s.shadowed / s.lit : 0;
  s.region.assign(g.valid.size(), 0);
  for (size_t k = 0; k < g.valid.size(); ++k) {
    if (g.valid[k] && s.ratio[k] < s.threshold) {
      s.region[k] = 1;
      s.area_m2 += kGridStep_m * kGridStep_m;
    }
  }
  return s;
}

// Length (m) of the contour f = 0 through the grid cells whose four corners
// are valid: marching squares, linear along each cell edge.
double contourLength(const FloorGrid& g, const std::vector<double>& f) {
  double length = 0;
  for (int j = 0; j + 1 < g.n; ++j) {
    for (int i = 0; i + 1 < g.n; ++i) {
      const size_t k[4] = {
          size_t(j) * size_t(g.n) + size_t(i), size_t(j) * size_t(g.n) + size_t(i + 1),
          size_t(j + 1) * size_t(g.n) + size_t(i + 1), size_t(j + 1) * size_t(g.n) + size_t(i)};
      if (!g.valid[k[0]] || !g.valid[k[1]] || !g.valid[k[2]] || !g.valid[k[3]]) continue;
      const double cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
      double px[4], py[4];
      int crossings = 0;
      for (int e = 0; e < 4; ++e) {
        const double a = f[k[e]], b = f[k[(e + 1) % 4]];
        if ((a < 0) == (b < 0)) continue;
        const double t = a / (a - b);
        px[crossings] = cx[e] + t * (cx[(e + 1) % 4] - cx[e]);
        py[crossings] = cy[e] + t * (cy[(e + 1) % 4] - cy[e]);
        ++crossings;
      }
      for (int c = 0; c + 1 < crossings; c += 2)  // a saddle's two segments pair in order
        length += std::hypot(px[c + 1] - px[c], py[c + 1] - py[c]) * kGridStep_m;
    }
  }
  return length;
}

struct Edge {
  double xor_m2 = 0, perimeter_m = 0;
  double displacementCm() const { return perimeter_m > 0 ? 100 * xor_m2 / perimeter_m : 0; }
};

Edge edgeError(const FloorGrid& g, const std::vector<uint8_t>& region,
               const std::vector<uint8_t>& reference_region, double reference_perimeter_m) {
  Edge e;
  e.perimeter_m = reference_perimeter_m;
  for (size_t k = 0; k < g.valid.size(); ++k) {
    if (g.valid[k] && region[k] != reference_region[k]) e.xor_m2 += kGridStep_m * kGridStep_m;
  }
  return e;
}

// ---- pictures for people ----
// The central half of `f` (both ways), shrunk 2 x 2 in linear radiance, as display sRGB.
Status writeCropPng(const std::string& path, const LinearFrame& f, float exposure) {
  const int w = f.width / 4, h = f.height / 4, x0 = f.width / 4, y0 = f.height / 4;
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        float sum = 0;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const size_t p = size_t(y0 + 2 * y + dy) * size_t(f.width) + size_t(x0 + 2 * x + dx);
            sum += f.rgb[p * 3 + size_t(c)];
          }
        }
        rgb[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(c)] =
            displayByte(0.25f * sum, exposure);
      }
    }
  }
  return gl::writeRgbPng(path, w, h, rgb);
}

nlohmann::json errorJson(const PictureError& e) {
  return {{"rel_rms", e.static_rel_rms},
          {"rms", e.static_rms},
          {"reference_mean", e.static_reference_mean},
          {"pixels", e.static_pixels}};
}

nlohmann::json splitJson(const Split& s) {
  return {{"inside", errorJson(s.inside)},
          {"outside", errorJson(s.outside)},
          {"all", errorJson(s.all)}};
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parseArgs(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: bench_sun_shadow --level LEVEL.json --work DIR --json OUT [--time 150] "
                 "[--quality 1] [--ball-x -3.0177 --ball-z -1.8] [--width 1280 --height 720] "
                 "[--exposure 0.0001] [--settle-samples 256 --settle-updates 12] [--png-prefix P] "
                 "[--overview PNG]\n");
    return 2;
  }
  const GlTestContext context;
  if (!context.ok()) {
    std::fprintf(stderr, "bench_sun_shadow: no GL 4.5 context (run under xvfb-run -a)\n");
    return 1;
  }
  const std::string gl = checkGlContext()->renderer;
  std::filesystem::create_directories(o.work);
  const auto t_bakes = std::chrono::steady_clock::now();
  const BakedLevel plain = bakeOnce(o.level, o.work + "/base-plain", o.quality, 7, o.time_s, false);

  const Scene& scene = plain.scene;
  const int ball_node = scene.findNode("ball");
  SVIT_SETUP_CHECK(ball_node >= 0 && scene.nodes[size_t(ball_node)].dynamic,
                   o.level + ": no dynamic node 'ball'");
  const float radius = meshRadius(scene, ball_node);
  const Vec3 ball_start = scene.nodes[size_t(ball_node)].translation;
  const std::vector<Vec3> triangles = staticTriangles(scene);

  if (!o.overview.empty()) {  // a top-down baked view of the ball's line
    Camera top;
    top.position = {-0.5f, 30.0f, ball_start.z};
    top.look_at = {-0.5f, 0.0f, ball_start.z};
    top.up = {0, 0, -1};
    top.yfov_rad = 0.8f;
    const LinearFrame f = bakedView(plain, top, o);
    LinearFrame copy = f;
    SVIT_SETUP_CHECK(writeComparisonPng(o.overview, f, copy, o.exposure).ok(), o.overview);
    std::printf("wrote %s (x from left %.1f to right %.1f m at the floor)\n", o.overview.c_str(),
                -0.5 - 30 * std::tan(0.4) * o.width / o.height,
                -0.5 + 30 * std::tan(0.4) * o.width / o.height);
    return 0;
  }

  // The moved ball rests on the floor under (ball_x, ball_z).
  const double floor_drop = nearestHit(triangles, {o.ball_x, ball_start.y, o.ball_z}, {0, -1, 0});
  SVIT_SETUP_CHECK(std::isfinite(floor_drop), "no floor under the moved ball");
  const float floor_y = ball_start.y - float(floor_drop);
  const Vec3 ball{o.ball_x, floor_y + radius, o.ball_z};
  const Vec3 to_sun = normalized(scene.sun.direction_to_sun);
  // The geometric shadow's centre on the floor, and sunlight there.
  const Vec3 centre = ball - (radius / to_sun.y) * to_sun;
  const double sun_hit = nearestHit(triangles, centre + Vec3{0, 0.001f, 0}, to_sun);
  SVIT_SETUP_CHECK(!std::isfinite(sun_hit),
                   "the moved ball's shadow centre is not in the sun (static geometry at " +
                       std::to_string(sun_hit) + " m towards it)");

  // The reference level: the ball static there, every other dynamic object
  // static where the level starts it.
  std::string reference_level =
      writeLevelWithNodeStatic(o.level, "ball", ball, Quat{}, o.work, "ball-moved");
  for (const Node& node : scene.nodes) {
    if (!node.dynamic || node.name == "ball" || node.parent >= 0) continue;
    reference_level = writeLevelWithNodeStatic(reference_level, node.name, node.translation,
                                               node.rotation, o.work, "ball-moved-" + node.name);
  }
  const BakedLevel masks = bakeOnce(o.level, o.work + "/base-masks", o.quality, 7, o.time_s, true);
  const BakedLevel reference =
      bakeOnce(reference_level, o.work + "/reference", o.quality, 8, o.time_s);
  const BakedLevel second =
      bakeOnce(reference_level, o.work + "/reference-2", o.quality, 9, o.time_s);
  const double bakes_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_bakes).count();

  // The view: from the side away from the sun, down at the shadow's centre.
  Vec3 away = normalized(Vec3{-to_sun.x, 0, -to_sun.z});
  Camera camera;
  camera.position = centre + (o.distance_m * std::cos(o.elevation_rad)) * away +
                    Vec3{0, o.distance_m * std::sin(o.elevation_rad), 0};
  camera.look_at = centre;
  camera.yfov_rad = o.yfov_rad;

  const LinearFrame ref_view = bakedView(reference, camera, o);
  const LinearFrame second_view = bakedView(second, camera, o);
  // (c) A sunlit floor point beside the shadow, on the side away from the sun.
  const Vec3 lit = centre + (2.0f * radius) * away;
  const Shown before = settledRuntimeView(plain, ball, camera, centre, lit, o);
  const Shown after = settledRuntimeView(masks, ball, camera, centre, lit, o);
  Expected<std::vector<baker::ProbeResult>> reference_probes =
      baker::probeBake(reference.dir, {{centre, {0, 1, 0}}, {lit, {0, 1, 0}}});
  SVIT_SETUP_CHECK(reference_probes.ok(), reference_probes.status().message());
  const auto probeLux = [&](size_t i) {
    const Rgb& e = (*reference_probes)[i].irradiance;
    return 0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b;
  };
  const double texels_per_m =
      nlohmann::json::parse(std::ifstream(reference.dir + "/report.json"))["texels_per_m"];
  const LinearFrame& without = before.baked_only;  // the ball far away: no shadow here

  // The runtime frames show the ball where the reference has it.
  const Projector view = projectorOf(camera, o.width, o.height);
  double bx = 0, by = 0;
  SVIT_SETUP_CHECK(view.project(ball, bx, by), "ball behind the camera");
  const size_t ball_pixel = size_t(by) * size_t(o.width) + size_t(bx);
  SVIT_SETUP_CHECK(after.runtime.surface[ball_pixel] == uint8_t(SurfaceKind::kDynamic) &&
                       before.runtime.surface[ball_pixel] == uint8_t(SurfaceKind::kDynamic),
                   "the ball's centre does not project onto the ball");

  // (a) The footprint: static pixels the reference shows darker than without the shadow.
  std::vector<uint8_t> footprint(size_t(o.width) * size_t(o.height), 0);
  size_t footprint_pixels = 0;
  for (size_t i = 0; i < footprint.size(); ++i) {
    const bool all_static = ref_view.surface[i] == uint8_t(SurfaceKind::kStatic) &&
                            without.surface[i] == uint8_t(SurfaceKind::kStatic) &&
                            after.runtime.surface[i] == uint8_t(SurfaceKind::kStatic);
    if (all_static && rec709Luminance(&ref_view.rgb[i * 3]) <
                          (1 - kFootprintDarkening) * rec709Luminance(&without.rgb[i * 3])) {
      footprint[i] = 1;
      ++footprint_pixels;
    }
  }
  const Split e_before = splitError(before.runtime, ref_view, footprint);
  const Split e_after = splitError(after.runtime, ref_view, footprint);
  const Split e_plain_baked = splitError(before.baked_only, ref_view, footprint);
  const Split e_masks_baked = splitError(after.baked_only, ref_view, footprint);
  const Split e_floor = splitError(second_view, ref_view, footprint);

  // (b) The edge on the floor grid.
  const FloorGrid grid =
      floorGrid(view, centre, ball, radius, to_sun, {&before.runtime, &after.runtime});
  const Shadow s_ref = thresholdShadow(grid, ref_view, without, radius);
  const Shadow s_second = thresholdShadow(grid, second_view, without, radius);
  Shadow s_before = thresholdShadow(grid, before.runtime, without, radius);
  Shadow s_after = thresholdShadow(grid, after.runtime, without, radius);
  for (Shadow* s : {&s_before, &s_after}) {
    s->found = s->contrast >= kNoShadowShare * s_ref.contrast;
    if (!s->found) {
      std::fill(s->region.begin(), s->region.end(), 0);
      s->area_m2 = 0;
    }
  }
  std::vector<double> f_ref(grid.valid.size()), f_geo(grid.valid.size());
  std::vector<uint8_t> geo(grid.valid.size(), 0);
  double geo_area_m2 = 0;
  size_t valid_points = 0;
  for (size_t k = 0; k < grid.valid.size(); ++k) {
    f_ref[k] = s_ref.ratio[k] - s_ref.threshold;
    f_geo[k] = grid.ball_distance_m[k] - radius;
    geo[k] = grid.valid[k] && grid.ball_distance_m[k] < radius ? 1 : 0;
    geo_area_m2 += geo[k] * kGridStep_m * kGridStep_m;
    valid_points += grid.valid[k];
  }
  const double ref_perimeter = contourLength(grid, f_ref);
  const double geo_perimeter = contourLength(grid, f_geo);
  struct EdgeRow {
    const char* name;
    const Shadow* s;
  };
  const EdgeRow edge_rows[] = {{"before", &s_before},
                               {"after", &s_after},
                               {"second reference", &s_second},
                               {"reference", &s_ref}};

  // Report.
  std::printf(
      "ball at (%.3f, %.3f, %.3f) m, radius %.3f m, floor y %.3f m; shadow centre (%.3f, %.3f) "
      "m; camera at (%.3f, %.3f, %.3f) m, %.0f deg down, yfov %.2f rad, %dx%d\n",
      ball.x, ball.y, ball.z, radius, floor_y, centre.x, centre.z, camera.position.x,
      camera.position.y, camera.position.z, o.elevation_rad * 180 / M_PI, o.yfov_rad, o.width,
      o.height);
  std::printf(
      "settled (%d samples an update): before %d updates (%u pending, %.0f ms), after %d "
      "updates (%u pending, %.0f ms); footprint %zu pixels\n",
      o.settle_samples, before.updates, before.pending, before.settle_ms, after.updates,
      after.pending, after.settle_ms, footprint_pixels);
  std::printf("(a) relative RMS against the reference   inside   outside   whole view\n");
  auto row = [](const char* name, const Split& s) {
    std::printf("    %-36s %.4f   %.4f    %.4f\n", name, s.inside.static_rel_rms,
                s.outside.static_rel_rms, s.all.static_rel_rms);
  };
  row("before (no masks), runtime settled", e_before);
  row("after (masks), runtime settled", e_after);
  row("before, baked-only", e_plain_baked);
  row("after, baked-only", e_masks_baked);
  row("noise floor (second reference)", e_floor);
  std::printf(
      "(b) shadow on the floor grid (%zu points of %.1f mm seen): reference area %.0f cm2, "
      "contour %.1f cm; geometric area %.0f cm2, contour %.1f cm\n",
      valid_points, 1000 * kGridStep_m, 1e4 * s_ref.area_m2, 100 * ref_perimeter, 1e4 * geo_area_m2,
      100 * geo_perimeter);
  nlohmann::json edges = nlohmann::json::object();
  for (const EdgeRow& r : edge_rows) {
    const Edge vs_ref = edgeError(grid, r.s->region, s_ref.region, ref_perimeter);
    const Edge vs_geo = edgeError(grid, r.s->region, geo, geo_perimeter);
    std::printf(
        "    %-17s contrast %.3f (lit %.3f, shadowed %.3f)%s area %.0f cm2; edge error "
        "%.2f cm against the reference, %.2f cm against the geometric shadow\n",
        r.name, r.s->contrast, r.s->lit, r.s->shadowed, r.s->found ? "" : " NO SHADOW,",
        1e4 * r.s->area_m2, vs_ref.displacementCm(), vs_geo.displacementCm());
    edges[r.name] = {{"contrast", r.s->contrast},
                     {"lit_ratio", r.s->lit},
                     {"shadowed_ratio", r.s->shadowed},
                     {"shadow_found", r.s->found},
                     {"area_cm2", 1e4 * r.s->area_m2},
                     {"xor_cm2_vs_reference", 1e4 * vs_ref.xor_m2},
                     {"edge_error_cm_vs_reference", vs_ref.displacementCm()},
                     {"xor_cm2_vs_geometric", 1e4 * vs_geo.xor_m2},
                     {"edge_error_cm_vs_geometric", vs_geo.displacementCm()}};
  }

  if (!o.png_prefix.empty()) {
    SVIT_SETUP_CHECK(writeCropPng(o.png_prefix + "-reference.png", ref_view, o.exposure).ok(),
                     "png");
    SVIT_SETUP_CHECK(writeCropPng(o.png_prefix + "-before.png", before.runtime, o.exposure).ok(),
                     "png");
    SVIT_SETUP_CHECK(writeCropPng(o.png_prefix + "-after.png", after.runtime, o.exposure).ok(),
                     "png");
  }
  (void)writeComparisonPng(o.work + "/before-vs-reference.png", before.runtime, ref_view,
                           o.exposure);
  (void)writeComparisonPng(o.work + "/after-vs-reference.png", after.runtime, ref_view, o.exposure);

  std::printf(
      "(c) at the shadow's centre, lux (bakes at %.2f texels/m, a texel %.0f cm): sunlit floor "
      "beside it %.0f (after), %.0f (before), %.0f (reference); centre: reference %.0f, "
      "before settled %.0f, after's lightmap alone %.0f, after settled %.0f\n",
      texels_per_m, 100 / texels_per_m, after.lit_lux, before.lit_lux, probeLux(1), probeLux(0),
      before.centre_lux, after.centre_unsettled_lux, after.centre_lux);
  nlohmann::json out = {
      {"level", o.level},
      {"renderer", gl},
      {"bake_quality", o.quality},
      {"bake_time_s", o.time_s},
      {"bakes_wall_s", bakes_s},
      {"reference_masked_lights", reference.bake.masks.lights.size()},
      {"ball", {ball.x, ball.y, ball.z}},
      {"ball_radius_m", radius},
      {"floor_y_m", floor_y},
      {"shadow_centre", {centre.x, centre.y, centre.z}},
      {"camera",
       {{"position", {camera.position.x, camera.position.y, camera.position.z}},
        {"look_at", {camera.look_at.x, camera.look_at.y, camera.look_at.z}},
        {"yfov_rad", camera.yfov_rad},
        {"elevation_rad", o.elevation_rad},
        {"width", o.width},
        {"height", o.height},
        {"exposure", o.exposure}}},
      {"settle",
       {{"samples_per_update", o.settle_samples},
        {"max_updates", o.settle_updates},
        {"before",
         {{"updates", before.updates}, {"pending", before.pending}, {"ms", before.settle_ms}}},
        {"after",
         {{"updates", after.updates}, {"pending", after.pending}, {"ms", after.settle_ms}}}}},
      {"footprint_darkening", kFootprintDarkening},
      {"footprint_pixels", footprint_pixels},
      {"picture_error",
       {{"before", splitJson(e_before)},
        {"after", splitJson(e_after)},
        {"before_baked_only", splitJson(e_plain_baked)},
        {"after_baked_only", splitJson(e_masks_baked)},
        {"noise_floor", splitJson(e_floor)}}},
      {"grid_step_m", kGridStep_m},
      {"grid_points_seen", valid_points},
      {"reference_shadow_area_cm2", 1e4 * s_ref.area_m2},
      {"reference_contour_cm", 100 * ref_perimeter},
      {"geometric_shadow_area_cm2", 1e4 * geo_area_m2},
      {"geometric_contour_cm", 100 * geo_perimeter},
      {"edges", edges},
      {"at_centre_lux",
       {{"texels_per_m", texels_per_m},
        {"lit_after", after.lit_lux},
        {"lit_before", before.lit_lux},
        {"lit_reference", probeLux(1)},
        {"reference", probeLux(0)},
        {"before_settled", before.centre_lux},
        {"after_lightmap_alone", after.centre_unsettled_lux},
        {"after_settled", after.centre_lux}}}};
  std::ofstream(o.json) << out.dump(1) << "\n";
  return 0;
}

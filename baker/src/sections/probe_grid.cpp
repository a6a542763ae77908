// The L1 spherical-harmonic probe grid dynamic objects take their indirect
// light from (docs/architecture/baker-sections.md "Probe grid"). Each probe
// gathers radiance over the sphere from the solved radiosity and projects it
// onto the first two SH bands (Ramamoorthi & Hanrahan 2001, "An Efficient
// Representation for Irradiance Environment Maps": irradiance is radiance SH
// convolved with the clamped cosine, A0 = pi, A1 = 2pi/3). Emission is
// estimated from two strategies, sphere directions and points on emissive
// triangles, weighted by the balance heuristic (Veach 1997, ch. 9: the
// multi-sample estimator sum_i f(x_i) / sum_s n_s p_s(x_i) over both
// strategies' samples); everything else only from the sphere directions.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "runtime_sections_internal.h"
#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

constexpr uint64_t kProbeStream = 0x70726f6265677264ull;  // "probegrd"
constexpr size_t kChunkProbes = 16;
constexpr double kY0 = 0.282094791773878;  // 1 / (2 sqrt(pi))
constexpr double kY1 = 0.488602511902920;  // sqrt(3 / (4 pi))
// Strata per axis of the unit square the sphere directions are drawn from.
constexpr uint32_t kStrata = 16;
static_assert(kStrata * kStrata == kProbeRays);
// Sphere directions have density 1 / 4pi per steradian.
constexpr double kSpherePdf = 1.0 / (4.0 * kPi);

// The emissive triangles, to sample points on by luminance x area.
struct EmitterTable {
  std::vector<uint32_t> triangle;
  std::vector<double> cdf;  // inclusive, last = total
  // per geometry triangle: channel-sum luminance (cd/m2), 0 when not emissive
  std::vector<double> weight;
  double total = 0;  // sum of luminance x area (cd)

  explicit EmitterTable(const BakeGeometry& g) : weight(g.triangleCount(), 0.0) {
    for (size_t t = 0; t < g.triangleCount(); ++t) {
      const Rgb& e = g.emission[t];
      const double luminance = double(e.r) + double(e.g) + double(e.b);
      const double area = g.areas_m2[t];
      if (!(luminance > 0) || !(area > 0) || !std::isfinite(luminance * area)) continue;
      weight[t] = luminance;
      total += luminance * area;
      triangle.push_back(uint32_t(t));
      cdf.push_back(total);
    }
  }
  bool empty() const { return triangle.empty(); }
  // Index into `triangle` for u in [0, 1).
  size_t pick(double u) const {
    const size_t i = size_t(std::upper_bound(cdf.begin(), cdf.end(), u * total) - cdf.begin());
    return std::min(i, triangle.size() - 1);
  }
  // Density per steradian, at the probe, of reaching triangle `t` at
  // distance `distance_m` and cosine `cos_emitter` by point sampling:
  // p_area = luminance / total (per m2), times distance^2 / cos.
  double solidAnglePdf(size_t t, double distance_m, double cos_emitter) const {
    return weight[t] / total * distance_m * distance_m / std::max(cos_emitter, 1e-9);
  }
};

// Sky luminance (cd/m2) seen looking along unit `d`, the model
// light_sources.cpp shoots from: uniform is the zenith luminance above the
// horizon and black below; gradient blends horizon to zenith with the cosine
// of the zenith angle, ground below.
glm::dvec3 skyLuminance(const Sky& sky, const glm::dvec3& d) {
  switch (sky.model) {
    case SkyModel::kNone: return glm::dvec3(0.0);
    case SkyModel::kUniform: return d.y >= 0 ? dvec(sky.zenith_luminance) : glm::dvec3(0.0);
    case SkyModel::kGradient:
      if (d.y < 0) return dvec(sky.ground_luminance);
      return dvec(sky.horizon_luminance) +
             (dvec(sky.zenith_luminance) - dvec(sky.horizon_luminance)) * d.y;
  }
  return glm::dvec3(0.0);
}

// The grid's layout: cell-centred probes over the static bounds, so
// probes never sit on the bounds, where walls usually are.
struct GridLayout {
  BakeProbeGrid grid;  ///< dims, origin and spacing set; no SH yet
  glm::dvec3 origin{0.0}, spacing{0.0};
};

GridLayout layOutGrid(const BakeGeometry& geometry, double spacing_m) {
  GridLayout layout;
  const glm::dvec3 lo = dvec(geometry.bounds.min), hi = dvec(geometry.bounds.max);
  const glm::dvec3 extent = hi - lo;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil(extent[a] / spacing_m);
    const uint32_t n =
        uint32_t(std::clamp(std::isfinite(cells) ? cells : 1.0, 1.0, double(kMaxProbesPerAxis)));
    layout.grid.dims[a] = n;
    layout.spacing[a] = extent[a] > 0 ? extent[a] / n : spacing_m;
    layout.origin[a] = extent[a] > 0 ? lo[a] + 0.5 * layout.spacing[a] : lo[a];
  }
  layout.grid.origin = vec3(layout.origin);
  layout.grid.spacing = vec3(layout.spacing);
  return layout;
}

// What every probe's gather reads.
struct ProbeContext {
  const Scene& scene;
  const BakeGeometry& geometry;
  const RayCaster& caster;
  const RadiositySolver& solver;
  const EmitterTable& emitters;
  uint32_t emitter_samples;
  uint64_t seed;
};

// One probe's rays: kProbeRays sphere directions, then the emitter samples.
struct ProbeRays {
  std::vector<Ray> rays;
  std::vector<RayHit> hits;
  std::vector<uint32_t> target;  // the triangle each emitter sample aims at
};

void aimProbeRays(const ProbeContext& c, const glm::dvec3& position, Rng& rng, ProbeRays& r) {
  // Jittered 16 x 16 strata of the uniform-sphere warp: uniform density,
  // less variance in the projection than independent directions.
  for (uint32_t i = 0; i < kProbeRays; ++i) {
    const double u1 = (double(i % kStrata) + rng.uniformDouble()) / kStrata;
    const double u2 = (double(i / kStrata) + rng.uniformDouble()) / kStrata;
    r.rays[i].origin = vec3(position);
    r.rays[i].direction = vec3(uniformSphere(u1, u2));
  }
  // Points on the emitters, the triangle choice stratified.
  for (uint32_t j = 0; j < c.emitter_samples; ++j) {
    const uint32_t t =
        c.emitters.triangle[c.emitters.pick((double(j) + rng.uniformDouble()) / c.emitter_samples)];
    const glm::dvec2 b = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
    const glm::dvec3 c0 = dvec(c.geometry.corner(t, 0)), c1 = dvec(c.geometry.corner(t, 1)),
                     c2 = dvec(c.geometry.corner(t, 2));
    const glm::dvec3 to = c0 + b.x * (c1 - c0) + b.y * (c2 - c0) - position;
    const double distance = glm::length(to);
    r.target[j] = t;
    r.rays[kProbeRays + j].origin = vec3(position);
    r.rays[kProbeRays + j].direction = vec3(distance > 0 ? to / distance : glm::dvec3(0, 1, 0));
  }
}

// Running L1 SH projection of radiance.
struct ShSums {
  glm::dvec3 c[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  void add(const glm::dvec3& d, const glm::dvec3& weighted_radiance) {
    c[0] += weighted_radiance * kY0;
    c[1] += weighted_radiance * (kY1 * d.y);
    c[2] += weighted_radiance * (kY1 * d.z);
    c[3] += weighted_radiance * (kY1 * d.x);
  }
};

// Emission seen along unit `d` at hit `h`, weighted by the balance
// heuristic over both strategies: L_e / (N_s p_s + N_e p_e).
glm::dvec3 emissionWeighted(const ProbeContext& c, const RayHit& h, const glm::dvec3& d) {
  const glm::dvec3 emission = dvec(c.geometry.emission[h.triangle]);
  if (emission == glm::dvec3(0.0)) return glm::dvec3(0.0);
  double pdfs = kProbeRays * kSpherePdf;
  if (c.emitter_samples > 0) {
    const double cos_emitter = std::abs(glm::dot(dvec(c.geometry.normals[h.triangle]), d));
    pdfs += c.emitter_samples * c.emitters.solidAnglePdf(h.triangle, double(h.t), cos_emitter);
  }
  return emission / pdfs;
}

// Projects probe p's radiance into grid.sh; false when most of its rays
// see backs (the probe is inside something solid).
bool gatherProbe(const ProbeContext& c, const GridLayout& layout, size_t p, ProbeRays& r,
                 std::vector<float>& sh) {
  const BakeGeometry& geometry = c.geometry;
  const size_t nx = layout.grid.dims[0], ny = layout.grid.dims[1];
  const size_t ix = p % nx, iy = (p / nx) % ny, iz = p / (nx * ny);
  const glm::dvec3 position =
      layout.origin + glm::dvec3(double(ix), double(iy), double(iz)) * layout.spacing;
  Rng rng(hashIds(c.seed, kProbeStream, p));
  aimProbeRays(c, position, rng, r);
  c.caster.intersect(r.rays, r.hits);
  ShSums sums;
  uint32_t back_hits = 0;
  for (uint32_t i = 0; i < kProbeRays; ++i) {
    const RayHit& h = r.hits[i];
    const glm::dvec3 d = glm::normalize(dvec(r.rays[i].direction));
    if (!h.hit()) {
      sums.add(d, skyLuminance(c.scene.sky, d) / (kProbeRays * kSpherePdf));
    } else if (h.front || geometry.double_sided[h.triangle]) {
      // Leaving radiance of a Lambertian side: (pi L_e + albedo E) / pi.
      const Rgb e =
          c.solver.irradianceAt(h.triangle, h.front, h.u, h.v, InterpolationMode::kVertex);
      sums.add(d, dvec(geometry.albedo[h.triangle]) * dvec(e) / kPi / (kProbeRays * kSpherePdf) +
                      emissionWeighted(c, h, d));
    } else {
      ++back_hits;  // the black back of a single-sided surface
    }
  }
  // An emitter sample counts where its ray reaches the aimed-at
  // triangle's emitting side first (anything else in between shadows it).
  for (uint32_t j = 0; j < c.emitter_samples; ++j) {
    const RayHit& h = r.hits[kProbeRays + j];
    if (!h.hit() || h.triangle != r.target[j] || !(h.front || geometry.double_sided[h.triangle]))
      continue;
    const glm::dvec3 d = dvec(r.rays[kProbeRays + j].direction);
    sums.add(d, emissionWeighted(c, h, d));
  }
  // The sums above are already the Monte Carlo projections: integral
  // of L * Y over the sphere (cd/m2 x sr).
  for (int k = 0; k < 4; ++k) {
    for (int ch = 0; ch < 3; ++ch) sh[p * 12 + size_t(k) * 3 + size_t(ch)] = float(sums.c[k][ch]);
  }
  return back_hits * 2 <= kProbeRays;
}

// Probes inside geometry: the mean of their valid neighbours (3x3x3 block,
// read from the gathered values only, so the order does not matter), or zero.
void fillInvalidProbes(BakeProbeGrid& grid, const std::vector<uint8_t>& valid) {
  const size_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const size_t probes = nx * ny * nz;
  std::vector<float> filled = grid.sh;
  for (size_t p = 0; p < probes; ++p) {
    if (valid[p]) continue;
    const long ix = long(p % nx), iy = long((p / nx) % ny), iz = long(p / (nx * ny));
    std::array<double, 12> sum{};
    int count = 0;
    for (long dz = -1; dz <= 1; ++dz) {
      for (long dy = -1; dy <= 1; ++dy) {
        for (long dx = -1; dx <= 1; ++dx) {
          const long x = ix + dx, y = iy + dy, z = iz + dz;
          if (x < 0 || y < 0 || z < 0 || x >= long(nx) || y >= long(ny) || z >= long(nz)) continue;
          const size_t q = size_t(x) + nx * (size_t(y) + ny * size_t(z));
          if (!valid[q]) continue;
          for (size_t k = 0; k < 12; ++k) sum[k] += grid.sh[q * 12 + k];
          ++count;
        }
      }
    }
    for (size_t k = 0; k < 12; ++k) filled[p * 12 + k] = count > 0 ? float(sum[k] / count) : 0.0f;
  }
  grid.sh = std::move(filled);
}

}  // namespace

Expected<BakeProbeGrid> buildProbeGrid(const Scene& scene, const BakeGeometry& geometry,
                                       const RayCaster& caster, const RadiositySolver& solver,
                                       double spacing_m, uint64_t seed, int threads,
                                       const std::atomic<bool>* cancel) {
  GridLayout layout = layOutGrid(geometry, spacing_m);
  BakeProbeGrid& grid = layout.grid;
  const size_t probes = size_t(grid.dims[0]) * size_t(grid.dims[1]) * size_t(grid.dims[2]);
  grid.sh.assign(probes * 12, 0.0f);
  std::vector<uint8_t> valid(probes, 0);

  const EmitterTable emitters(geometry);
  const uint32_t emitter_samples = emitters.empty() ? 0 : kProbeEmitterSamples;
  const ProbeContext context{scene, geometry, caster, solver, emitters, emitter_samples, seed};
  solver.prepareQueries();  // so irradianceAt is thread-safe below
  parallelFor(probes, kChunkProbes, threads, [&](size_t begin, size_t end) {
    if (cancel && cancel->load()) return;
    const uint32_t ray_count = kProbeRays + emitter_samples;
    ProbeRays scratch;
    scratch.rays.resize(ray_count);
    scratch.hits.resize(ray_count);
    scratch.target.resize(emitter_samples);
    for (size_t p = begin; p < end; ++p)
      valid[p] = gatherProbe(context, layout, p, scratch, grid.sh) ? 1 : 0;
  });
  if (cancel && cancel->load())
    return Status(StatusCode::kCancelled, "runtime sections: probes cancelled");
  fillInvalidProbes(grid, valid);
  return std::move(layout.grid);
}

}  // namespace svit::baker

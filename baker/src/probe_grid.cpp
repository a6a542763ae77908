// The L1 spherical-harmonic probe grid dynamic objects take their indirect
// light from (DESIGN.md "Dynamic objects receive light"). Each probe gathers
// radiance over the sphere from the solved radiosity and projects it onto
// the first two SH bands (Ramamoorthi & Hanrahan 2001, "An Efficient
// Representation for Irradiance Environment Maps": irradiance is radiance
// SH convolved with the clamped cosine, A0 = pi, A1 = 2pi/3). Emission is
// estimated from two strategies, sphere directions and points on emissive
// triangles, weighted by the balance heuristic (Veach 1997, ch. 9: the
// multi-sample estimator sum_i f(x_i) / sum_s n_s p_s(x_i) over both
// strategies' samples); everything else only from the sphere directions.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "double_math.h"
#include "parallel_for.h"
#include "random.h"
#include "runtime_sections_internal.h"
#include "sampling.h"

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
  std::vector<double> cdf;        // inclusive, last = total
  std::vector<double> weight;     // per geometry triangle: channel-sum luminance (cd/m2), 0 when not emissive
  double total = 0;               // sum of luminance x area (cd)

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
    case SkyModel::kNone:
      return glm::dvec3(0.0);
    case SkyModel::kUniform:
      return d.y >= 0 ? dvec(sky.zenith_luminance) : glm::dvec3(0.0);
    case SkyModel::kGradient:
      if (d.y < 0) return dvec(sky.ground_luminance);
      return dvec(sky.horizon_luminance) + (dvec(sky.zenith_luminance) - dvec(sky.horizon_luminance)) * d.y;
  }
  return glm::dvec3(0.0);
}

}  // namespace

Expected<BakeProbeGrid> buildProbeGrid(const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
                                       const RadiositySolver& solver, double spacing_m, uint64_t seed, int threads,
                                       const std::atomic<bool>* cancel) {
  BakeProbeGrid grid;
  const glm::dvec3 lo = dvec(geometry.bounds.min), hi = dvec(geometry.bounds.max);
  const glm::dvec3 extent = hi - lo;
  glm::dvec3 origin, spacing;
  for (int a = 0; a < 3; ++a) {
    // Cell-centred: probes never sit on the bounds, where walls usually are.
    const double cells = std::ceil(extent[a] / spacing_m);
    const uint32_t n = uint32_t(std::clamp(std::isfinite(cells) ? cells : 1.0, 1.0, double(kMaxProbesPerAxis)));
    grid.dims[a] = n;
    spacing[a] = extent[a] > 0 ? extent[a] / n : spacing_m;
    origin[a] = extent[a] > 0 ? lo[a] + 0.5 * spacing[a] : lo[a];
  }
  grid.origin = vec3(origin);
  grid.spacing = vec3(spacing);
  const size_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  const size_t probes = nx * ny * nz;
  grid.sh.assign(probes * 12, 0.0f);
  std::vector<uint8_t> valid(probes, 0);

  const EmitterTable emitters(geometry);
  const uint32_t emitter_samples = emitters.empty() ? 0 : kProbeEmitterSamples;
  solver.prepareQueries();  // so irradianceAt is thread-safe below
  parallelFor(probes, kChunkProbes, threads, [&](size_t begin, size_t end) {
    if (cancel && cancel->load()) return;
    const uint32_t ray_count = kProbeRays + emitter_samples;
    std::vector<Ray> rays(ray_count);
    std::vector<RayHit> hits(ray_count);
    std::vector<uint32_t> target(emitter_samples);  // the triangle each emitter sample aims at
    for (size_t p = begin; p < end; ++p) {
      const size_t ix = p % nx, iy = (p / nx) % ny, iz = p / (nx * ny);
      const glm::dvec3 position = origin + glm::dvec3(double(ix), double(iy), double(iz)) * spacing;
      Rng rng(hashIds(seed, kProbeStream, p));
      // Jittered 16 x 16 strata of the uniform-sphere warp: uniform density,
      // less variance in the projection than independent directions.
      for (uint32_t r = 0; r < kProbeRays; ++r) {
        const double u1 = (double(r % kStrata) + rng.uniformDouble()) / kStrata;
        const double u2 = (double(r / kStrata) + rng.uniformDouble()) / kStrata;
        rays[r].origin = vec3(position);
        rays[r].direction = vec3(uniformSphere(u1, u2));
      }
      // Points on the emitters, the triangle choice stratified.
      for (uint32_t j = 0; j < emitter_samples; ++j) {
        const uint32_t t = emitters.triangle[emitters.pick((double(j) + rng.uniformDouble()) / emitter_samples)];
        const glm::dvec2 b = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
        const glm::dvec3 c0 = dvec(geometry.corner(t, 0)), c1 = dvec(geometry.corner(t, 1)),
                         c2 = dvec(geometry.corner(t, 2));
        const glm::dvec3 to = c0 + b.x * (c1 - c0) + b.y * (c2 - c0) - position;
        const double distance = glm::length(to);
        target[j] = t;
        rays[kProbeRays + j].origin = vec3(position);
        rays[kProbeRays + j].direction = vec3(distance > 0 ? to / distance : glm::dvec3(0, 1, 0));
      }
      caster.intersect(rays, hits);
      glm::dvec3 c[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      auto add = [&](const glm::dvec3& d, const glm::dvec3& weighted_radiance) {
        c[0] += weighted_radiance * kY0;
        c[1] += weighted_radiance * (kY1 * d.y);
        c[2] += weighted_radiance * (kY1 * d.z);
        c[3] += weighted_radiance * (kY1 * d.x);
      };
      // Emission seen along unit `d` at hit `h`, weighted by the balance
      // heuristic over both strategies: L_e / (N_s p_s + N_e p_e).
      auto emissionWeighted = [&](const RayHit& h, const glm::dvec3& d) {
        const glm::dvec3 emission = dvec(geometry.emission[h.triangle]);
        if (emission == glm::dvec3(0.0)) return glm::dvec3(0.0);
        double pdfs = kProbeRays * kSpherePdf;
        if (emitter_samples > 0) {
          const double cos_emitter = std::abs(glm::dot(dvec(geometry.normals[h.triangle]), d));
          pdfs += emitter_samples * emitters.solidAnglePdf(h.triangle, double(h.t), cos_emitter);
        }
        return emission / pdfs;
      };
      uint32_t back_hits = 0;
      for (uint32_t r = 0; r < kProbeRays; ++r) {
        const RayHit& h = hits[r];
        const glm::dvec3 d = glm::normalize(dvec(rays[r].direction));
        if (!h.hit()) {
          add(d, skyLuminance(scene.sky, d) / (kProbeRays * kSpherePdf));
        } else if (h.front || geometry.double_sided[h.triangle]) {
          // Leaving radiance of a Lambertian side: (pi L_e + albedo E) / pi.
          const Rgb e = solver.irradianceAt(h.triangle, h.front, h.u, h.v, InterpolationMode::kVertex);
          add(d, dvec(geometry.albedo[h.triangle]) * dvec(e) / kPi / (kProbeRays * kSpherePdf) + emissionWeighted(h, d));
        } else {
          ++back_hits;  // the black back of a single-sided surface
        }
      }
      // An emitter sample counts where its ray reaches the aimed-at
      // triangle's emitting side first (anything else in between shadows it).
      for (uint32_t j = 0; j < emitter_samples; ++j) {
        const RayHit& h = hits[kProbeRays + j];
        if (!h.hit() || h.triangle != target[j] || !(h.front || geometry.double_sided[h.triangle])) continue;
        const glm::dvec3 d = dvec(rays[kProbeRays + j].direction);
        add(d, emissionWeighted(h, d));
      }
      // The sums above are already the Monte Carlo projections: integral
      // of L * Y over the sphere (cd/m2 x sr).
      for (int k = 0; k < 4; ++k) {
        for (int ch = 0; ch < 3; ++ch) grid.sh[p * 12 + size_t(k) * 3 + size_t(ch)] = float(c[k][ch]);
      }
      // Most rays on backs: the probe is inside something solid.
      valid[p] = back_hits * 2 <= kProbeRays ? 1 : 0;
    }
  });
  if (cancel && cancel->load()) return Status(StatusCode::kCancelled, "runtime sections: probes cancelled");

  // Probes inside geometry: the mean of their valid neighbours (3x3x3 block,
  // read from the gathered values only, so the order does not matter), or zero.
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
  return grid;
}

}  // namespace svit::baker

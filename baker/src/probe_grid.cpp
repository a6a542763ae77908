// The L1 spherical-harmonic probe grid dynamic objects take their indirect
// light from (DESIGN.md "Dynamic objects receive light"). Each probe gathers
// radiance over the sphere from the solved radiosity and projects it onto
// the first two SH bands (Ramamoorthi & Hanrahan 2001, "An Efficient
// Representation for Irradiance Environment Maps": irradiance is radiance
// SH convolved with the clamped cosine, A0 = pi, A1 = 2pi/3).

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
constexpr size_t kChunkProbes = 64;
constexpr double kY0 = 0.282094791773878;  // 1 / (2 sqrt(pi))
constexpr double kY1 = 0.488602511902920;  // sqrt(3 / (4 pi))
// Strata per axis of the unit square the sphere directions are drawn from.
constexpr uint32_t kStrata = 8;
static_assert(kStrata * kStrata == kProbeRays);

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

  solver.prepareQueries();  // so irradianceAt is thread-safe below
  parallelFor(probes, kChunkProbes, threads, [&](size_t begin, size_t end) {
    if (cancel && cancel->load()) return;
    std::vector<Ray> rays(kProbeRays);
    std::vector<RayHit> hits(kProbeRays);
    for (size_t p = begin; p < end; ++p) {
      const size_t ix = p % nx, iy = (p / nx) % ny, iz = p / (nx * ny);
      const glm::dvec3 position = origin + glm::dvec3(double(ix), double(iy), double(iz)) * spacing;
      Rng rng(hashIds(seed, kProbeStream, p));
      // Jittered 8 x 8 strata of the uniform-sphere warp: uniform density,
      // less variance in the projection than independent directions.
      for (uint32_t r = 0; r < kProbeRays; ++r) {
        const double u1 = (double(r % kStrata) + rng.uniformDouble()) / kStrata;
        const double u2 = (double(r / kStrata) + rng.uniformDouble()) / kStrata;
        rays[r].origin = vec3(position);
        rays[r].direction = vec3(uniformSphere(u1, u2));
      }
      caster.intersect(rays, hits);
      glm::dvec3 c[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      uint32_t back_hits = 0;
      for (uint32_t r = 0; r < kProbeRays; ++r) {
        const RayHit& h = hits[r];
        const glm::dvec3 d = glm::normalize(dvec(rays[r].direction));
        glm::dvec3 radiance(0.0);
        if (!h.hit()) {
          radiance = skyLuminance(scene.sky, d);
        } else if (h.front || geometry.double_sided[h.triangle]) {
          // Leaving radiance of a Lambertian side: (pi L_e + albedo E) / pi.
          const Rgb e = solver.irradianceAt(h.triangle, h.front, h.u, h.v, InterpolationMode::kVertex);
          radiance = dvec(geometry.emission[h.triangle]) + dvec(geometry.albedo[h.triangle]) * dvec(e) / kPi;
        } else {
          ++back_hits;  // the black back of a single-sided surface
        }
        c[0] += radiance * kY0;
        c[1] += radiance * (kY1 * d.y);
        c[2] += radiance * (kY1 * d.z);
        c[3] += radiance * (kY1 * d.x);
      }
      // Monte Carlo projection: integral of L * Y over the sphere ~ (4 pi / N) sum.
      const double weight = 4.0 * kPi / kProbeRays;
      for (int k = 0; k < 4; ++k) {
        for (int ch = 0; ch < 3; ++ch) grid.sh[p * 12 + size_t(k) * 3 + size_t(ch)] = float(c[k][ch] * weight);
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

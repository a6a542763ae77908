#include "light_reach.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "util/double_math.h"

namespace svit::baker {
namespace {

// Empty margin around the geometry, in voxels: keeps the outside one
// connected shell for the sun and the sky to flood from.
constexpr uint32_t kPadVoxels = 2;

bool bit(const std::vector<uint64_t>& bits, size_t i) { return (bits[i >> 6] >> (i & 63)) & 1u; }
void setBit(std::vector<uint64_t>& bits, size_t i) { bits[i >> 6] |= uint64_t(1) << (i & 63); }

/// Voxel edge for `extent`: a 512th of its diagonal (openings of a few
/// voxels stay open at any scale), coarser when that would exceed the
/// budget (the box's thinnest side counted as at least a thousandth of its
/// longest, so a flat level gets a grid too).
double voxelFor(const glm::dvec3& extent) {
  const double longest = std::max({extent.x, extent.y, extent.z, 1e-6});
  const glm::dvec3 e = glm::max(extent, glm::dvec3(longest * 1e-3));
  const double budget = std::cbrt(e.x * e.y * e.z / double(LightReach::kVoxelBudget)) * 1.05;
  return std::max(budget, glm::length(e) / double(LightReach::kDiagonalVoxels));
}

}  // namespace

bool LightReach::cellOf(const glm::dvec3& p, uint32_t* x, uint32_t* y, uint32_t* z) const {
  const glm::dvec3 q = (p - origin_) / voxel_;
  if (!(q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < nx_ && q.y < ny_ && q.z < nz_)) return false;
  *x = uint32_t(q.x);
  *y = uint32_t(q.y);
  *z = uint32_t(q.z);
  return true;
}

// Conservative raster along the dominant axis d: every column (over the two
// other axes) whose square touches the triangle's projection marks the
// voxels the triangle's plane passes through over that square, within the
// triangle's extent along d.
void LightReach::markTriangle(const glm::dvec3 (&c)[3]) {
  const glm::dvec3 n = glm::cross(c[1] - c[0], c[2] - c[0]);
  const glm::dvec3 an = glm::abs(n);
  const int d = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  if (!(an[d] > 0)) return;
  const int a = (d + 1) % 3, b = (d + 2) % 3;
  const uint32_t size[3] = {nx_, ny_, nz_};
  glm::dvec3 lo = glm::min(c[0], glm::min(c[1], c[2])), hi = glm::max(c[0], glm::max(c[1], c[2]));
  const auto cell = [&](double w, int axis) {
    return uint32_t(std::clamp((w - origin_[axis]) / voxel_, 0.0, double(size[axis] - 1)));
  };
  // Edge functions of the projection, positive inside whatever the winding.
  const double orient = n[d] > 0 ? 1.0 : -1.0;
  double ea[3], eb[3], ec[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3& p = c[k];
    const glm::dvec3& q = c[(k + 1) % 3];
    ea[k] = -(q[b] - p[b]) * orient;
    eb[k] = (q[a] - p[a]) * orient;
    ec[k] = -(ea[k] * p[a] + eb[k] * p[b]);
  }
  const double h = 0.5 * voxel_;
  for (uint32_t i = cell(lo[a], a); i <= cell(hi[a], a); ++i) {
    for (uint32_t j = cell(lo[b], b); j <= cell(hi[b], b); ++j) {
      const double ca = origin_[a] + (i + 0.5) * voxel_, cb = origin_[b] + (j + 0.5) * voxel_;
      bool touches = true;
      for (int k = 0; k < 3 && touches; ++k)
        touches = ea[k] * ca + eb[k] * cb + ec[k] + h * (std::fabs(ea[k]) + std::fabs(eb[k])) >= 0;
      if (!touches) continue;
      // The plane's depth over the column's square: extreme at its corners.
      double dmin = hi[d], dmax = lo[d];
      for (double sa : {-h, h}) {
        for (double sb : {-h, h}) {
          const double depth =
              c[0][d] - (n[a] * (ca + sa - c[0][a]) + n[b] * (cb + sb - c[0][b])) / n[d];
          dmin = std::min(dmin, depth);
          dmax = std::max(dmax, depth);
        }
      }
      dmin = std::max(dmin, lo[d]);
      dmax = std::min(dmax, hi[d]);
      if (dmin > dmax) continue;
      uint32_t cellv[3];
      cellv[a] = i;
      cellv[b] = j;
      for (uint32_t k = cell(dmin, d); k <= cell(dmax, d); ++k) {
        cellv[d] = k;
        setBit(solid_, index(cellv[0], cellv[1], cellv[2]));
      }
    }
  }
}

// A light inside a voxel some surface passes through floods from the free
// voxels around it; one outside the grid is outside every wall, with the sun.
void LightReach::seed(const glm::dvec3& p, std::vector<size_t>& frontier) {
  uint32_t x, y, z;
  if (!cellOf(p, &x, &y, &z)) return seedBoundary(frontier);
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const bool centre = dx == 0 && dy == 0 && dz == 0;
        if (!centre && !bit(solid_, index(x, y, z))) continue;  // free: the centre alone
        const int64_t X = int64_t(x) + dx, Y = int64_t(y) + dy, Z = int64_t(z) + dz;
        if (X < 0 || Y < 0 || Z < 0 || X >= nx_ || Y >= ny_ || Z >= nz_) continue;
        const size_t i = index(uint32_t(X), uint32_t(Y), uint32_t(Z));
        if (bit(solid_, i) || bit(reached_, i)) continue;
        setBit(reached_, i);
        frontier.push_back(i);
      }
    }
  }
}

void LightReach::seedBoundary(std::vector<size_t>& frontier) {
  // The margin is one connected shell of free voxels: its corner floods it.
  if (bit(reached_, 0)) return;
  setBit(reached_, 0);
  frontier.push_back(0);
}

// Every 6-connected set of free voxels the flood did not reach that has at
// most `max_voxels` counts as reached: the gaps between the leaves of a
// plant or the folds of a curtain, closed at this voxel size, are no room
// sealed from the light. Returns how many were opened.
size_t LightReach::openSmallPockets(size_t max_voxels) {
  std::vector<uint64_t> seen = reached_;
  std::vector<size_t> pocket;
  std::vector<VoxelRun> runs;
  size_t opened = 0;
  for (size_t word = 0; word < seen.size(); ++word) {
    for (uint64_t free = ~(solid_[word] | seen[word]); free != 0;
         free = ~(solid_[word] | seen[word])) {
      const size_t i = (word << 6) + size_t(__builtin_ctzll(free));
      setBit(seen, i);
      pocket.assign(1, i);
      runs.clear();
      if (floodVoxels(rows_, solid_, seen, pocket, &runs) > max_voxels) continue;
      for (const auto& [first, length] : runs)
        for (size_t j = first; j < first + length; ++j) setBit(reached_, j);
      ++opened;
    }
  }
  return opened;
}

// The bits of each row past nx are solid: a run along x stops in its row.
void LightReach::markRowPadding() {
  for (size_t row = 0; row < size_t(ny_) * nz_; ++row)
    for (size_t x = nx_; x < rows_.rowBits(); ++x) setBit(solid_, row * rows_.rowBits() + x);
}

LightReach LightReach::build(const BakeGeometry& geometry, const std::vector<LightSource>& lights,
                             double max_voxel_m) {
  const auto start = std::chrono::steady_clock::now();
  LightReach r;
  const glm::dvec3 lo = dvec(geometry.bounds.min), hi = dvec(geometry.bounds.max);
  r.voxel_ = voxelFor(hi - lo);
  r.stats_.voxel_m = r.voxel_;
  if (!(r.voxel_ <= max_voxel_m) || geometry.triangleCount() == 0) return r;
  r.origin_ = lo - double(kPadVoxels) * r.voxel_;
  const glm::dvec3 cells = glm::ceil((hi - lo) / r.voxel_) + 2.0 * kPadVoxels + 1.0;
  r.nx_ = uint32_t(cells.x);
  r.ny_ = uint32_t(cells.y);
  r.nz_ = uint32_t(cells.z);
  r.rows_ = VoxelRows::forSize(r.nx_, r.ny_, r.nz_);
  const size_t count = r.rows_.bits();
  r.solid_.assign(r.rows_.words(), 0);
  r.reached_.assign(r.rows_.words(), 0);
  r.markRowPadding();
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const glm::dvec3 c[3] = {dvec(geometry.corner(t, 0)), dvec(geometry.corner(t, 1)),
                             dvec(geometry.corner(t, 2))};
    r.markTriangle(c);
  }
  std::vector<size_t> frontier;
  for (const LightSource& light : lights) {
    if (light.kind == LightKind::kPoint || light.kind == LightKind::kSpot)
      r.seed(light.position, frontier);
    else
      r.seedBoundary(frontier);
  }
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const Rgb& e = geometry.emission[t];
    if (!(e.r > 0 || e.g > 0 || e.b > 0)) continue;
    const glm::dvec3 centroid =
        (dvec(geometry.corner(t, 0)) + dvec(geometry.corner(t, 1)) + dvec(geometry.corner(t, 2))) /
        3.0;
    const glm::dvec3 n = dvec(geometry.normals[t]);
    r.seed(centroid + n * r.voxel_, frontier);
    if (geometry.double_sided[t]) r.seed(centroid - n * r.voxel_, frontier);
  }
  floodVoxels(r.rows_, r.solid_, r.reached_, frontier);
  r.stats_.sealed_pockets_opened = r.openSmallPockets(kMaxPocketVoxels);
  size_t solid = 0, reached = 0;
  for (uint64_t word : r.solid_) solid += size_t(__builtin_popcountll(word));
  for (uint64_t word : r.reached_) reached += size_t(__builtin_popcountll(word));
  r.stats_.enabled = true;
  r.stats_.nx = r.nx_;
  r.stats_.ny = r.ny_;
  r.stats_.nz = r.nz_;
  r.stats_.reached_fraction = count > solid ? double(reached) / double(count - solid) : 0;
  r.stats_.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// The voxel in front of the surface at p, past p's own voxel (which the
// surface marks). Solid too: another surface within a voxel walls p in (a
// room's very corner, the floor along a wall's foot) and what lies past it
// may be across a wall, so it tells nothing.
LightReachVerdict LightReach::verdict(const glm::dvec3& p, const glm::dvec3& n) const {
  if (!stats_.enabled) return LightReachVerdict::kReached;
  // p's own voxel is taken a hair in front of p: a surface on a voxel
  // boundary fills the voxel in front, and p, rounded to float, may lie
  // just behind it.
  uint32_t x0, y0, z0;
  if (!cellOf(p + n * (1e-3 * voxel_), &x0, &y0, &z0)) return LightReachVerdict::kReached;
  const size_t own = index(x0, y0, z0);
  for (double step = 0.25; step <= 2.0; step += 0.25) {
    uint32_t x, y, z;
    if (!cellOf(p + n * (step * voxel_), &x, &y, &z)) return LightReachVerdict::kReached;
    const size_t i = index(x, y, z);
    if (i == own) continue;
    if (bit(solid_, i)) return LightReachVerdict::kWalledIn;
    return bit(reached_, i) ? LightReachVerdict::kReached : LightReachVerdict::kUnreached;
  }
  return LightReachVerdict::kWalledIn;
}

}  // namespace svit::baker

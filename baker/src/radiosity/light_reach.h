#pragma once
// Where light can reach: the free space of the level on a voxel grid,
// flooded from every baked light (a lamp's voxel, an emitter's front, the
// outside for the sun, the sky and directional lights). A surface point
// whose front looks into space no flood reached lies in a sealed room or
// under a wall: no light arrives there, whatever the hierarchical solution
// spread onto its element from the lit part (an element of a floor that
// runs under a wall from the sunlit outside into a closed room, a cluster
// holding both rooms of a partition). The solver shoots no light from such
// points and the final gather reads them as black
// (docs/architecture/baker-radiosity.md "Leaks").
//
// Surfaces mark every voxel they pass through (a conservative raster along
// each triangle's dominant axis), so even a wall of zero thickness is a
// 6-connected barrier; the cost is that an opening narrower than about two
// voxels closes. The voxel is a 512th of the level's diagonal (coarser only
// past a budget of voxels), and the guard stays off where the voxel would
// be coarser than RadiositySettings::leak_guard_max_voxel_m, as it would
// close doors and windows.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "light_sources.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/radiosity.h"
#include "voxel_flood.h"

namespace svit::baker {

struct LightReachStats {
  bool enabled = false;
  double voxel_m = 0;
  uint32_t nx = 0, ny = 0, nz = 0;
  double reached_fraction = 0;       ///< of the free voxels
  size_t sealed_pockets_opened = 0;  ///< unreached spaces too small to be rooms
  double seconds = 0;
};

class LightReach {
 public:
  /// Voxels along the level's bounding-box diagonal.
  static constexpr double kDiagonalVoxels = 512;
  /// Most voxels of the grid (two bits each).
  static constexpr uint64_t kVoxelBudget = 96'000'000;
  /// Unreached spaces of at most this many voxels count as reached (4^3:
  /// a room is larger, the gaps between a plant's leaves are not).
  static constexpr size_t kMaxPocketVoxels = 64;

  LightReach() = default;
  /// Voxelizes `geometry` and floods from `lights` and the emissive
  /// triangles. Deterministic; threads are not used.
  /// Off (every point reached) where the voxel would be coarser than
  /// `max_voxel_m`.
  static LightReach build(const BakeGeometry& geometry, const std::vector<LightSource>& lights,
                          double max_voxel_m);

  /// Whether light can arrive at surface point `p` from the side `n` (unit)
  /// faces: the voxel in front of `p`'s own along `n` was reached (true
  /// when the guard is off, or when that voxel is solid too: another
  /// surface within a voxel walls `p` in and what lies past it may be
  /// across a wall).
  bool reaches(const glm::dvec3& p, const glm::dvec3& n) const {
    return verdict(p, n) != LightReachVerdict::kUnreached;
  }
  /// The verdict behind `reaches` (kReached when the guard is off).
  LightReachVerdict verdict(const glm::dvec3& p, const glm::dvec3& n) const;
  const LightReachStats& stats() const { return stats_; }

 private:
  size_t index(uint32_t x, uint32_t y, uint32_t z) const { return rows_.index(x, y, z); }
  bool cellOf(const glm::dvec3& p, uint32_t* x, uint32_t* y, uint32_t* z) const;
  void markTriangle(const glm::dvec3 (&c)[3]);
  void markRowPadding();
  void seed(const glm::dvec3& p, std::vector<size_t>& frontier);
  void seedBoundary(std::vector<size_t>& frontier);
  size_t openSmallPockets(size_t max_voxels);

  LightReachStats stats_;
  glm::dvec3 origin_{0.0};
  double voxel_ = 0;
  uint32_t nx_ = 0, ny_ = 0, nz_ = 0;
  VoxelRows rows_;  ///< how the bitsets lay the grid out (rows padded to words)
  std::vector<uint64_t> solid_, reached_;  ///< bitsets over the grid
};

}  // namespace svit::baker

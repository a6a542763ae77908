#pragma once
// Scanline flood fill over a 3-D bit grid (light_reach.h's voxels): a seed
// grows into the run of free voxels along its row, word by word, and each
// run seeds the free runs beside it in the four neighbouring rows. Marks
// exactly the voxels a breadth-first flood through 6-connected free voxels
// marks, touching each row's words once per run instead of pushing every
// voxel (docs/architecture/baker-radiosity.md "Leaks" has the timings).
// Internal.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace svit::baker {

/// A grid of nx x ny x nz voxels stored as bits, x fastest, each row of x
/// padded to whole 64-bit words with at least one bit past nx that the
/// solid set must hold, so no run leaves its row.
struct VoxelRows {
  uint32_t row_words = 0;  ///< (nx + 64) / 64
  uint32_t ny = 0, nz = 0;

  static VoxelRows forSize(uint32_t nx, uint32_t ny, uint32_t nz) {
    return {(nx + 64) / 64, ny, nz};
  }
  size_t rowBits() const { return size_t(row_words) * 64; }
  size_t bits() const { return rowBits() * ny * nz; }
  size_t words() const { return size_t(row_words) * ny * nz; }
  size_t index(uint32_t x, uint32_t y, uint32_t z) const {
    return (size_t(z) * ny + y) * rowBits() + x;
  }
};

/// A run of marked voxels along a row: its first bit and its length.
using VoxelRun = std::pair<size_t, uint32_t>;

/// Floods from `seeds` (bit indices already set in `marks`) through the
/// voxels clear in both `solid` and `marks`, setting them in `marks`.
/// Returns the voxels it marked, seeds included; with `runs`, appends
/// every run it marked. `seeds` is used as the work stack.
size_t floodVoxels(const VoxelRows& grid, const std::vector<uint64_t>& solid,
                   std::vector<uint64_t>& marks, std::vector<size_t>& seeds,
                   std::vector<VoxelRun>* runs = nullptr);

}  // namespace svit::baker

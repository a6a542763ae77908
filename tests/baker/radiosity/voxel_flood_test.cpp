// The scanline flood (voxel_flood.h) against a breadth-first flood through
// 6-connected free voxels, on random grids whose rows end inside a word, at
// its last bit and one past it, so runs meet the row padding and the word
// edges everywhere.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "radiosity/voxel_flood.h"

namespace svit::baker {
namespace {

bool bit(const std::vector<uint64_t>& bits, size_t i) { return (bits[i >> 6] >> (i & 63)) & 1u; }
void setBit(std::vector<uint64_t>& bits, size_t i) { bits[i >> 6] |= uint64_t(1) << (i & 63); }

struct Grid {
  uint32_t nx, ny, nz;
  VoxelRows rows;
  std::vector<uint64_t> solid;
};

// Solid with probability `density` (and the rows' padding), from `seed`.
Grid randomGrid(uint32_t nx, uint32_t ny, uint32_t nz, double density, uint32_t seed) {
  Grid g{nx, ny, nz, VoxelRows::forSize(nx, ny, nz), {}};
  g.solid.assign(g.rows.words(), 0);
  std::mt19937 rng(seed);
  std::bernoulli_distribution solid(density);
  for (uint32_t z = 0; z < nz; ++z)
    for (uint32_t y = 0; y < ny; ++y)
      for (uint32_t x = 0; x < uint32_t(g.rows.rowBits()); ++x)
        if (x >= nx || solid(rng)) setBit(g.solid, g.rows.index(x, y, z));
  return g;
}

// Breadth-first through 6-connected free voxels from `seed`, voxel by voxel.
std::vector<uint64_t> breadthFirst(const Grid& g, uint32_t sx, uint32_t sy, uint32_t sz) {
  std::vector<uint64_t> marks(g.rows.words(), 0);
  std::vector<uint32_t> queue = {sx, sy, sz};
  setBit(marks, g.rows.index(sx, sy, sz));
  for (size_t q = 0; q < queue.size(); q += 3) {
    const int64_t p[3] = {queue[q], queue[q + 1], queue[q + 2]};
    const int64_t size[3] = {g.nx, g.ny, g.nz};
    for (int axis = 0; axis < 3; ++axis) {
      for (int step : {-1, 1}) {
        int64_t n[3] = {p[0], p[1], p[2]};
        n[axis] += step;
        if (n[axis] < 0 || n[axis] >= size[axis]) continue;
        const size_t i = g.rows.index(uint32_t(n[0]), uint32_t(n[1]), uint32_t(n[2]));
        if (bit(g.solid, i) || bit(marks, i)) continue;
        setBit(marks, i);
        queue.insert(queue.end(), {uint32_t(n[0]), uint32_t(n[1]), uint32_t(n[2])});
      }
    }
  }
  return marks;
}

size_t countBits(const std::vector<uint64_t>& bits) {
  size_t n = 0;
  for (uint64_t word : bits) n += size_t(__builtin_popcountll(word));
  return n;
}

TEST(VoxelFlood, MarksWhatABreadthFirstFloodMarksAtEveryRowLength) {
  uint32_t seed = 1;
  for (uint32_t nx : {1u, 5u, 63u, 64u, 65u, 127u, 130u}) {
    for (double density : {0.0, 0.2, 0.35, 0.5}) {
      const Grid g = randomGrid(nx, 6, 5, density, seed++);
      const uint32_t sx = nx / 2, sy = 3, sz = 2;
      const size_t start = g.rows.index(sx, sy, sz);
      if (bit(g.solid, start)) continue;
      const std::vector<uint64_t> expected = breadthFirst(g, sx, sy, sz);
      std::vector<uint64_t> marks(g.rows.words(), 0);
      setBit(marks, start);
      std::vector<size_t> seeds = {start};
      std::vector<VoxelRun> runs;
      const size_t marked = floodVoxels(g.rows, g.solid, marks, seeds, &runs);
      EXPECT_EQ(marks, expected) << "nx " << nx << ", density " << density;
      EXPECT_EQ(marked, countBits(expected)) << "nx " << nx << ", density " << density;
      size_t in_runs = 0;
      for (const VoxelRun& run : runs) {
        in_runs += run.second;
        for (size_t i = run.first; i < run.first + run.second; ++i) EXPECT_TRUE(bit(expected, i));
      }
      EXPECT_EQ(in_runs, marked);
    }
  }
}

TEST(VoxelFlood, StopsAtMarksAlreadySetAndCountsOnlyWhatItMarks) {
  const Grid g = randomGrid(70, 4, 3, 0.0, 7);  // all free
  std::vector<uint64_t> marks(g.rows.words(), 0);
  // A marked wall at z = 1.
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 70; ++x) setBit(marks, g.rows.index(x, y, 1));
  const size_t start = g.rows.index(3, 2, 0);
  setBit(marks, start);
  std::vector<size_t> seeds = {start};
  EXPECT_EQ(floodVoxels(g.rows, g.solid, marks, seeds), 70u * 4u);  // the z = 0 slice alone
  EXPECT_FALSE(bit(marks, g.rows.index(3, 2, 2)));
}

}  // namespace
}  // namespace svit::baker

#include "voxel_flood.h"

#include <algorithm>

namespace svit::baker {
namespace {

uint64_t freeBits(const std::vector<uint64_t>& solid, const std::vector<uint64_t>& marks,
                  size_t word) {
  return ~(solid[word] | marks[word]);
}

/// Ones from bit 0 of `bits` up to its first zero (64 when all are ones).
uint32_t lowOnes(uint64_t bits) { return ~bits == 0 ? 64u : uint32_t(__builtin_ctzll(~bits)); }
/// Ones from bit 63 of `bits` down to its first zero.
uint32_t highOnes(uint64_t bits) { return ~bits == 0 ? 64u : uint32_t(__builtin_clzll(~bits)); }
/// Bits [from, from + count) of a word.
uint64_t span(uint32_t from, uint32_t count) {
  return (count >= 64 ? ~uint64_t(0) : (uint64_t(1) << count) - 1) << from;
}

/// Marks the free bits after `last` along its row; returns the last marked.
/// The row's padding bit is solid, so the run stops inside the row.
size_t growRight(const std::vector<uint64_t>& solid, std::vector<uint64_t>& marks, size_t last) {
  while (true) {
    const size_t next = last + 1, word = next >> 6;
    const uint32_t bit = uint32_t(next & 63);
    const uint32_t ones = lowOnes(freeBits(solid, marks, word) >> bit);
    const uint32_t count = ones > 64 - bit ? 64 - bit : ones;
    if (count == 0) return last;
    marks[word] |= span(bit, count);
    last = next + count - 1;
    if (bit + count < 64) return last;
  }
}

/// Marks the free bits before `first` along its row (back to the row's
/// start: the padding bit of the row before is solid); returns the first marked.
size_t growLeft(const std::vector<uint64_t>& solid, std::vector<uint64_t>& marks, size_t first) {
  while (first > 0) {
    const size_t previous = first - 1, word = previous >> 6;
    const uint32_t bit = uint32_t(previous & 63);
    const uint32_t ones = highOnes(freeBits(solid, marks, word) << (63 - bit));
    const uint32_t count = ones > bit + 1 ? bit + 1 : ones;
    if (count == 0) return first;
    marks[word] |= span(bit + 1 - count, count);
    first = previous + 1 - count;
    if (count < bit + 1) return first;
  }
  return first;
}

/// Seeds every free run of the row `row_start` holds over bits [x0, x1]
/// (offsets within the row): marks each run's first bit and pushes it.
void seedRow(const std::vector<uint64_t>& solid, std::vector<uint64_t>& marks, size_t row_start,
             size_t x0, size_t x1, std::vector<size_t>& seeds, size_t& marked) {
  for (size_t word = (row_start + x0) >> 6; word <= (row_start + x1) >> 6; ++word) {
    const size_t lo = word << 6;
    const size_t from = std::max(lo, row_start + x0), to = std::min(lo + 63, row_start + x1);
    uint64_t bits =
        freeBits(solid, marks, word) & span(uint32_t(from - lo), uint32_t(to - from + 1));
    while (bits != 0) {
      const size_t first = lo + size_t(__builtin_ctzll(bits));
      marks[word] |= uint64_t(1) << (first - lo);
      seeds.push_back(first);
      ++marked;
      bits &= bits + (bits & (~bits + 1));  // clears the lowest run of ones
    }
  }
}

}  // namespace

size_t floodVoxels(const VoxelRows& grid, const std::vector<uint64_t>& solid,
                   std::vector<uint64_t>& marks, std::vector<size_t>& seeds,
                   std::vector<VoxelRun>* runs) {
  const size_t row_bits = grid.rowBits();
  size_t marked = seeds.size();
  while (!seeds.empty()) {
    const size_t seed = seeds.back();
    seeds.pop_back();
    const size_t first = growLeft(solid, marks, seed), last = growRight(solid, marks, seed);
    marked += last - first;
    if (runs) runs->push_back({first, uint32_t(last - first + 1)});
    const size_t row = first / row_bits, row_start = row * row_bits;
    const size_t y = row % grid.ny, z = row / grid.ny;
    const size_t x0 = first - row_start, x1 = last - row_start;
    if (y > 0) seedRow(solid, marks, row_start - row_bits, x0, x1, seeds, marked);
    if (y + 1 < grid.ny) seedRow(solid, marks, row_start + row_bits, x0, x1, seeds, marked);
    const size_t slice = row_bits * grid.ny;
    if (z > 0) seedRow(solid, marks, row_start - slice, x0, x1, seeds, marked);
    if (z + 1 < grid.nz) seedRow(solid, marks, row_start + slice, x0, x1, seeds, marked);
  }
  return marked;
}

}  // namespace svit::baker

#pragma once
// Running per-texel sums of a bake's lighting passes: their mean is the
// lightmap; the spread of the passes, or the pages of the even passes
// against those of the odd ones, its error estimate. A sharded bake's shards each
// keep one over their texels; the merge puts the sums side by side and gets
// the same mean, bit for bit, as one bake (sharded_bake.h). Internal.

#include <array>
#include <cstdint>
#include <vector>

#include "svit/baker/texel_lighting.h"

namespace svit::baker {

/// Sums over texels of the passes' spread, what the relative error needs;
/// adding those of disjoint texel sets gives that of their union.
struct PassSpread {
  double variance_sum = 0;  ///< sum over texels of the variance of their mean, lux^2
  double mean_sum = 0;      ///< sum over texels of their mean luminance, lux
  uint64_t texels = 0;

  /// RMS standard error of the texel means over the mean texel value; 1
  /// with fewer than two passes (no spread to measure yet).
  double relativeError(uint32_t passes) const;
};

class TexelAccumulator {
 public:
  TexelAccumulator() = default;
  /// The accumulator whose sums over `passes` passes are `sums`, over the
  /// odd ones (1, 3, ...) `odd_sums`, and over those of quarters 2 and 3
  /// (passes 2, 6, ... and 3, 7, ...) `quarter_sums` (its spread unknown:
  /// spread() of it is meaningless).
  TexelAccumulator(std::vector<TexelIrradiance> sums, std::vector<TexelIrradiance> odd_sums,
                   std::array<std::vector<TexelIrradiance>, 2> quarter_sums, uint32_t passes);

  void add(const std::vector<TexelIrradiance>& pass);
  std::vector<TexelIrradiance> mean() const;
  /// The mean of the odd passes (1, 3, ...), or of the even ones (0, 2, ...).
  std::vector<TexelIrradiance> halfMean(bool odd) const;
  /// halfMean(false) - halfMean(true), per texel.
  std::vector<TexelIrradiance> halfDifference() const;
  uint32_t halfPasses(bool odd) const { return odd ? passes_ / 2 : passes_ - passes_ / 2; }
  /// A half's own two quarters, its first minus its second (passes 0, 4,
  /// ... minus 2, 6, ... for the even half; 1, 5, ... minus 3, 7, ... for
  /// the odd one): noise of that half only, for the filter's guide that
  /// half gives the other (filtered_passes.h). Zero without both quarters.
  std::vector<TexelIrradiance> quarterDifference(bool odd) const;
  /// Passes in quarter q (those p with p % 4 == q).
  uint32_t quarterPasses(uint32_t q) const { return passes_ > q ? (passes_ - q + 3) / 4 : 0; }
  PassSpread spread() const;
  double relativeError() const { return spread().relativeError(passes_); }
  const std::vector<TexelIrradiance>& sums() const { return sum_; }
  const std::vector<TexelIrradiance>& oddSums() const { return odd_sum_; }
  const std::array<std::vector<TexelIrradiance>, 2>& quarterSums() const { return quarter_sum_; }
  uint32_t passes() const { return passes_; }

 private:
  std::vector<TexelIrradiance> sum_, odd_sum_;
  std::array<std::vector<TexelIrradiance>, 2> quarter_sum_;  ///< passes 2, 6, ... and 3, 7, ...
  std::vector<double> sum_y_, sum_y2_;
  uint32_t passes_ = 0;
};

}  // namespace svit::baker

// The lightmap's error estimate (lightmap_error.h).

#include "lightmap_error.h"

#include <algorithm>
#include <cmath>

#include "svit/baker/lightmap_pages.h"
#include "util/double_math.h"

namespace svit::baker {
namespace {

// The luminance sum over the texels of `mean`; what the estimates are
// relative to.
double meanLuminanceSum(const std::vector<TexelIrradiance>& mean) {
  double sum = 0;
  for (const TexelIrradiance& t : mean) sum += luminanceOf(t.direct) + luminanceOf(t.indirect);
  return sum;
}

// The filter's bias, relative (filtered_passes.h): what the halves cannot
// see, since both are filtered alike. Floored at 0: its estimate is noisy.
double filterBias(const FilteredPasses& passes, double luminance_sum) {
  const double texels = double(passes.mean.size());
  return std::sqrt(std::max(0.0, passes.bias_squares) / texels) / (luminance_sum / texels);
}

struct SplitHalf {
  double noise = 0;        ///< the halves' difference scaled to the mean, relative
  double filter_bias = 0;  ///< filterBias
};

// The split-half estimate of `passes`, the passes in `accumulator` (two or more).
SplitHalf splitHalfError(const LoadedLevel& level, const AtlasTexels& atlas,
                         const BakeOptions& options, const TexelAccumulator& accumulator,
                         const FilteredPasses& passes) {
  // Dilation and seams are linear, so the pages of the halves' difference
  // are the difference of their pages: one build, not two.
  const LightmapPages difference =
      buildLightmapPages(level.geometry, atlas.atlas, atlas.texels, passes.difference,
                         bakePageSettings(atlas, options));
  double squares = 0;
  for (const TexelSample& s : atlas.texels.samples) {
    const double d = luminanceOf(difference.images[s.page].texel(int(s.x), int(s.y)));
    squares += d * d;
  }
  const double sum = meanLuminanceSum(passes.mean);
  if (!(sum > 0)) return {};
  const double texels = double(atlas.texels.samples.size());
  // Per-pass noise s: the halves differ by s^2 (1/n_even + 1/n_odd) in
  // variance, the mean of all n passes has s^2 / n, so the mean's error is
  // the difference's times sqrt(n_even * n_odd) / n.
  const double n_even = accumulator.halfPasses(false), n_odd = accumulator.halfPasses(true);
  const double to_mean = std::sqrt(n_even * n_odd) / (n_even + n_odd);
  SplitHalf out;
  out.noise = std::sqrt(squares / texels) / (sum / texels) * to_mean;
  out.filter_bias = filterBias(passes, sum);
  return out;
}

}  // namespace

LightmapErrorEstimator::LightmapErrorEstimator(const LoadedLevel& level, const AtlasTexels& atlas,
                                               const RadiositySolver& solver,
                                               const BakeOptions& options)
    : level_(level),
      atlas_(atlas),
      options_(options),
      unseen_solver_error_(solver.hasSolutionHalves() ? 0.0 : solver.estimatedRelativeError()) {}

double LightmapErrorEstimator::texelSpread(double texel_error) const {
  return std::hypot(texel_error, unseen_solver_error_);
}

void LightmapErrorEstimator::estimate(const TexelAccumulator& accumulator, double texel_error,
                                      const FilteredPasses* split_half, ErrorPoint& point) {
  const double spread = texelSpread(texel_error);
  if (split_half != nullptr && accumulator.passes() >= 2) {
    const SplitHalf halves = splitHalfError(level_, atlas_, options_, accumulator, *split_half);
    point.est_rel_error =
        std::sqrt(halves.noise * halves.noise + halves.filter_bias * halves.filter_bias +
                  unseen_solver_error_ * unseen_solver_error_);
    point.est_filter_bias = halves.filter_bias;
    point.estimate = ErrorEstimate::kSplitHalfPages;
    ratio_ = spread > 0 ? point.est_rel_error / spread : 0.0;
    if (!split_half->filtered) unfiltered_ratio_ = ratio_;
  } else if (ratio_ > 0) {
    point.est_rel_error = spread * ratio_;
    point.estimate = ErrorEstimate::kScaledTexelSpread;
  } else {
    point.est_rel_error = spread;
    point.estimate = ErrorEstimate::kTexelSpread;
  }
}

void LightmapErrorEstimator::scaleEarlier(std::vector<ErrorPoint>& series, size_t first) const {
  if (!(ratio_ > 0)) return;
  for (size_t i = first; i < series.size(); ++i) {
    if (series[i].estimate != ErrorEstimate::kTexelSpread) continue;
    const bool unfiltered = i - first + 2 < kFilteredPasses && unfiltered_ratio_ > 0;
    series[i].est_rel_error *= unfiltered ? unfiltered_ratio_ : ratio_;
    series[i].estimate = ErrorEstimate::kScaledTexelSpread;
  }
}

}  // namespace svit::baker

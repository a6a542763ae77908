// The lightmap's error estimate (lightmap_error.h).

#include "lightmap_error.h"

#include <cmath>

#include "svit/baker/lightmap_pages.h"
#include "double_math.h"

namespace svit::baker {
namespace {

// The split-half estimate after the passes in `accumulator` (two or more),
// the solution's unseen noise `unseen_solver_error` added.
double splitHalfError(const LoadedLevel& level, const AtlasTexels& atlas,
                      const BakeOptions& options, const TexelAccumulator& accumulator,
                      double unseen_solver_error) {
  // The page build is linear (filter weights, dilation and seams depend on
  // the geometry and the mean's guide only), so the pages of the halves'
  // difference are the difference of their pages: one build, not two.
  const LightmapPages difference =
      buildLightmapPages(level.geometry, atlas.atlas, atlas.texels, accumulator.halfDifference(),
                         bakePageSettings(atlas, options, accumulator));
  const std::vector<TexelIrradiance> mean = accumulator.mean();
  double squares = 0, sum = 0;
  for (size_t i = 0; i < atlas.texels.samples.size(); ++i) {
    const TexelSample& s = atlas.texels.samples[i];
    const double d = luminanceOf(difference.images[s.page].texel(int(s.x), int(s.y)));
    squares += d * d;
    sum += luminanceOf(mean[i].direct) + luminanceOf(mean[i].indirect);
  }
  if (!(sum > 0)) return unseen_solver_error;
  const double texels = double(atlas.texels.samples.size());
  const double halves = std::sqrt(squares / texels) / (sum / texels);
  // Per-pass noise s: the halves differ by s^2 (1/n_even + 1/n_odd) in
  // variance, the mean of all n passes has s^2 / n, so the mean's error is
  // the difference's times sqrt(n_even * n_odd) / n.
  const double n_even = accumulator.halfPasses(false), n_odd = accumulator.halfPasses(true);
  const double n = n_even + n_odd;
  return std::hypot(halves * std::sqrt(n_even * n_odd) / n, unseen_solver_error);
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
                                      bool split_half, ErrorPoint& point) {
  const double spread = texelSpread(texel_error);
  if (split_half && accumulator.passes() >= 2) {
    point.est_rel_error =
        splitHalfError(level_, atlas_, options_, accumulator, unseen_solver_error_);
    point.estimate = ErrorEstimate::kSplitHalfPages;
    ratio_ = spread > 0 ? point.est_rel_error / spread : 0.0;
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
    series[i].est_rel_error *= ratio_;
    series[i].estimate = ErrorEstimate::kScaledTexelSpread;
  }
}

}  // namespace svit::baker

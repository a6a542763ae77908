#pragma once
// The lightmap's error estimate, what report.json's error-versus-time
// series and its lightmap.est_rel_error carry. Two estimates of the error
// of the mean of the lighting passes:
// - the texel spread: each texel's variance over the passes. Cheap (every
//   pass), but pessimistic where the page filter averages the noise away,
//   and blind to the radiosity solution's noise when every pass gathers
//   from the same solution (the solver's own estimate is added then).
// - the split-half: the pages of the even passes against those of the odd
//   ones, each filtered as the pages written and gathered from its own
//   half of the solver's passes (SolutionHalf), so it counts what is left
//   after the filter and the solution's noise too. One page build a call
//   (of the halves' difference). The halves are filtered alike, so what
//   the filter shifts (light it smooths across an edge it took for noise)
//   is invisible to them; it is estimated apart and added in quadrature:
//   the filter's change to the mean less the part of it that is noise,
//   which its change to the halves' difference measures. Both need the
//   filter crosswise (filtered_passes.h): a self-guided one hides its noise
//   from the halves.
// Internal.

#include <vector>

#include "bake_stages.h"
#include "lightmap/filtered_passes.h"
#include "lightmap/texel_accumulator.h"
#include "svit/baker/radiosity.h"

namespace svit::baker {

// The estimates of a bake's passes in order: the split-half where asked,
// and between, the texel spread scaled by the ratio of the two at the
// last pass that measured both. The ratio drifts slowly: the gather's
// noise falls as one over the square root of the pass count in both, the
// solution's does not fall and only the split-half sees it.
class LightmapErrorEstimator {
 public:
  /// `options`: how the bake builds its pages from the texels.
  LightmapErrorEstimator(const LoadedLevel& level, const AtlasTexels& atlas,
                         const RadiositySolver& solver, const BakeOptions& options);

  /// The texel-spread estimate from the texels' relative spread `texel_error`.
  double texelSpread(double texel_error) const;

  /// `point`'s estimate after the passes in `accumulator`, whose texels'
  /// relative spread is `texel_error` (TexelAccumulator::relativeError, or
  /// a sharded bake's merged spreads): the split-half of `split_half`
  /// (bakeLighting of those passes) when given and there are two or more
  /// passes.
  void estimate(const TexelAccumulator& accumulator, double texel_error,
                const FilteredPasses* split_half, ErrorPoint& point);
  /// Scales the unscaled texel-spread estimates of `series` from index
  /// `first` on (those of two or more passes, made before any split-half)
  /// by the last split-half's ratio, if one was measured; those of fewer
  /// passes than the filter needs (kFilteredPasses) by the last unfiltered
  /// split-half's, if one was.
  void scaleEarlier(std::vector<ErrorPoint>& series, size_t first) const;

 private:
  const LoadedLevel& level_;
  const AtlasTexels& atlas_;
  const BakeOptions& options_;
  /// The solution's noise where the passes' spread cannot see it (frozen
  /// into every pass when there are no halves to gather from), else 0.
  double unseen_solver_error_ = 0;
  double ratio_ = 0;  ///< split-half over texel spread at the last split-half; 0: none yet
  double unfiltered_ratio_ = 0;  ///< the same at the last split-half of unfiltered passes
};

}  // namespace svit::baker

#pragma once
// A bake's lighting passes as its pages hold them: the indirect light of
// each half of the passes (the even ones, the odd ones) filtered on its
// own, the two halves then averaged; and what the split-half error
// estimate reads (lightmap_error.h): the filtered halves' difference and
// the filter's bias. Internal.
//
// Each half on its own, guided by itself only (its indirect luminance, its
// noise from its own two quarters: passes 0, 4, ... against 2, 6, ...; 1,
// 5, ... against 3, 7, ...), so the two filtered halves are independent:
// their difference measures the noise the filter leaves, whatever the
// filter does. A filter whose weights come from both halves (one guide made
// from the mean, or each half guided by the other) adapts to the very
// noise the halves' difference measures, and that difference shrinks more
// than the mean's noise does: such an estimate reads well below the true
// error, while the same estimate of a filter whose weights ignore the light
// stays exact (docs/bench/estimate_honesty.md).
//
// The bias, what the filter shifts alike in both halves (light smoothed
// across an edge it took for noise), is invisible to their difference. Its
// square is estimated per texel by the product of the two halves' shifts,
// (filtered even - even) (filtered odd - odd): independent halves make
// that product's expectation the square of the expected shift.

#include <array>
#include <cstdint>
#include <vector>

#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "texel_accumulator.h"

namespace svit::baker {

/// The passes the filter needs: two in each half, so that each half's
/// guide has its own two quarters to tell its noise by.
inline constexpr uint32_t kFilteredPasses = 4;

struct FilteredPasses {
  std::vector<TexelIrradiance> mean;        ///< the lightmap's texels
  std::vector<TexelIrradiance> difference;  ///< even half minus odd half, each as filtered
  /// Sum over the texels of the halves' indirect luminance shifts'
  /// product: the filter's squared bias, lux^2 (0 unfiltered; may be < 0
  /// where noise outweighs it).
  double bias_squares = 0;
  bool filtered = false;    ///< false: the raw mean and difference
  double noise_sigmas = 0;  ///< the filter's k (PageSettings::filter_noise_sigmas); 0 unfiltered
};

/// The filter strengths a bake chooses among (PageSettings::filter_noise_sigmas):
/// a larger k smooths more noise and more of the light's real detail. The
/// best k falls as passes are added and the noise falls while the bias
/// stays; the split-half estimate tracks the true error at every k
/// (docs/bench/estimate_honesty.md), so a bake can choose by it.
inline constexpr std::array<double, 4> kFilterNoiseSigmaChoices = {0.75, 1.0, 1.5, 2.0};

/// The passes in `accumulator` filtered as `settings` says (edge_aware_filter,
/// filter_radius_texels, filter_noise_sigmas, filter_normal_power; its
/// guide is ignored: each half makes its own). Unfiltered where the settings
/// ask for no filter or there are fewer than kFilteredPasses.
FilteredPasses filterPasses(const LightmapAtlas& atlas, const TexelSet& texels,
                            const TexelAccumulator& accumulator, const PageSettings& settings);

/// filterPasses at each k of `choices`, keeping the one whose estimated
/// error is least: the halves' noise and the bias, over the texels (the
/// estimate is honest at every k, so its least is the filter to keep).
FilteredPasses bestFilteredPasses(const LightmapAtlas& atlas, const TexelSet& texels,
                                  const TexelAccumulator& accumulator, const PageSettings& settings,
                                  const std::array<double, 4>& choices);

/// One half's guide for its own filter: its indirect luminance, and that
/// half-mean's standard error from its own quarters' difference (squares
/// averaged over the filter's window, radius `radius`, same chart and side:
/// one texel's difference is a single sample). Nothing of the other half
/// is in it.
FilterGuide halfGuide(const LightmapAtlas& atlas, const TexelSet& texels,
                      const TexelAccumulator& accumulator, bool odd, int radius);

}  // namespace svit::baker

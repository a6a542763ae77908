// A bake's lighting passes, each half filtered on its own (filtered_passes.h).

#include "filtered_passes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "atlas/texel_neighbours.h"
#include "util/double_math.h"

namespace svit::baker {
namespace {

// `lighting` with its indirect light replaced by `indirect`.
std::vector<TexelIrradiance> withIndirect(std::vector<TexelIrradiance> lighting,
                                          const std::vector<Rgb>& indirect) {
  for (size_t i = 0; i < lighting.size(); ++i) lighting[i].indirect = indirect[i];
  return lighting;
}

// One half of the passes and its own guide: what its filter reads, the
// same for every k.
struct Half {
  std::vector<TexelIrradiance> raw;
  std::shared_ptr<const FilterGuide> guide;
};

Half halfOf(const LightmapAtlas& atlas, const TexelSet& texels, const TexelAccumulator& accumulator,
            bool odd, int radius) {
  return {accumulator.halfMean(odd),
          std::make_shared<FilterGuide>(halfGuide(atlas, texels, accumulator, odd, radius))};
}

std::array<Half, 2> bothHalves(const LightmapAtlas& atlas, const TexelSet& texels,
                               const TexelAccumulator& accumulator, int radius) {
  return {halfOf(atlas, texels, accumulator, false, radius),
          halfOf(atlas, texels, accumulator, true, radius)};
}

// One half of the passes and its indirect light filtered by its own guide.
struct FilteredHalf {
  const std::vector<TexelIrradiance>& raw;
  std::vector<Rgb> indirect;
};

FilteredHalf filteredHalf(const LightmapAtlas& atlas, const TexelSet& texels, const Half& half,
                          PageSettings settings) {
  settings.guide = half.guide;
  return {half.raw, filterIndirect(atlas, texels, half.raw, settings)};
}

// FilteredPasses::bias_squares of the two halves.
double shiftProducts(const FilteredHalf& even, const FilteredHalf& odd) {
  double sum = 0;
  for (size_t i = 0; i < even.raw.size(); ++i) {
    sum += (luminanceOf(even.indirect[i]) - luminanceOf(even.raw[i].indirect)) *
           (luminanceOf(odd.indirect[i]) - luminanceOf(odd.raw[i].indirect));
  }
  return sum;
}

// The squared error of `passes`' mean estimated over the texels, lux^2:
// the halves' difference scaled to the mean (lightmap_error.cpp does the
// same on the pages) and the bias.
double estimatedSquares(const FilteredPasses& passes, const TexelAccumulator& accumulator) {
  const double n_even = accumulator.halfPasses(false), n_odd = accumulator.halfPasses(true);
  const double to_mean = n_even * n_odd / ((n_even + n_odd) * (n_even + n_odd));
  double noise = 0;
  for (const TexelIrradiance& d : passes.difference) {
    const double y = luminanceOf(d.direct) + luminanceOf(d.indirect);
    noise += y * y;
  }
  return noise * to_mean + std::max(0.0, passes.bias_squares);
}

}  // namespace

FilterGuide halfGuide(const LightmapAtlas& atlas, const TexelSet& texels,
                      const TexelAccumulator& accumulator, bool odd, int radius) {
  const std::vector<TexelIrradiance> half = accumulator.halfMean(odd);
  const std::vector<TexelIrradiance> quarters = accumulator.quarterDifference(odd);
  // The half's quarters differ with variance s^2 (1/n_a + 1/n_b) for
  // per-pass variance s^2; the half's mean has s^2 / (n_a + n_b), the
  // quarters' difference's n_a n_b / (n_a + n_b)^2 of it.
  const double n_a = accumulator.quarterPasses(odd ? 1 : 0),
               n_b = accumulator.quarterPasses(odd ? 3 : 2);
  const double to_half = n_a * n_b / ((n_a + n_b) * (n_a + n_b));
  FilterGuide guide;
  guide.luminance.resize(half.size());
  guide.sigma.resize(half.size());
  std::vector<double> squared(half.size());
  for (size_t i = 0; i < half.size(); ++i) {
    guide.luminance[i] = float(luminanceOf(half[i].indirect));
    const double d = luminanceOf(quarters[i].indirect);
    squared[i] = d * d * to_half;
  }
  for (size_t i = 0; i < texels.samples.size() && i < half.size(); ++i) {
    double sum = 0, count = 0;
    forEachChartNeighbour(atlas, texels, i, radius, [&](size_t j, int, int, double) {
      sum += squared[j];
      count += 1;
    });
    guide.sigma[i] = float(std::sqrt(sum / count));
  }
  return guide;
}

namespace {

// filterPasses with both halves and their guides already made.
FilteredPasses filterHalves(const LightmapAtlas& atlas, const TexelSet& texels,
                            const TexelAccumulator& accumulator, const PageSettings& settings,
                            const std::array<Half, 2>& halves) {
  FilteredPasses out;
  out.mean = accumulator.mean();
  out.difference = accumulator.halfDifference();
  const FilteredHalf even = filteredHalf(atlas, texels, halves[0], settings);
  const FilteredHalf odd = filteredHalf(atlas, texels, halves[1], settings);
  // The mean of all passes weighs each half by its passes.
  const float n_even = float(accumulator.halfPasses(false));
  const float n_odd = float(accumulator.halfPasses(true));
  const float w_even = n_even / (n_even + n_odd), w_odd = n_odd / (n_even + n_odd);
  std::vector<Rgb> mean(even.raw.size()), difference(even.raw.size());
  for (size_t i = 0; i < mean.size(); ++i) {
    const Rgb& a = even.indirect[i];
    const Rgb& b = odd.indirect[i];
    mean[i] = {w_even * a.r + w_odd * b.r, w_even * a.g + w_odd * b.g, w_even * a.b + w_odd * b.b};
    difference[i] = {a.r - b.r, a.g - b.g, a.b - b.b};
  }
  out.bias_squares = shiftProducts(even, odd);
  out.mean = withIndirect(std::move(out.mean), mean);
  out.difference = withIndirect(std::move(out.difference), difference);
  out.filtered = true;
  out.noise_sigmas = settings.filter_noise_sigmas;
  return out;
}

bool filters(const TexelAccumulator& accumulator, const PageSettings& settings) {
  return settings.edge_aware_filter && accumulator.passes() >= kFilteredPasses;
}

}  // namespace

FilteredPasses filterPasses(const LightmapAtlas& atlas, const TexelSet& texels,
                            const TexelAccumulator& accumulator, const PageSettings& settings) {
  if (!filters(accumulator, settings)) return {accumulator.mean(), accumulator.halfDifference()};
  const std::array<Half, 2> halves =
      bothHalves(atlas, texels, accumulator, settings.filter_radius_texels);
  return filterHalves(atlas, texels, accumulator, settings, halves);
}

FilteredPasses bestFilteredPasses(const LightmapAtlas& atlas, const TexelSet& texels,
                                  const TexelAccumulator& accumulator, const PageSettings& settings,
                                  const std::array<double, 4>& choices) {
  if (!filters(accumulator, settings)) return filterPasses(atlas, texels, accumulator, settings);
  const std::array<Half, 2> halves =
      bothHalves(atlas, texels, accumulator, settings.filter_radius_texels);
  FilteredPasses best;
  double best_error = std::numeric_limits<double>::infinity();
  for (double k : choices) {
    PageSettings with_k = settings;
    with_k.filter_noise_sigmas = k;
    FilteredPasses passes = filterHalves(atlas, texels, accumulator, with_k, halves);
    const double error = estimatedSquares(passes, accumulator);
    if (error < best_error) {
      best_error = error;
      best = std::move(passes);
    }
  }
  return best;
}

}  // namespace svit::baker

// The lightmap filter's guide (filter_guide.h).

#include "filter_guide.h"

#include <cmath>
#include <vector>

#include "double_math.h"
#include "texel_neighbours.h"

namespace svit::baker {

std::shared_ptr<const FilterGuide> filterGuide(const LightmapAtlas& atlas, const TexelSet& texels,
                                               const TexelAccumulator& accumulator, int radius) {
  if (accumulator.passes() < 2) return nullptr;
  const std::vector<TexelIrradiance> mean = accumulator.mean();
  const std::vector<TexelIrradiance> difference = accumulator.halfDifference();
  // The halves differ with variance s^2 (1/n_even + 1/n_odd) for per-pass
  // variance s^2; the mean of all n passes has s^2 / n, the difference's
  // n_even n_odd / n^2.
  const double n_even = accumulator.halfPasses(false), n_odd = accumulator.halfPasses(true);
  const double to_mean = n_even * n_odd / ((n_even + n_odd) * (n_even + n_odd));
  auto guide = std::make_shared<FilterGuide>();
  guide->luminance.resize(mean.size());
  guide->sigma.resize(mean.size());
  std::vector<double> squared(mean.size());
  for (size_t i = 0; i < mean.size(); ++i) {
    guide->luminance[i] = float(luminanceOf(mean[i].indirect));
    const double d = luminanceOf(difference[i].indirect);
    squared[i] = d * d * to_mean;
  }
  for (size_t i = 0; i < texels.samples.size() && i < mean.size(); ++i) {
    double sum = 0, count = 0;
    forEachChartNeighbour(atlas, texels, i, radius, [&](size_t j, int, int, double) {
      sum += squared[j];
      count += 1;
    });
    guide->sigma[i] = float(std::sqrt(sum / count));
  }
  return guide;
}

}  // namespace svit::baker

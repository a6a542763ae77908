// TexelAccumulator (texel_accumulator.h).

#include "texel_accumulator.h"

#include <algorithm>
#include <cmath>

#include "util/double_math.h"

namespace svit::baker {
namespace {

void addTo(TexelIrradiance& sum, const TexelIrradiance& pass) {
  sum.direct = {sum.direct.r + pass.direct.r, sum.direct.g + pass.direct.g,
                sum.direct.b + pass.direct.b};
  sum.indirect = {sum.indirect.r + pass.indirect.r, sum.indirect.g + pass.indirect.g,
                  sum.indirect.b + pass.indirect.b};
}

TexelIrradiance scaled(const TexelIrradiance& t, float k) {
  return {{t.direct.r * k, t.direct.g * k, t.direct.b * k},
          {t.indirect.r * k, t.indirect.g * k, t.indirect.b * k}};
}

// `sums` over `passes` passes, divided by their count.
std::vector<TexelIrradiance> meanOf(const std::vector<TexelIrradiance>& sums, uint32_t passes) {
  std::vector<TexelIrradiance> out(sums.size());
  const float k = passes > 0 ? 1.0f / float(passes) : 0.0f;
  for (size_t i = 0; i < sums.size(); ++i) out[i] = scaled(sums[i], k);
  return out;
}

}  // namespace

double PassSpread::relativeError(uint32_t passes) const {
  if (passes < 2 || texels == 0) return 1.0;
  const double n = double(texels);
  const double mean = mean_sum / n;
  return mean > 0 ? std::sqrt(variance_sum / n) / mean : 0.0;
}

TexelAccumulator::TexelAccumulator(std::vector<TexelIrradiance> sums,
                                   std::vector<TexelIrradiance> odd_sums,
                                   std::array<std::vector<TexelIrradiance>, 2> quarter_sums,
                                   uint32_t passes)
    : sum_(std::move(sums)),
      odd_sum_(std::move(odd_sums)),
      quarter_sum_(std::move(quarter_sums)),
      passes_(passes) {}

void TexelAccumulator::add(const std::vector<TexelIrradiance>& pass) {
  if (sum_.empty()) {
    sum_.assign(pass.size(), TexelIrradiance{});
    odd_sum_.assign(pass.size(), TexelIrradiance{});
    for (std::vector<TexelIrradiance>& q : quarter_sum_) q.assign(pass.size(), TexelIrradiance{});
    sum_y_.assign(pass.size(), 0.0);
    sum_y2_.assign(pass.size(), 0.0);
  }
  const bool odd = passes_ % 2 == 1;
  const uint32_t quarter = passes_ % 4;
  for (size_t i = 0; i < pass.size(); ++i) {
    addTo(sum_[i], pass[i]);
    if (odd) addTo(odd_sum_[i], pass[i]);
    if (quarter >= 2) addTo(quarter_sum_[quarter - 2][i], pass[i]);
    const double y = luminanceOf(pass[i].direct) + luminanceOf(pass[i].indirect);
    sum_y_[i] += y;
    sum_y2_[i] += y * y;
  }
  ++passes_;
}

std::vector<TexelIrradiance> TexelAccumulator::mean() const { return meanOf(sum_, passes_); }

std::vector<TexelIrradiance> TexelAccumulator::halfMean(bool odd) const {
  if (odd) return meanOf(odd_sum_, halfPasses(true));
  std::vector<TexelIrradiance> even = sum_;
  for (size_t i = 0; i < even.size(); ++i) addTo(even[i], scaled(odd_sum_[i], -1.0f));
  return meanOf(even, halfPasses(false));
}

std::vector<TexelIrradiance> TexelAccumulator::halfDifference() const {
  std::vector<TexelIrradiance> out = halfMean(false);
  const float k = passes_ >= 2 ? 1.0f / float(halfPasses(true)) : 0.0f;
  for (size_t i = 0; i < out.size(); ++i) addTo(out[i], scaled(odd_sum_[i], -k));
  return out;
}

std::vector<TexelIrradiance> TexelAccumulator::quarterDifference(bool odd) const {
  const uint32_t first = odd ? 1 : 0, second = first + 2;
  std::vector<TexelIrradiance> out(sum_.size());
  if (quarterPasses(second) == 0) return out;
  // The half's first quarter is the half less its second.
  const std::vector<TexelIrradiance>& half = odd ? odd_sum_ : sum_;
  const std::vector<TexelIrradiance>& later = quarter_sum_[first];
  const float k_first = 1.0f / float(quarterPasses(first)),
              k_second = 1.0f / float(quarterPasses(second));
  for (size_t i = 0; i < out.size(); ++i) {
    TexelIrradiance first_sum = half[i];
    addTo(first_sum, scaled(later[i], -1.0f));
    if (!odd) addTo(first_sum, scaled(odd_sum_[i], -1.0f));  // the even half is all less the odd
    out[i] = scaled(first_sum, k_first);
    addTo(out[i], scaled(later[i], -k_second));
  }
  return out;
}

PassSpread TexelAccumulator::spread() const {
  PassSpread out;
  out.texels = sum_y_.size();
  if (passes_ < 2) return out;
  const double n = double(passes_);
  for (size_t i = 0; i < sum_y_.size(); ++i) {
    const double m = sum_y_[i] / n;
    out.variance_sum += std::max(0.0, (sum_y2_[i] / n - m * m) * n / (n - 1)) / n;
    out.mean_sum += m;
  }
  return out;
}

}  // namespace svit::baker

// TexelAccumulator (texel_accumulator.h).

#include "texel_accumulator.h"

#include <algorithm>
#include <cmath>

#include "double_math.h"

namespace svit::baker {

double PassSpread::relativeError(uint32_t passes) const {
  if (passes < 2 || texels == 0) return 1.0;
  const double n = double(texels);
  const double mean = mean_sum / n;
  return mean > 0 ? std::sqrt(variance_sum / n) / mean : 0.0;
}

TexelAccumulator::TexelAccumulator(std::vector<TexelIrradiance> sums, uint32_t passes)
    : sum_(std::move(sums)), passes_(passes) {}

void TexelAccumulator::add(const std::vector<TexelIrradiance>& pass) {
  if (sum_.empty()) {
    sum_.assign(pass.size(), TexelIrradiance{});
    sum_y_.assign(pass.size(), 0.0);
    sum_y2_.assign(pass.size(), 0.0);
  }
  for (size_t i = 0; i < pass.size(); ++i) {
    sum_[i].direct = {sum_[i].direct.r + pass[i].direct.r, sum_[i].direct.g + pass[i].direct.g,
                      sum_[i].direct.b + pass[i].direct.b};
    sum_[i].indirect = {sum_[i].indirect.r + pass[i].indirect.r,
                        sum_[i].indirect.g + pass[i].indirect.g,
                        sum_[i].indirect.b + pass[i].indirect.b};
    const double y = luminanceOf(pass[i].direct) + luminanceOf(pass[i].indirect);
    sum_y_[i] += y;
    sum_y2_[i] += y * y;
  }
  ++passes_;
}

std::vector<TexelIrradiance> TexelAccumulator::mean() const {
  std::vector<TexelIrradiance> out(sum_.size());
  const float k = passes_ > 0 ? 1.0f / float(passes_) : 0.0f;
  for (size_t i = 0; i < sum_.size(); ++i) {
    out[i].direct = {sum_[i].direct.r * k, sum_[i].direct.g * k, sum_[i].direct.b * k};
    out[i].indirect = {sum_[i].indirect.r * k, sum_[i].indirect.g * k, sum_[i].indirect.b * k};
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

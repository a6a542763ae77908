#include "light_scale.h"

#include <algorithm>

#include "numeric.h"

namespace svit::gl {

bool isPrimaryBakedEmitter(const Emitter& e) {
  switch (e.kind) {
    case EmitterKind::kBakedLight:
    case EmitterKind::kSun:
    case EmitterKind::kSky: return true;
    case EmitterKind::kStaticPatch: return e.bake_emitter != kInvalidId;
    default: return false;
  }
}

bool LightScale::setEmitterScale(uint32_t bake_emitter, float scale) {
  if (emitter_scale_[bake_emitter] == scale) return false;
  emitter_scale_[bake_emitter] = scale;
  return true;
}

void LightScale::update(const std::vector<Emitter>& emitters, const StaticLevel& level,
                        const std::vector<Receiver>& receivers) {
  const bool any_scaled =
      std::any_of(emitter_scale_.begin(), emitter_scale_.end(), [](float s) { return s != 1.0f; });
  if (!any_scaled) {  // pay for what is used: nothing while every emitter is as baked
    receiver_scale_.clear();
    group_scale_.clear();
    return;
  }
  const uint32_t static_receivers = level.static_receivers;
  std::vector<double> scaled(static_receivers, 0.0), total(static_receivers, 0.0);
  double scaled_flux = 0, total_flux = 0;
  for (const Emitter& e : emitters) {
    if (!isPrimaryBakedEmitter(e)) continue;
    const double s = e.bake_emitter == kInvalidId ? 1.0 : double(emitter_scale_[e.bake_emitter]);
    const double flux = std::max(0.0, luminanceOf(e.flux));
    const SparseShares& shares = e.has_baseline ? e.baseline : e.bake_shares;
    for (size_t i = 0; i < shares.receivers.size(); ++i) {
      const uint32_t r = shares.receivers[i];
      if (r >= static_receivers) continue;
      const double w = flux * double(shares.shares[i]);
      scaled[r] += s * w;
      total[r] += w;
    }
    scaled_flux += s * flux;
    total_flux += flux;
  }
  // A receiver no emitter lights directly takes the level's ratio.
  const double level_scale = total_flux > 0 ? scaled_flux / total_flux : 1.0;
  receiver_scale_.assign(static_receivers, level_scale);
  for (uint32_t r = 0; r < static_receivers; ++r) {
    if (total[r] > 0) receiver_scale_[r] = scaled[r] / total[r];
  }
  group_scale_.assign(level.static_groups, level_scale);
  for (uint32_t g = 0; g < level.static_groups; ++g) {
    double sum = 0, area = 0;
    for (uint32_t r : level.patches.shooter_members[g]) {
      sum += receiver_scale_[r] * double(receivers[r].area_m2);
      area += double(receivers[r].area_m2);
    }
    if (area > 0) group_scale_[g] = sum / area;
  }
}

}  // namespace svit::gl

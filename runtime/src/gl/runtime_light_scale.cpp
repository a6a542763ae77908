// Baked emitters dimmed or switched off (Runtime::setBakedEmitterScale) as
// a factor on the baked light, per static receiver: the share of its light
// each primary baked emitter (a light, the sun, the sky, a lamp's emissive
// patch) puts there directly, weighted by that emitter's scale. Shading
// multiplies the lightmap by it (svit_runtime_delta.frag), so a level lit
// by one lamp goes exactly black with the lamp off and exactly half as
// bright dimmed to 0.5, at the lightmap's resolution; bounced light is
// split between emitters as their direct light is. Additive patch deltas
// would leave the lightmap's detail inside each patch as a residue.

#include <algorithm>

#include "runtime_impl.h"

namespace svit {

bool Runtime::Impl::isPrimaryBakedEmitter(const Emitter& e) const {
  switch (e.kind) {
    case EmitterKind::kBakedLight:
    case EmitterKind::kSun:
    case EmitterKind::kSky:
      return true;
    case EmitterKind::kStaticPatch:
      return e.bake_emitter != kInvalidId;
    default:
      return false;
  }
}

void Runtime::Impl::updateLightScale() {
  const bool any_scaled = std::any_of(bake_emitter_scale.begin(), bake_emitter_scale.end(),
                                      [](float s) { return s != 1.0f; });
  if (!any_scaled) {  // pay for what is used: nothing while every emitter is as baked
    light_scale.clear();
    group_light_scale.clear();
    return;
  }
  std::vector<double> scaled(static_receivers, 0.0), total(static_receivers, 0.0);
  double scaled_flux = 0, total_flux = 0;
  for (const Emitter& e : emitters) {
    if (!isPrimaryBakedEmitter(e)) continue;
    const double s = emitterScale(e), flux = std::max(0.0, lum(e.flux));
    // Its own maps where it has them, else the bake's factors.
    const rt::SparseShares& shares = e.has_baseline ? e.baseline : e.bake_shares;
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
  light_scale.assign(static_receivers, level_scale);
  for (uint32_t r = 0; r < static_receivers; ++r) {
    if (total[r] > 0) light_scale[r] = scaled[r] / total[r];
  }
  group_light_scale.assign(static_groups, level_scale);
  for (uint32_t g = 0; g < static_groups; ++g) {
    double sum = 0, area = 0;
    for (uint32_t r : patches.shooter_members[g]) {
      sum += light_scale[r] * double(receivers[r].area_m2);
      area += double(receivers[r].area_m2);
    }
    if (area > 0) group_light_scale[g] = sum / area;
  }
}

double Runtime::Impl::lightScaleOf(uint32_t receiver) const {
  return receiver < light_scale.size() ? light_scale[receiver] : 1.0;
}

}  // namespace svit

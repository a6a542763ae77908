#include "light_scale.h"

#include <algorithm>

#include "scene/numeric.h"

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

namespace {

// Per static receiver, the primary emitters' direct flux (lm), all of it,
// its scaled part, and the masked emitters' (at scale 1).
struct DirectSums {
  std::vector<double> total, scaled, masked_total;
  double total_flux = 0, scaled_flux = 0;
};

DirectSums sumDirect(const std::vector<Emitter>& emitters, const std::vector<float>& emitter_scale,
                     uint32_t static_receivers) {
  DirectSums d;
  for (auto* v : {&d.total, &d.scaled, &d.masked_total}) v->assign(static_receivers, 0.0);
  for (const Emitter& e : emitters) {
    if (!isPrimaryBakedEmitter(e)) continue;
    // A masked emitter's dimming is a delta (runtime_deltas.cpp), not a factor.
    const double s =
        e.bake_emitter == kInvalidId || e.masked ? 1.0 : double(emitter_scale[e.bake_emitter]);
    const double flux = std::max(0.0, luminanceOf(e.flux));
    const SparseShares& shares = e.has_baseline ? e.baseline : e.bake_shares;
    for (size_t i = 0; i < shares.receivers.size(); ++i) {
      const uint32_t r = shares.receivers[i];
      if (r >= static_receivers) continue;
      const double w = flux * double(shares.shares[i]);
      d.scaled[r] += s * w;
      d.total[r] += w;
      if (e.masked) d.masked_total[r] += w;
    }
    d.scaled_flux += s * flux;
    d.total_flux += flux;
  }
  return d;
}

}  // namespace

// Bounced light is split between emitters as their direct light is. A
// masked emitter's direct light is not in the lightmap, and its dimming is
// a delta (shaded per pixel, bounced by the solver), so here it counts at
// scale 1, and only through the bounce: the lightmap holds the unmasked
// emitters' direct light U (from their shares) and a bounce I = lightmap -
// U, scaled as the direct light is split.
void LightScale::update(const std::vector<Emitter>& emitters, const StaticLevel& level,
                        const std::vector<Receiver>& receivers) {
  bool any_scaled = false;
  for (const Emitter& e : emitters) {
    if (isPrimaryBakedEmitter(e) && !e.masked && e.bake_emitter != kInvalidId)
      any_scaled = any_scaled || emitter_scale_[e.bake_emitter] != 1.0f;
  }
  if (!any_scaled) {  // pay for what is used: nothing while every emitter is as baked
    receiver_scale_.clear();
    group_scale_.clear();
    return;
  }
  const uint32_t static_receivers = level.static_receivers;
  const DirectSums d = sumDirect(emitters, emitter_scale_, static_receivers);
  // A receiver no emitter lights directly takes the level's ratio.
  const double level_scale = d.total_flux > 0 ? d.scaled_flux / d.total_flux : 1.0;
  receiver_scale_.assign(static_receivers, level_scale);
  std::vector<double> shown_scale(static_receivers, level_scale);  // of all its baked light
  for (uint32_t r = 0; r < static_receivers; ++r) {
    if (!(d.total[r] > 0)) continue;
    const double bounce_scale = d.scaled[r] / d.total[r];
    receiver_scale_[r] = shown_scale[r] = bounce_scale;
    if (!(d.masked_total[r] > 0)) continue;
    const double area = std::max(double(receivers[r].area_m2), 1e-30);
    const double lightmap = luminanceOf(level.patches.lightmap_irradiance[r]);
    const double masked = luminanceOf(level.patches.masked_direct[r]);
    const double unmasked = (d.total[r] - d.masked_total[r]) / area;
    const double unmasked_scaled = (d.scaled[r] - d.masked_total[r]) / area;
    const double bounce = std::max(lightmap - unmasked, 0.0);
    if (unmasked + bounce > 0)
      receiver_scale_[r] = (unmasked_scaled + bounce * bounce_scale) / (unmasked + bounce);
    if (lightmap + masked > 0)  // the masked part is as baked here (its dimming is a delta)
      shown_scale[r] = (lightmap * receiver_scale_[r] + masked) / (lightmap + masked);
  }
  group_scale_.assign(level.static_groups, level_scale);
  for (uint32_t g = 0; g < level.static_groups; ++g) {
    double sum = 0, area = 0;
    for (uint32_t r : level.patches.shooter_members[g]) {
      sum += shown_scale[r] * double(receivers[r].area_m2);
      area += double(receivers[r].area_m2);
    }
    if (area > 0) group_scale_[g] = sum / area;
  }
}

}  // namespace svit::gl

#pragma once
// Baked emitters dimmed or switched off (Runtime::setBakedEmitterScale) as
// a factor on the baked light, per static receiver: the share of its light
// each primary baked emitter (a light, the sun, the sky, a lamp's emissive
// patch) puts there directly, weighted by that emitter's scale. Shading
// multiplies the lightmap by it (svit_runtime_delta.frag), so a level lit
// by one lamp goes exactly black with the lamp off and exactly half as
// bright dimmed to 0.5, at the lightmap's resolution; bounced light is
// split between emitters as their direct light is. Additive patch deltas
// would leave the lightmap's detail inside each patch as a residue. A
// masked emitter's direct light is not in the lightmap (shading scales it
// per pixel): on the lightmap it weighs only through its bounce.

#include <cstdint>
#include <vector>

#include "emitter.h"
#include "receivers/receivers.h"
#include "static_level.h"

namespace svit::gl {

/// A light, the sun, the sky or a lamp's emissive patch of the bake: what
/// puts baked light on the level directly.
bool isPrimaryBakedEmitter(const Emitter& e);

class LightScale {
 public:
  /// One per BakeData emitter, all 1 (as baked).
  void reset(size_t bake_emitters) { emitter_scale_.assign(bake_emitters, 1.0f); }
  /// Sets one; false when it already had that value.
  bool setEmitterScale(uint32_t bake_emitter, float scale);
  float emitterScale(uint32_t bake_emitter) const { return emitter_scale_[bake_emitter]; }

  /// Recomputes the factors from the emitters' direct shares (their maps
  /// where they have them, else the bake's factors); clears them while
  /// every emitter is as baked.
  void update(const std::vector<Emitter>& emitters, const StaticLevel& level,
              const std::vector<Receiver>& receivers);
  /// The factor on a static receiver's baked light (1 while as baked).
  double ofReceiver(uint32_t receiver) const {
    return receiver < receiver_scale_.size() ? receiver_scale_[receiver] : 1.0;
  }
  /// The area mean over a static group of the factor on all its baked
  /// light (lightmap and masked lights), or 1 while as baked.
  double ofGroup(uint32_t group) const {
    return group < group_scale_.size() ? group_scale_[group] : 1.0;
  }
  /// Per static receiver; empty while every baked emitter is as baked.
  const std::vector<double>& receiverScales() const { return receiver_scale_; }

 private:
  std::vector<float> emitter_scale_;  ///< per BakeData emitter, 1 = as baked
  std::vector<double> receiver_scale_, group_scale_;
};

}  // namespace svit::gl

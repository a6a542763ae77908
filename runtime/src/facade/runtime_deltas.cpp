// Each emitter's light as coefficients of its two share sets (thesis 5.3):
// what it adds through its current shares and takes back through its
// baseline, by kind. DeltaAccumulator (delta_accumulator.h) sums them.

#include "runtime_impl.h"
#include "scene/numeric.h"

namespace svit {
namespace {

glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

}  // namespace

rt::DeltaTerms Runtime::Impl::deltaTerms(const Emitter& e) const {
  rt::DeltaTerms t;
  t.current_revision = e.hasCurrent() ? e.current_revision : 0;
  switch (e.kind) {
    case EmitterKind::kBakedLight:
    case EmitterKind::kSun:
    case EmitterKind::kSky: {
      // Baked light is in the lightmap, scaled there by the light scale:
      // what objects change of it is a delta, at the emitter's scale. A
      // masked emitter's direct light is shaded per pixel and its bounce is
      // smooth: its dimming is a delta too (current at its scale less the
      // baseline as baked), which the bounce carries into its bounce.
      if (!e.has_baseline || !e.hasCurrent()) break;
      const double scale = light_scale.emitterScale(e.bake_emitter);
      t.on_current = e.flux * scale;
      t.on_baseline = -e.flux * (e.masked ? 1.0 : scale);
      break;
    }
    case EmitterKind::kStaticPatch: {
      // A bright patch (or a lamp) sends what objects change of its light,
      // at the factor its own baked light now has; a masked lamp's dimming
      // is a delta, as a masked light's.
      if (e.needs_baseline && e.has_baseline && e.hasCurrent()) {
        const double scale = e.bake_emitter != kInvalidId
                                 ? double(light_scale.emitterScale(e.bake_emitter))
                                 : light_scale.ofGroup(e.index);
        t.on_current = e.flux * scale;
        t.on_baseline = -e.flux * (e.masked ? 1.0 : scale);
      }
      break;
    }
    case EmitterKind::kDynamicObject: {
      const rt::DynamicObject& object = objects[e.index / kObjectShooters];
      if (!e.hasCurrent() || !object.visible || object.removed) break;
      // Its own emission (Lambertian: exitance pi L); reflection is a bounce.
      for (size_t t_index = 0; t_index < object.emission.size(); ++t_index) {
        if (object.shooter_bin[t_index] != e.index % kObjectShooters) continue;
        t.on_current += kPi * dvec(object.emission[t_index]) *
                        double(receivers[object.first_receiver + t_index].area_m2);
      }
      break;
    }
    case EmitterKind::kRuntimeLight: {
      const RuntimeLightState& light = lights[e.index];
      if (!e.hasCurrent() || !light.enabled || light.removed) break;
      t.on_current = dvec(light.light.color) * double(light.light.intensity) *
                     double(light.dimmer) * rt::lightLobeSolidAngle(light.light);
      t.direct = t.on_current;
      break;
    }
  }
  return t;
}

}  // namespace svit

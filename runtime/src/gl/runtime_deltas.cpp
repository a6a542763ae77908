// The emitters' first-round deltas summed per receiver (thesis 5.3):
// each emitter's light as coefficients of its two share sets (DeltaTerms),
// and first_flux kept by adding what changed since the last solve, so a
// frame costs the emitters it refreshed, switched or dimmed, not every
// emitter's shares (on the 8 x 8 house every lamp has a table in reach and
// so a delta: summing them all took 4-5 ms per solve).

#include "runtime_impl.h"

namespace svit {
namespace {

void addShares(std::vector<glm::dvec3>& to, const rt::SparseShares& shares, const glm::dvec3& flux) {
  if (flux == glm::dvec3(0.0)) return;
  for (size_t i = 0; i < shares.receivers.size(); ++i) to[shares.receivers[i]] += flux * double(shares.shares[i]);
}

}  // namespace

DeltaTerms Runtime::Impl::deltaTerms(const Emitter& e) const {
  DeltaTerms t;
  t.current_revision = e.has_current ? e.current_revision : 0;
  switch (e.kind) {
    case EmitterKind::kBakedLight:
    case EmitterKind::kSun:
    case EmitterKind::kSky: {
      // Baked light is in the lightmap, scaled there by the light scale:
      // what objects change of it is a delta, at the emitter's scale.
      if (!e.has_baseline || !e.has_current) break;
      const double scale = bake_emitter_scale[e.bake_emitter];
      t.on_current = e.flux * scale;
      t.on_baseline = -e.flux * scale;
      break;
    }
    case EmitterKind::kStaticPatch: {
      // A bright patch (or a lamp) sends what objects change of its light,
      // at the factor its own baked light now has.
      if (e.needs_baseline && e.has_baseline && e.has_current) {
        const double scale = e.bake_emitter != kInvalidId ? double(bake_emitter_scale[e.bake_emitter])
                             : e.index < group_light_scale.size() ? group_light_scale[e.index]
                                                                  : 1.0;
        t.on_current = e.flux * scale;
        t.on_baseline = -e.flux * scale;
      }
      break;
    }
    case EmitterKind::kDynamicObject: {
      const rt::DynamicObject& object = objects[e.index / kObjectShooters];
      if (!e.has_current || !object.visible || object.removed) break;
      // Its own emission (Lambertian: exitance pi L); reflection is a bounce.
      for (size_t t_index = 0; t_index < object.emission.size(); ++t_index) {
        if (object.shooter_bin[t_index] != e.index % kObjectShooters) continue;
        t.on_current += 3.14159265358979 * dvec(object.emission[t_index]) *
                        double(receivers[object.first_receiver + t_index].area_m2);
      }
      break;
    }
    case EmitterKind::kRuntimeLight: {
      const RuntimeLightState& light = lights[e.index];
      if (!e.has_current || !light.enabled || light.removed) break;
      t.on_current = dvec(light.light.color) * double(light.light.intensity) * double(light.dimmer) *
                     rt::lightLobeSolidAngle(light.light);
      t.direct = t.on_current;
      break;
    }
  }
  return t;
}

void Runtime::Impl::retractCurrent(Emitter& e) {
  if (!e.has_current || e.summed.current_revision != e.current_revision) return;
  addShares(first_flux, e.current, -e.summed.on_current);
  addShares(direct_flux, e.current, -e.summed.direct);
  e.summed.on_current = e.summed.direct = glm::dvec3(0.0);
  e.summed.current_revision = 0;
}

void Runtime::Impl::setCurrent(Emitter& e, rt::SparseShares shares) {
  retractCurrent(e);
  e.current = std::move(shares);
  e.current_revision = ++shares_revisions;
  e.has_current = true;
}

void Runtime::Impl::sumEmitterDeltas() {
  const size_t n = receivers.size();  // receivers are only ever appended
  first_flux.resize(n, glm::dvec3(0.0));
  direct_flux.resize(n, glm::dvec3(0.0));
  for (Emitter& e : emitters) {
    const DeltaTerms now = deltaTerms(e);
    DeltaTerms& was = e.summed;
    if (now == was) continue;
    if (was.current_revision != now.current_revision && (was.on_current != glm::dvec3(0.0) || was.direct != glm::dvec3(0.0))) {
      // A current replaced without retractCurrent: what it carried is
      // unknown, so sum every emitter again.
      std::fill(first_flux.begin(), first_flux.end(), glm::dvec3(0.0));
      std::fill(direct_flux.begin(), direct_flux.end(), glm::dvec3(0.0));
      for (Emitter& other : emitters) other.summed = DeltaTerms{};
      sumEmitterDeltas();
      return;
    }
    const glm::dvec3 on_current = was.current_revision == now.current_revision ? was.on_current : glm::dvec3(0.0);
    const glm::dvec3 direct = was.current_revision == now.current_revision ? was.direct : glm::dvec3(0.0);
    if (e.has_current) {
      addShares(first_flux, e.current, now.on_current - on_current);
      addShares(direct_flux, e.current, now.direct - direct);
    }
    addShares(first_flux, e.baseline, now.on_baseline - was.on_baseline);
    was = now;
  }
}

}  // namespace svit

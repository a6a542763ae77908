// The bounce (thesis 5.3 steps 6-8): the emitters' first-round deltas
// reflected through the receivers' own cached shares, with ambient
// compensation for what was not shot; then which objects are lit, and the
// upload of what shading shows.

#include <algorithm>
#include <chrono>

#include "runtime_impl.h"
#include "scene/glm_interop.h"
#include "scene/numeric.h"

namespace svit {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

/// Most wanted first, ties by group.
void sortWanted(std::vector<std::pair<double, uint32_t>>& wanted) {
  std::sort(wanted.begin(), wanted.end(), [](auto& a, auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
}

/// A flat face of an object made of several triangles shows one value:
/// average coplanar triangles (the per-triangle estimates come from few
/// samples each and would otherwise differ across a face's diagonal).
/// Linear in the triangles: the faces are known from binObjectTriangles.
void averageFlatFaces(const std::vector<rt::DynamicObject>& objects,
                      const std::vector<rt::Receiver>& receivers,
                      std::vector<glm::dvec3>& delta_total) {
  std::vector<glm::dvec3> face_sum;
  std::vector<double> face_area;
  for (const rt::DynamicObject& object : objects) {
    const size_t count = object.albedo.size();
    if (!object.visible || object.removed || object.flat_face.size() != count) continue;
    face_sum.assign(count, glm::dvec3(0.0));
    face_area.assign(count, 0.0);
    for (size_t t = 0; t < count; ++t) {
      const double area = receivers[object.first_receiver + t].area_m2;
      face_sum[object.flat_face[t]] += delta_total[object.first_receiver + t] * area;
      face_area[object.flat_face[t]] += area;
    }
    for (size_t t = 0; t < count; ++t) {
      const uint32_t f = object.flat_face[t];
      if (face_area[f] > 0) delta_total[object.first_receiver + t] = face_sum[f] / face_area[f];
    }
  }
}

}  // namespace

void Runtime::Impl::solve(FrameStats& stats, std::vector<std::pair<double, uint32_t>>& wanted) {
  const auto t0 = Clock::now();
  const size_t n = receivers.size();
  light_scale.update(emitter_set.emitters, level, receivers);
  accumulator.sum(emitter_set.emitters, n, [this](const Emitter& e) { return deltaTerms(e); });
  const std::vector<glm::dvec3>& first = accumulator.firstFlux();
  const std::vector<glm::dvec3>& direct = accumulator.directFlux();
  const std::vector<glm::dvec3>& masked = accumulator.maskedFlux();
  const std::vector<int32_t> group_of = receiverGroups();
  const std::vector<uint32_t>& group_emitter = emitter_set.group_emitter;
  std::vector<const rt::SparseShares*> shooters(group_emitter.size(), nullptr);
  std::vector<uint64_t> revisions(group_emitter.size(), 0);
  for (size_t g = 0; g < group_emitter.size(); ++g) {
    const uint32_t id = group_emitter[g];
    if (id == kInvalidId || !emitter_set.emitters[id].hasCurrent()) continue;
    shooters[g] = &emitter_set.emitters[id].current;
    revisions[g] = emitter_set.emitters[id].current_revision;
  }
  rt::BounceSettings bounce;
  bounce.max_bounces = settings.max_bounces;
  bounce.stop_share = settings.bounce_stop_share;
  bounce.ambient = settings.ambient_compensation;
  const rt::BounceResult& result =
      bounce_solver.solve(receivers, first, group_of, shooters, revisions, bounce);
  stats.bounce_rounds = uint32_t(result.rounds);
  stats.unshot_share = result.unshot_share;
  for (size_t r = 0; r < n; ++r) {
    const double area = receivers[r].area_m2;
    outputs.delta_total[r] = area > 0 ? result.received[r] / area : glm::dvec3(0.0);
    // Shaded per pixel: runtime lights everywhere, masked lights on static surfaces.
    const glm::dvec3 masked_here = r < level.static_receivers ? masked[r] : glm::dvec3(0.0);
    outputs.runtime_direct[r] = area > 0 ? (direct[r] + masked_here) / area : glm::dvec3(0.0);
    outputs.masked_direct[r] = area > 0 ? masked_here / area : glm::dvec3(0.0);
  }
  averageFlatFaces(objects, receivers, outputs.delta_total);
  for (size_t g = 0; g < result.wanted.size(); ++g) {
    if (result.wanted[g] > 0) wanted.push_back({result.wanted[g], uint32_t(g)});
  }
  outputs.deltasChanged();
  sortWanted(wanted);
  stats.bounce_ms += msSince(t0);
}

// An object is lit once the emitters that carry light to it (a baked light,
// the sun, the sky, a lamp or bright patch: those with a baseline) and have
// rendered shares since it appeared carry all but kUnlitShare of its light,
// each weighed by flux over squared distance from its source to the object.
// A partial sum of its emitters would draw it darker than the probe grid
// does (black after the first update), so it keeps the probes until then;
// waiting for every last dim emitter would keep it there for as long as
// importance caching lets those wait. Once lit, later moves refresh its
// emitters one by one from values that are already nearly whole.
void Runtime::Impl::updateObjectsLit() {
  constexpr double kUnlitShare = 0.05;
  for (rt::DynamicObject& object : objects) {
    if (object.lit || !object.visible || object.removed || object.bounds.empty()) continue;
    const glm::dvec3 low(toGlm(object.bounds.min)), high(toGlm(object.bounds.max));
    const glm::dvec3 centre = 0.5 * (low + high);
    const double radius2 = 0.25 * glm::dot(high - low, high - low);
    double total = 0, missing = 0;
    for (const Emitter& e : emitter_set.emitters) {
      if (!e.needs_baseline || !reaches(e, object.bounds)) continue;
      // The sun's and sky's source is their window over the level, about as
      // far as it is wide: flux over squared distance is then about their
      // illuminance, as it is a lamp's irradiance.
      const Aabb& source_box = e.reach.source_box;
      const glm::dvec3 source =
          source_box.empty()
              ? centre
              : 0.5 * (glm::dvec3(toGlm(source_box.min)) + glm::dvec3(toGlm(source_box.max)));
      const glm::dvec3 d = source - centre;
      const double weight = std::max(0.0, luminanceOf(e.flux)) / std::max(glm::dot(d, d), radius2);
      total += weight;
      if (!e.hasCurrent() || e.current_revision <= object.shown_revision) missing += weight;
    }
    object.lit = missing <= kUnlitShare * total;
  }
}

void Runtime::Impl::uploadDisplay(FrameStats& stats) {
  const auto t0 = Clock::now();
  rt::DisplayInput in;
  in.patches = &level.patches;
  in.static_receivers = level.static_receivers;
  in.light_scale = &light_scale.receiverScales();
  in.objects = &objects;
  in.pages = &level.pages;
  in.temporal_blend = settings.temporal_blend;
  in.delta_textures = settings.delta_textures;
  gl_objects_created += outputs.upload(in);
  stats.upload_ms += msSince(t0);
}

}  // namespace svit

// Importance caching in the runtime (thesis 5.9-5.10): what each emitter
// needs (maps at all? out of date?), its importance for the view set with
// Runtime::setView, and the candidates the refresh scheduler picks from.
// An emitter with no dynamic object in its reach and its baked scale needs
// no map at all: its delta against the bake is exactly zero.

#include <algorithm>
#include <chrono>
#include <cmath>

#include "lighting/aabb_ops.h"
#include "lighting/emitter_importance.h"
#include "runtime_impl.h"
#include "scene/glm_interop.h"
#include "scene/numeric.h"

namespace svit {

std::vector<int32_t> Runtime::Impl::receiverGroups() const {
  // Static patches reflect through their shooter, object triangles through
  // their object's facing (one pass per object, not a search per receiver).
  const size_t n = receivers.size();
  std::vector<int32_t> group_of(n, -1);
  for (uint32_t r = 0; r < level.static_receivers; ++r)
    group_of[r] = int32_t(level.patches.shooter[r]);
  for (size_t o = 0; o < objects.size(); ++o) {
    const rt::DynamicObject& object = objects[o];
    for (size_t t = 0; t < object.albedo.size(); ++t) {
      group_of[object.first_receiver + t] =
          int32_t(level.static_groups + o * kObjectShooters + object.shooter_bin[t]);
    }
  }
  return group_of;
}

double Runtime::Impl::emitterScale(const Emitter& e) const {
  return e.bake_emitter == kInvalidId ? 1.0 : double(light_scale.emitterScale(e.bake_emitter));
}

bool Runtime::Impl::reaches(const Emitter& e, const Aabb& box) const {
  if (!e.reach.region_known) return true;
  if (!rt::overlaps(e.reach.region, box)) return false;
  // parallel light, or at the source
  if (e.reach.region.isEverything() || rt::overlaps(e.reach.source_box, box)) return true;
  // Light to a patch travels inside the box of the source and the patch: an
  // object outside every such box can neither shadow what the emitter lights
  // nor catch its light (in a closed level, a lit object stands in front of
  // some patch the emitter lit without it). Finer than the one region box,
  // which spans two rooms' worth of corners when light passes a doorway.
  auto hits = [&](uint32_t r) {
    Aabb hull = e.reach.source_box;
    if (r < level.static_receivers) {
      rt::grow(hull, level.patches.bounds[r]);
    } else {
      rt::grow(hull, receivers[r].centroid);
    }
    return rt::overlaps(hull, box);
  };
  auto any = [&](const rt::SparseShares& shares) {
    if (shares.blocks.empty())
      return std::any_of(shares.receivers.begin(), shares.receivers.end(), hits);
    for (size_t k = 0; k < shares.blocks.size(); ++k) {
      // Each patch of a whole static block lies in the block's bounds, so
      // a box the hull of the source and those bounds misses, every
      // patch's hull misses too: a block costs one test, not one per patch.
      const uint32_t block = shares.blocks[k];
      if (block < level.static_block_bounds.size()) {
        Aabb hull = e.reach.source_box;
        rt::grow(hull, level.static_block_bounds[block]);
        if (!rt::overlaps(hull, box)) continue;
      }
      const size_t end =
          k + 1 < shares.blocks.size() ? shares.block_begin[k + 1] : shares.receivers.size();
      for (size_t i = shares.block_begin[k]; i < end; ++i) {
        if (hits(shares.receivers[i])) return true;
      }
    }
    return false;
  };
  if (e.hasCurrent() && any(e.current)) return true;
  if (e.has_baseline) return any(e.baseline);
  return any(e.bake_shares);
}

bool Runtime::Impl::wantsLitSetMaps(const Emitter& e) const {
  return settings.lit_set_culling && e.kind == EmitterKind::kStaticPatch && !e.has_baseline;
}

bool Runtime::Impl::facingEmits(const Emitter& e) const {
  const rt::DynamicObject& object = objects[e.index / kObjectShooters];
  for (size_t t = 0; t < object.emission.size(); ++t) {
    const Rgb& c = object.emission[t];
    if (object.shooter_bin[t] == e.index % kObjectShooters && (c.r > 0 || c.g > 0 || c.b > 0))
      return true;
  }
  return false;
}

bool Runtime::Impl::reachesAnyObject(const Emitter& e) const {
  for (const rt::DynamicObject& object : objects) {
    if (object.visible && !object.removed && reaches(e, object.bounds)) return true;
  }
  return false;
}

void Runtime::Impl::updateReach() {
  // An emitter no moved, added or removed object's box reached (it would
  // have been invalidated) keeps its answer: O(changed), not O(level).
  for (Emitter& e : emitter_set.emitters) {
    if (!e.reach.touched_dirty && !e.isStale() && e.reach.region_known) continue;
    e.reach.touched = reachesAnyObject(e);
    e.reach.touched_dirty = false;
  }
}

bool Runtime::Impl::needsMaps(const Emitter& e) const {
  switch (e.kind) {
    case EmitterKind::kBakedLight:
    case EmitterKind::kSun:
    case EmitterKind::kSky: return emitterScale(e) != 1.0 || e.reach.touched;
    case EmitterKind::kStaticPatch:
      return e.bounce_requested || emitterScale(e) != 1.0 || (e.needs_baseline && e.reach.touched);
    case EmitterKind::kDynamicObject: {
      const rt::DynamicObject& object = objects[e.index / kObjectShooters];
      return object.visible && !object.removed;
    }
    case EmitterKind::kRuntimeLight: return !lights[e.index].removed && lights[e.index].enabled;
  }
  return false;
}

bool Runtime::Impl::outOfDate(const Emitter& e) const {
  return e.isStale() || !e.hasCurrent() || (e.needs_baseline && !e.has_baseline);
}

void Runtime::Impl::rankForView(FrameStats& stats) {
  const auto t0 = std::chrono::steady_clock::now();
  const RuntimeView& view = ranking.view;
  const glm::vec3 eye = toGlm(view.position);
  const glm::vec3 forward = glm::normalize(toGlm(view.look_at) - eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, toGlm(view.up)));
  const glm::vec3 up = glm::cross(right, forward);
  rt::ViewFrame frame_view;
  frame_view.eye = view.position;
  frame_view.right = fromGlm(right);
  frame_view.up = fromGlm(up);
  frame_view.forward = fromGlm(forward);
  frame_view.tan_half_y = std::tan(0.5f * view.yfov_rad);
  frame_view.tan_half_x = frame_view.tan_half_y * view.aspect;
  frame_view.near_m = view.near_m;
  const int width = settings.view_pass_width;
  const int height = std::clamp(int(std::lround(double(width) / double(view.aspect))), 1, 4096);
  renderer->setReceiverCount(uint32_t(receivers.size()));
  std::vector<uint32_t>& view_pixels = ranking.view_pixels;
  if (Status s = renderer->countViewPixels(frame_view, width, height, view_pixels); !s.ok()) {
    stats.error = s.message();
    view_pixels.assign(receivers.size(), 0u);
  }
  rt::ViewWeights& weights = ranking.weights;
  const size_t n = receivers.size();
  weights.weight.assign(n, 0.0);
  weights.reflectance.assign(n, 0.0);
  for (size_t r = 0; r < n; ++r) {
    const double rho = luminanceOf(receivers[r].albedo);
    weights.reflectance[r] = rho;
    const double area = receivers[r].area_m2;
    weights.weight[r] =
        area > 0 && r < view_pixels.size() ? double(view_pixels[r]) * rho / area : 0.0;
    if (r < view_pixels.size() && view_pixels[r] > 0) ++stats.visible_patches;
  }
  weights.group_of = receiverGroups();
  std::vector<Emitter>& emitters = emitter_set.emitters;
  const std::vector<uint32_t>& group_emitter = emitter_set.group_emitter;
  weights.group_shares.assign(group_emitter.size(), nullptr);
  for (size_t g = 0; g < group_emitter.size(); ++g) {
    const uint32_t id = group_emitter[g];
    if (id != kInvalidId && emitters[id].hasCurrent())
      weights.group_shares[g] = &emitters[id].current;
  }
  std::vector<rt::ImportanceQuery> queries(emitters.size());
  for (size_t i = 0; i < emitters.size(); ++i) queries[i] = importanceQuery(emitters[i], false);
  ranking.group_view = rt::groupView(weights, queries);
  double& top_importance = ranking.top_importance;
  top_importance = 0;
  const std::vector<double> importance = rt::importanceOfAll(ranking.group_view, queries);
  for (double v : importance) top_importance = std::max(top_importance, v);
  const uint32_t max_interval = uint32_t(settings.max_refresh_interval);
  for (size_t i = 0; i < emitters.size(); ++i) {
    Emitter& e = emitters[i];
    e.queue.importance = importance[i];
    e.queue.interval = rt::refreshInterval(importance[i], top_importance, max_interval);
    if (!outOfDate(e)) e.queue.settled_importance = importance[i];
  }
  stats.view_ms +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

rt::ImportanceQuery Runtime::Impl::importanceQuery(const Emitter& e, bool current_only) const {
  rt::ImportanceQuery q;
  q.flux = std::max(0.0, luminanceOf(e.flux)) * std::max(1.0, emitterScale(e));
  if (e.kind == EmitterKind::kRuntimeLight) {
    const RuntimeLightState& light = lights[e.index];
    q.flux = std::max(0.0, luminanceOf(light.light.color) * double(light.light.intensity) *
                               double(light.dimmer) * rt::lightLobeSolidAngle(light.light));
  }
  if (e.hasCurrent()) q.shares.push_back(&e.current);
  // An out-of-date cache counts what it lit and what the static level lets
  // it light (a door that opened, an object that left).
  if (!current_only && (outOfDate(e) || !e.hasCurrent())) {
    if (e.has_baseline) {
      q.shares.push_back(&e.baseline);
    } else if (!e.bake_shares.receivers.empty()) {
      q.shares.push_back(&e.bake_shares);
    }
  }
  // With nothing cached, a shooter counts what its group passes on (a
  // group with no shares borrows from the emitters lighting it).
  if (e.kind == EmitterKind::kStaticPatch) q.own_group = int32_t(e.index);
  if (e.kind == EmitterKind::kDynamicObject) q.own_group = int32_t(level.static_groups + e.index);
  return q;
}

void Runtime::Impl::settleImportance(const std::vector<rt::RefreshDecision>& refreshed) {
  // What a just-refreshed emitter shows now, from its fresh shares: the
  // reference a later rise (a door opening onto its light) is judged by.
  for (const rt::RefreshDecision& d : refreshed) {
    Emitter& e = emitter_set.emitters[d.emitter];
    if (outOfDate(e)) continue;
    e.queue.settled_importance = rt::importanceOf(ranking.group_view, importanceQuery(e, true));
  }
}

std::vector<rt::RefreshCandidate> Runtime::Impl::refreshCandidates() {
  std::vector<rt::RefreshCandidate> candidates;
  for (uint32_t i = 0; i < emitter_set.emitters.size(); ++i) {
    Emitter& e = emitter_set.emitters[i];
    if (!needsMaps(e)) continue;
    if (!settings.refresh_all && !outOfDate(e)) continue;
    rt::EmitterQueue& queue = e.queue;
    if (!queue.waiting) {
      queue.waiting = true;
      queue.waiting_since = changes.frame;
      queue.queued_interval = queue.interval;
    }
    rt::RefreshCandidate c;
    c.emitter = i;
    c.importance = queue.importance;
    const size_t samples = e.samples.empty() ? size_t(e.sample_count) : e.samples.size();
    const bool static_maps_first = (e.needs_baseline && !e.has_baseline) || wantsLitSetMaps(e);
    c.cost = double(std::max<size_t>(samples, 1)) * (static_maps_first ? 2.0 : 1.0);
    c.waiting_since = queue.waiting_since;
    c.queued_interval = queue.queued_interval;
    c.settled_importance = queue.settled_importance;
    // Switched or dimmed with nothing cached to scale, or new light: shows
    // in the very next frame whatever its importance. A new facing of an
    // object that only reflects is not a light: it goes by importance, or
    // a level full of objects would spend its first frames far over budget.
    c.urgent = (emitterScale(e) != 1.0 && e.needs_baseline && !e.has_baseline) ||
               (e.kind == EmitterKind::kRuntimeLight && !e.hasCurrent()) ||
               (e.kind == EmitterKind::kDynamicObject && !e.hasCurrent() && facingEmits(e));
    candidates.push_back(c);
  }
  return candidates;
}

}  // namespace svit

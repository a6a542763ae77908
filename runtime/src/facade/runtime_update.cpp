// The runtime's frame (thesis 5.3): bring emitters' cached index-map shares
// up to date where something moved, within the budget; turn them into
// per-receiver flux deltas against the baked baseline (current minus
// baseline shares of every baked emitter, plus new emitters); bounce the
// deltas through the receivers' own cached shares; compensate what was not
// shot as ambient; publish the deltas for shading.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "runtime_impl.h"
#include "scene/numeric.h"

namespace svit {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

bool Runtime::Impl::anythingDue() const {
  return std::any_of(
      emitter_set.emitters.begin(), emitter_set.emitters.end(), [&](const Emitter& e) {
        return settings.refresh_all
                   ? needsMaps(e)
                   : (outOfDate(e) && needsMaps(e)) || (e.isStale() && e.needs_baseline);
      });
}

Status Runtime::Impl::ensureRenderer() {
  if (renderer) return Status();
  rt::IndexMapSettings map_settings;
  map_settings.resolution = settings.map_resolution;
  map_settings.small_polygon_fallback = settings.small_polygon_fallback;
  map_settings.edge_taps = settings.edge_taps;
  map_settings.neighbour_ids = settings.neighbour_ids;
  map_settings.occlusion_culling = settings.occlusion_culling;
  Expected<std::unique_ptr<rt::IndexMapRenderer>> created =
      rt::IndexMapRenderer::create(map_settings);
  if (!created.ok()) return created.status();
  renderer = std::move(created).value();
  renderer->setStaticTriangles(level.static_map);
  renderer->setReceiverCount(uint32_t(receivers.size()));
  ++gl_objects_created;
  return Status();
}

void Runtime::Impl::ensureBakedEmitters() {
  if (emitter_set.baked_emitters_added) return;
  rt::addBakedEmitters(emitter_set, emitterContext());
  emitter_set.baked_emitters_added = true;
}

void Runtime::Impl::rebuildDynamicMaps() {
  dynamic_map = rt::dynamicMapTriangles(objects);
  object_map_base.assign(objects.size(), 0);
  uint32_t base = 0;
  for (size_t o = 0; o < objects.size(); ++o) {
    object_map_base[o] = base;
    if (objects[o].visible && !objects[o].removed) base += uint32_t(objects[o].albedo.size());
  }
  renderer->setDynamicTriangles(dynamic_map);
  renderer->setReceiverCount(uint32_t(receivers.size()));
  // Every dynamic emitter's samples follow its triangle (and its place in the map set).
  for (Emitter& e : emitter_set.emitters) {
    if (e.kind == EmitterKind::kDynamicObject) e.samples_stale = true;
  }
  // Emissive objects are primary emitters.
  double max_flux = 0;
  for (const Emitter& e : emitter_set.emitters) max_flux = std::max(max_flux, luminanceOf(e.flux));
  for (size_t o = 0; o < objects.size(); ++o) {
    const rt::DynamicObject& object = objects[o];
    double flux = 0;
    for (size_t t = 0; t < object.emission.size(); ++t) {
      flux += kPi * luminance(object.emission[t]) * receivers[object.first_receiver + t].area_m2;
    }
    for (uint32_t bin = 0; flux > 0 && bin < kObjectShooters; ++bin) {
      const uint32_t g = level.static_groups + uint32_t(o) * kObjectShooters + bin;
      if (emitter_set.group_emitter[g] == kInvalidId) {
        rt::addGroupEmitter(emitter_set, emitterContext(), g, false, flux,
                            std::max(max_flux, flux));
      }
    }
  }
  changes.dynamic_geometry_changed = false;
}

void Runtime::Impl::addRuntimeLightEmitters() {
  for (size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].emitter != kInvalidId || lights[i].removed) continue;
    Emitter e;
    e.kind = EmitterKind::kRuntimeLight;
    e.index = uint32_t(i);
    e.sample_count = settings.min_samples_per_emitter;
    emitter_set.emitters.push_back(std::move(e));
    lights[i].emitter = uint32_t(emitter_set.emitters.size() - 1);
  }
}

// A baked emitter with nothing dynamic in its reach and its baked scale
// adds exactly nothing: it settles to its baseline without a map.
void Runtime::Impl::settleUnreachedBakedEmitters() {
  for (Emitter& e : emitter_set.emitters) {
    if (!e.needs_baseline || !e.isStale() || needsMaps(e)) continue;
    if (e.has_baseline) {
      accumulator.setCurrent(e, e.baseline);
    } else {
      accumulator.retractCurrent(e);
      e.markAsBaked();
    }
    e.queue.waiting = false;
  }
}

// Which emitters refresh: by importance for the view (thesis 5.10), or
// brightest first without one.
void Runtime::Impl::rankEmitters(bool by_view, FrameStats& stats) {
  if (by_view) {
    rankForView(stats);
    return;
  }
  ranking.top_importance = 0;
  for (Emitter& e : emitter_set.emitters) {
    e.queue.importance = std::max(0.0, luminanceOf(e.flux)) * std::max(1.0, emitterScale(e));
    e.queue.interval = 1;
  }
}

// Baselines first (the static level's shares, once per emitter); an emitter
// nothing dynamic reaches then needs no second map. Then the current shares
// of every scheduled emitter that is still out of date.
Status Runtime::Impl::refreshScheduled(const std::vector<rt::RefreshDecision>& decisions,
                                       bool by_view, FrameStats& stats) {
  std::vector<Emitter>& emitters = emitter_set.emitters;
  std::vector<uint32_t> baseline_ids, current_ids;
  for (const rt::RefreshDecision& d : decisions) {
    const Emitter& e = emitters[d.emitter];
    if (e.needs_baseline && !e.has_baseline) baseline_ids.push_back(d.emitter);
    RefreshReason reason = d.reason;
    if (!by_view && reason != RefreshReason::kLightChanged) reason = RefreshReason::kNoView;
    if (settings.refresh_all) reason = RefreshReason::kRefreshAll;
    stats.refreshes.push_back({d.emitter, reason, d.importance});
  }
  Status status = gatherShares(baseline_ids, true, stats);
  for (uint32_t id : baseline_ids) {
    Emitter& e = emitters[id];
    e.reach.touched = reachesAnyObject(e);  // its reach is known now
    if (!e.reach.touched) {
      accumulator.setCurrent(e, e.baseline);
      e.queue.refreshed_frame = changes.frame;
      ++stats.emitters_refreshed;
    } else {
      e.markStale();
    }
  }
  for (const rt::RefreshDecision& d : decisions) {
    if (emitters[d.emitter].state() != rt::SharesState::kCurrent) current_ids.push_back(d.emitter);
  }
  if (status.ok()) status = gatherShares(current_ids, false, stats);
  for (const rt::RefreshDecision& d : decisions) {
    Emitter& e = emitters[d.emitter];
    if (!outOfDate(e)) e.queue.waiting = false;
    e.reach.region_known = e.reach.region_known || e.hasCurrent();
  }
  if (by_view) settleImportance(decisions);
  return status;
}

// Receivers whose reflected delta had no shares to go through get emitters
// (fewer samples as energy falls), budget permitting, and the bounce is
// solved again with them. False when nothing could be shot this frame.
bool Runtime::Impl::shootWanted(std::vector<std::pair<double, uint32_t>>& wanted, double budget,
                                FrameStats& stats, Status& status) {
  std::vector<Emitter>& emitters = emitter_set.emitters;
  double total = 0, covered = 0;
  for (auto& [w, r] : wanted) total += w;
  std::vector<uint32_t> fresh;
  for (auto& [w, r] : wanted) {
    if (covered >= (1.0 - settings.bounce_stop_share) * total) break;
    covered += w;
    const uint32_t id =
        rt::addGroupEmitter(emitter_set, emitterContext(), r, false, w, wanted.front().first);
    emitters[id].bounce_requested = true;
    if (!emitters[id].hasCurrent()) fresh.push_back(id);
  }
  // Within what is left of the budget, most wanted first (the order of `wanted`).
  std::vector<rt::RefreshCandidate> bounce_candidates;
  for (uint32_t id : fresh) {
    rt::RefreshCandidate c;
    c.emitter = id;
    c.importance = double(fresh.size() - bounce_candidates.size());
    c.cost = double(std::max(emitters[id].sample_count, 1));
    bounce_candidates.push_back(c);
  }
  double left = budget;
  for (const EmitterRefresh& r : stats.refreshes)
    left -= double(std::max<size_t>(emitters[r.emitter].samples.size(), 1));
  // No budget left: the wanted shooters wait for the scheduler (by
  // importance) instead of one each pass and a solve again for it.
  if (!stats.refreshes.empty() && left <= 0) return false;
  const std::vector<rt::RefreshDecision> chosen = rt::scheduleRefreshes(
      bounce_candidates, changes.frame, 0.0, 1, stats.refreshes.empty() ? budget : left);
  if (chosen.empty()) return false;
  std::vector<uint32_t> ids;
  for (const rt::RefreshDecision& d : chosen) {
    ids.push_back(d.emitter);
    stats.refreshes.push_back(
        {d.emitter, RefreshReason::kBounce, emitters[d.emitter].queue.importance});
  }
  status = gatherShares(ids, false, stats);
  for (uint32_t id : ids) emitters[id].reach.region_known = true;
  wanted.clear();
  solve(stats, wanted);
  return true;
}

void Runtime::Impl::publish(const Status& status, FrameStats& stats) {
  if (!status.ok()) stats.error = status.message();
  for (const Emitter& e : emitter_set.emitters) {
    if (outOfDate(e) && needsMaps(e)) ++stats.emitters_pending;
  }
  updateObjectsLit();
  uploadDisplay(stats);
  stats.gl_objects_created = gl_objects_created;
}

FrameStats Runtime::Impl::update(double budget_ms) {
  const auto start = Clock::now();
  FrameStats stats;
  ++changes.frame;
  gl_objects_created = 0;
  if (!have_content || (!changes.anythingChanged() && !anythingDue())) {
    stats.idle = true;
    stats.total_ms = msSince(start);
    return stats;
  }
  if (Status s = ensureRenderer(); !s.ok()) {
    stats.error = s.message();
    stats.total_ms = msSince(start);
    return stats;
  }
  ensureBakedEmitters();
  if (changes.dynamic_geometry_changed) rebuildDynamicMaps();
  addRuntimeLightEmitters();
  invalidateMoved();
  updateReach();
  changes.lighting_changed = false;
  if (settings.refresh_all) {
    for (Emitter& e : emitter_set.emitters) {
      if (needsMaps(e)) e.markStale();
    }
  }
  settleUnreachedBakedEmitters();

  const bool by_view = ranking.has_view && settings.importance_caching && !settings.refresh_all;
  rankEmitters(by_view, stats);
  const std::vector<rt::RefreshCandidate> candidates = refreshCandidates();
  double budget = std::numeric_limits<double>::infinity();
  if (!settings.refresh_all) {
    if (budget_ms > 0) budget = std::max(0.0, budget_ms - msSince(start)) / ms_per_sample;
    if (settings.max_samples_per_frame > 0)
      budget = std::min(budget, double(settings.max_samples_per_frame));
  }
  const std::vector<rt::RefreshDecision> decisions =
      rt::scheduleRefreshes(candidates, changes.frame, by_view ? ranking.top_importance : 0.0,
                            by_view ? uint32_t(settings.max_refresh_interval) : 1u, budget);
  Status status = refreshScheduled(decisions, by_view, stats);

  std::vector<std::pair<double, uint32_t>> wanted;
  solve(stats, wanted);
  const double time_limit_ms = budget_ms > 0 ? budget_ms : kNoUpperBound;
  for (int pass = 0; status.ok() && pass < 2 && !wanted.empty() && msSince(start) < time_limit_ms;
       ++pass) {
    if (!shootWanted(wanted, budget, stats, status)) break;
  }
  changes.pending_wanted = false;
  for (auto& [w, r] : wanted) {
    const uint32_t id = emitter_set.group_emitter[r];
    if (id == kInvalidId || !emitter_set.emitters[id].hasCurrent()) changes.pending_wanted = true;
  }
  publish(status, stats);
  stats.total_ms = msSince(start);
  return stats;
}

}  // namespace svit

#pragma once
// One emitter of the runtime and its cache of form factors (thesis 5.10):
// what it is, where its light goes, its shares and their state, and its
// place in the refresh queue. The cache's lifecycle is one enum,
// SharesState, changed only by the transitions below.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bounce_solver.h"
#include "indexmaps/emitter_samples.h"
#include "indexmaps/index_map_culling.h"
#include "indexmaps/index_map_renderer.h"
#include "svit/runtime.h"

namespace svit::gl {

enum class EmitterKind {  // same order as svit::EmitterType
  kBakedLight,            ///< a static light of the bake (BakeData emitter index)
  kSun,                   ///< the baked sun
  kSky,                   ///< the baked sky
  /// a shooter (runtime patches within one bake patch): re-shoots its baseline (bright) and deltas
  kStaticPatch,
  /// one facing of a dynamic object (kObjectShooters per object): emits and reflects
  kDynamicObject,
  kRuntimeLight,  ///< a light the game moves
};

/// The state of an emitter's `current` shares.
///
///   kNone ──refresh──▶ kCurrent ──something moved in its region──▶ kStale
///     ▲                  ▲  │                                         │
///     │                  │  └──nothing dynamic in reach, as baked──▶ kAsBaked
///     └──something moved─┼───────────────────────────────────────────┘
///                        └──refresh (from kStale or kNone)
///
/// kAsBaked keeps no shares: its delta against the bake is exactly zero.
enum class SharesState : uint8_t {
  kNone,     ///< no current shares yet, and they are due
  kAsBaked,  ///< no current shares, none needed: what it lights is the bake's
  kStale,    ///< current shares from before something in its region moved
  kCurrent,  ///< current shares up to date
};

/// An emitter's deltas as coefficients of its share sets (lm per unit share).
struct DeltaTerms {
  uint64_t current_revision = 0;  ///< of the `current` on_current applies to
  glm::dvec3 on_current{0.0};     ///< first-round flux through `current`
  glm::dvec3 on_baseline{0.0};    ///< through `baseline` (taking the baked light back)
  glm::dvec3 direct{0.0};         ///< runtime lights: direct flux through `current`
  bool operator==(const DeltaTerms&) const = default;
};

/// Where an emitter's light goes, as boxes: what object moves can change it.
struct EmitterReach {
  Aabb region;  ///< samples and everything its shares light
  /// from its maps or the bake's factors; unknown = anything may matter
  bool region_known = false;
  Aabb source_box;            ///< where its light leaves from (samples, lamp, shooter patches)
  bool touched = false;       ///< a dynamic object in its reach (computed once per update)
  bool touched_dirty = true;  ///< `touched` needs recomputing: invalidated, or its reach changed
};

/// Its place in importance caching (emitter_importance.h, refresh_scheduler.h).
struct EmitterQueue {
  double importance = 0;          ///< for the last view
  uint32_t interval = 1;          ///< frames it may wait while out of date
  bool waiting = false;           ///< out of date and not yet refreshed
  uint64_t waiting_since = 0;     ///< frame it went out of date
  uint32_t queued_interval = 1;   ///< its interval then
  double settled_importance = 0;  ///< its importance in the last view it was up to date in
  uint64_t refreshed_frame = 0;   ///< the frame its current shares were last made
};

struct Emitter {
  EmitterKind kind = EmitterKind::kBakedLight;
  /// bake emitter (lights, sun, sky), shooter, object * kObjectShooters + bin, light id
  uint32_t index = 0;
  uint32_t bake_emitter = kInvalidId;  ///< BakeData::emitters index when the bake lists it
  /// Baked emitters and bright patches: their delta is current minus
  /// baseline (the static level's shares), so they need both.
  bool needs_baseline = false;
  /// A baked light or the sun with a shadow mask (BakeData::masks): static
  /// surfaces shade its direct light per pixel, so its first-round delta
  /// there is left out of what they show (it still bounces).
  bool masked = false;
  /// Made because a bounce had delta to shoot through its group.
  bool bounce_requested = false;
  glm::dvec3 flux{0.0};  ///< lm: the flux its shares distribute (patches: baseline B x A)
  int sample_count = 1;
  std::vector<PointSample> samples;
  /// the emitter itself moved: its samples are remade before its next maps
  bool samples_stale = true;

  SparseShares current, baseline;
  bool has_baseline = false;
  uint64_t current_revision = 0;  ///< the accumulator's revision when `current` was last set
  /// What it adds to the first-round flux now (delta_accumulator.h): per
  /// unit share of `current` (at current_revision) and of `baseline`.
  DeltaTerms summed;
  /// Baked emitters: the bake's baseline factors spread over the runtime
  /// patches by area, for importance and reach before the first map.
  SparseShares bake_shares;
  /// Static triangles its baseline maps showed (PointSample::
  /// static_triangles), for lit-set culling; empty = unknown, or its
  /// samples changed since (refreshSamples clears it).
  TriangleBits lit_triangles;

  EmitterReach reach;
  EmitterQueue queue;

  SharesState state() const { return state_; }
  bool hasCurrent() const {
    return state_ == SharesState::kStale || state_ == SharesState::kCurrent;
  }
  /// Its current shares (or their absence) no longer hold.
  bool isStale() const { return state_ == SharesState::kNone || state_ == SharesState::kStale; }
  /// Something moved where it reaches, or it moved.
  void markStale() {
    if (state_ == SharesState::kCurrent) state_ = SharesState::kStale;
    if (state_ == SharesState::kAsBaked) state_ = SharesState::kNone;
  }
  /// Fresh current shares were set (delta_accumulator.h sets `current`).
  void markCurrent() { state_ = SharesState::kCurrent; }
  /// Nothing dynamic in its reach at its baked scale: no current shares.
  void markAsBaked() {
    current = {};
    state_ = SharesState::kAsBaked;
  }

 private:
  SharesState state_ = SharesState::kNone;
};

}  // namespace svit::gl

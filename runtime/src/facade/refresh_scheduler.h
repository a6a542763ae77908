#pragma once
// Which out-of-date emitters refresh this frame (thesis 5.10): the most
// important every frame, the rest round-robin at intervals that double each
// time their importance falls by 4x against the most important emitter of
// the view, within a budget. An emitter whose importance rises while it
// waits (a door opens, the view turns) gets a shorter interval at once and
// is promoted. Pure CPU and deterministic: same inputs, same schedule.

#include <cstdint>
#include <vector>

#include "svit/runtime.h"

namespace svit::gl {

struct RefreshCandidate {
  uint32_t emitter = 0;
  double importance = 0;         ///< for this frame's view, >= 0
  double cost = 1;               ///< in budget units (samples or milliseconds), > 0
  uint64_t waiting_since = 0;    ///< frame it went out of date
  uint32_t queued_interval = 1;  ///< its interval when it went out of date
  /// Its importance while it was last up to date (0: unknown); twice that
  /// or more now promotes it at once (a door opened onto what it lights).
  double settled_importance = 0;
  /// a switched or dimmed emitter with nothing cached: goes first, always
  bool urgent = false;
};

struct RefreshDecision {
  uint32_t emitter = 0;
  RefreshReason reason = RefreshReason::kImportant;
  double importance = 0;
};

/// Frames an emitter of `importance` may wait when the view's most important
/// emitter has `top`: 1 within 4x of it, doubling per further 4x, at most
/// `max_interval`; `max_interval` when it accounts for nothing.
uint32_t refreshInterval(double importance, double top, uint32_t max_interval);

/// The candidates due this frame (urgent ones, and those that waited their
/// interval or were promoted): urgent ones always; then the promoted ones
/// (importance doubled since last up to date), most important first; then
/// the important ones (interval 1), most important first, within three
/// quarters of `budget` while any round-robin one is due; then the
/// round-robin ones, longest waiting first; then the rest of the important
/// ones, all while the summed cost fits `budget` (ties: lower emitter id).
/// The first emitter of a frame always goes, so every frame makes progress.
std::vector<RefreshDecision> scheduleRefreshes(const std::vector<RefreshCandidate>& candidates,
                                               uint64_t frame, double top, uint32_t max_interval,
                                               double budget);

}  // namespace svit::gl

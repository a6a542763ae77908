// The refresh schedule of importance caching; see refresh_scheduler.h.

#include "refresh_scheduler.h"

#include <algorithm>
#include <cmath>

namespace svit::gl {

uint32_t refreshInterval(double importance, double top, uint32_t max_interval) {
  max_interval = std::max(max_interval, 1u);
  if (!(importance > 0) || !(top > 0)) return max_interval;
  const double ratio = top / importance;
  if (ratio < 4.0) return 1;
  // floor(log4(ratio)) doublings, computed without overflow for huge ratios.
  const double doublings = std::floor(std::log(ratio) / std::log(4.0));
  if (doublings >= 31) return max_interval;
  return std::min(max_interval, uint32_t(1) << uint32_t(doublings));
}

std::vector<RefreshDecision> scheduleRefreshes(const std::vector<RefreshCandidate>& candidates,
                                               uint64_t frame, double top, uint32_t max_interval,
                                               double budget) {
  struct Due {
    const RefreshCandidate* c;
    RefreshReason reason;
  };
  std::vector<Due> due;
  for (const RefreshCandidate& c : candidates) {
    if (c.urgent) {
      due.push_back({&c, RefreshReason::kLightChanged});
      continue;
    }
    const uint32_t interval = refreshInterval(c.importance, top, max_interval);
    const uint64_t waited = frame >= c.waiting_since ? frame - c.waiting_since : 0;
    const bool risen = c.settled_importance > 0 && c.importance >= 2.0 * c.settled_importance;
    if (waited + 1 < interval && !risen) continue;
    // Due now but not under the interval it had when it went out of date,
    // or by a risen importance: promoted.
    const bool promoted = risen || (interval < c.queued_interval && waited + 1 < c.queued_interval);
    RefreshReason reason = interval == 1 ? RefreshReason::kImportant : RefreshReason::kRoundRobin;
    if (promoted) reason = RefreshReason::kPromoted;
    due.push_back({&c, reason});
  }
  // Urgent and promoted first; then the important (interval 1) most important first,
  // and the round-robin ones longest waiting first. The round-robin ones
  // get a quarter of the budget whenever any is due, so a budget too small
  // for everything never starves the rest of the level.
  std::vector<Due> urgent, important, round_robin;
  for (const Due& d : due) {
    // A promoted emitter's light just started to matter (a door opened):
    // it goes with the urgent ones, before the steadily important.
    if (d.c->urgent || d.reason == RefreshReason::kPromoted) {
      urgent.push_back(d);
    } else if (refreshInterval(d.c->importance, top, max_interval) == 1) {
      important.push_back(d);
    } else {
      round_robin.push_back(d);
    }
  }
  auto byImportance = [](const Due& a, const Due& b) {
    if (a.c->importance != b.c->importance) return a.c->importance > b.c->importance;
    return a.c->emitter < b.c->emitter;
  };
  std::sort(urgent.begin(), urgent.end(), byImportance);
  std::sort(important.begin(), important.end(), byImportance);
  std::sort(round_robin.begin(), round_robin.end(), [&](const Due& a, const Due& b) {
    if (a.c->waiting_since != b.c->waiting_since) return a.c->waiting_since < b.c->waiting_since;
    return byImportance(a, b);
  });
  std::vector<RefreshDecision> chosen;
  double spent = 0;
  for (const Due& d : urgent) {
    // Switched lamps always; promoted ones while the budget lasts.
    if (!d.c->urgent && !chosen.empty() && spent + d.c->cost > budget) continue;
    chosen.push_back({d.c->emitter, d.reason, d.c->importance});
    spent += d.c->cost;
  }
  // Takes from `list` (from `next` on) while the cost fits `limit`; the
  // first emitter of a frame always goes, so every frame makes progress.
  auto take = [&](const std::vector<Due>& list, size_t& next, double limit) {
    for (; next < list.size(); ++next) {
      const Due& d = list[next];
      if (!chosen.empty() && spent + d.c->cost > limit) return;
      chosen.push_back({d.c->emitter, d.reason, d.c->importance});
      spent += d.c->cost;
    }
  };
  size_t next_important = 0, next_round_robin = 0;
  take(important, next_important, round_robin.empty() ? budget : 0.75 * budget);
  take(round_robin, next_round_robin, budget);
  take(important, next_important, budget);
  return chosen;
}

}  // namespace svit::gl

// The refresh schedule of importance caching (runtime/src/facade/refresh_scheduler.h):
// intervals from importance, what each frame refreshes and why. Pure CPU.

#include <gtest/gtest.h>

#include <algorithm>

#include "facade/refresh_scheduler.h"

namespace svit::gl {
namespace {

RefreshCandidate candidate(uint32_t emitter, double importance, double cost = 1,
                           uint64_t waiting_since = 1) {
  RefreshCandidate c;
  c.emitter = emitter;
  c.importance = importance;
  c.cost = cost;
  c.waiting_since = waiting_since;
  c.queued_interval = 1;
  return c;
}

TEST(RefreshInterval, DoublesPerFourfoldDropAndCaps) {
  EXPECT_EQ(refreshInterval(100, 100, 32), 1u);
  EXPECT_EQ(refreshInterval(26, 100, 32), 1u);
  EXPECT_EQ(refreshInterval(25, 100, 32), 2u);
  EXPECT_EQ(refreshInterval(100.0 / 16, 100, 32), 4u);
  EXPECT_EQ(refreshInterval(100.0 / 64, 100, 32), 8u);
  EXPECT_EQ(refreshInterval(1e-9, 100, 32), 32u);
  EXPECT_EQ(refreshInterval(0, 100, 32), 32u);
  EXPECT_EQ(refreshInterval(5, 0, 32), 32u);
  EXPECT_EQ(refreshInterval(1e-300, 1e300, 8), 8u);
}

TEST(ScheduleRefreshes, ImportantEveryFrameTheRestAtTheirInterval) {
  // Emitter 0 is the view's most important, 1 is 16x less (interval 4).
  std::vector<int> refreshed(2, 0);
  uint64_t waiting_since[2] = {1, 1};
  for (uint64_t frame = 1; frame <= 16; ++frame) {
    std::vector<RefreshCandidate> c = {candidate(0, 100, 1, waiting_since[0]),
                                       candidate(1, 100.0 / 16, 1, waiting_since[1])};
    for (const RefreshDecision& d : scheduleRefreshes(c, frame, 100, 32, 1e9)) {
      ++refreshed[d.emitter];
      waiting_since[d.emitter] = frame + 1;  // out of date again next frame
      EXPECT_EQ(d.reason, d.emitter == 0 ? RefreshReason::kImportant : RefreshReason::kRoundRobin);
    }
  }
  EXPECT_EQ(refreshed[0], 16);
  EXPECT_EQ(refreshed[1], 4);
}

TEST(ScheduleRefreshes, ARisenImportancePromotesAtOnce) {
  RefreshCandidate low = candidate(3, 1.0, 1, 10);
  low.queued_interval = refreshInterval(1.0, 1000, 32);
  EXPECT_TRUE(scheduleRefreshes({candidate(0, 1000), low}, 10, 1000, 32, 1e9).size() == 1);
  // The door opens: it now lights visible patches (importance 40 >= 2 x 1).
  low.importance = 40;
  low.settled_importance = 1;
  // It goes before the steadily important one, even on a budget of one.
  const std::vector<RefreshDecision> chosen =
      scheduleRefreshes({candidate(0, 1000), low}, 10, 1000, 32, 1);
  ASSERT_EQ(chosen.size(), 1u);
  EXPECT_EQ(chosen[0].emitter, 3u);
  EXPECT_EQ(chosen[0].reason, RefreshReason::kPromoted);
}

TEST(ScheduleRefreshes, UrgentAlwaysGoesFirstWhateverTheBudget) {
  RefreshCandidate urgent = candidate(7, 0.0, 5);
  urgent.urgent = true;
  const std::vector<RefreshDecision> chosen =
      scheduleRefreshes({candidate(0, 1000, 1), urgent}, 1, 1000, 32, 1);
  ASSERT_GE(chosen.size(), 1u);
  EXPECT_EQ(chosen[0].emitter, 7u);
  EXPECT_EQ(chosen[0].reason, RefreshReason::kLightChanged);
}

TEST(ScheduleRefreshes, ASmallBudgetStillServesTheLongestWaiting) {
  // Ten important emitters would fill the budget of 8; two overdue
  // unimportant ones still get the quarter kept for them.
  std::vector<RefreshCandidate> c;
  for (uint32_t i = 0; i < 10; ++i) c.push_back(candidate(i, 1000 - i, 1, 20));
  c.push_back(candidate(100, 1, 1, 2));
  c.push_back(candidate(101, 1, 1, 5));
  const std::vector<RefreshDecision> chosen = scheduleRefreshes(c, 20, 1000, 8, 8);
  ASSERT_EQ(chosen.size(), 8u);
  EXPECT_EQ(chosen[0].emitter, 0u);
  EXPECT_EQ(chosen[6].emitter, 100u);  // longest waiting first
  EXPECT_EQ(chosen[7].emitter, 101u);
  EXPECT_EQ(chosen[6].reason, RefreshReason::kRoundRobin);
}

TEST(ScheduleRefreshes, TheFirstAlwaysGoesAndTheScheduleIsDeterministic) {
  std::vector<RefreshCandidate> c = {candidate(4, 10, 50), candidate(2, 10, 1),
                                     candidate(9, 10, 1)};
  const std::vector<RefreshDecision> a = scheduleRefreshes(c, 3, 10, 32, 2);
  const std::vector<RefreshDecision> b = scheduleRefreshes(c, 3, 10, 32, 2);
  ASSERT_EQ(a.size(), 1u);  // ties by id: 2 first, then 4 does not fit
  EXPECT_EQ(a[0].emitter, 2u);
  ASSERT_EQ(b.size(), a.size());
  EXPECT_EQ(b[0].emitter, a[0].emitter);
}

}  // namespace
}  // namespace svit::gl

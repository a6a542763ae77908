// The bounce solver's incremental solves (bounce_solver.h) against a solve
// from nothing: through random changes of the primary deltas, of groups'
// shares, of receivers' albedo, group and presence, and appended rooms,
// every solve matches; a change in one room of many costs that room.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "indexmaps/sample_random.h"
#include "lighting/bounce_solver.h"

namespace svit::gl {
namespace {

constexpr uint32_t kRoomReceivers = 40;
/// receivers per group; every tenth receiver shoots with none
constexpr uint32_t kGroupReceivers = 4;

/// Rooms of receivers whose groups light (part of) their own room only.
struct Level {
  std::vector<Receiver> receivers;
  std::vector<glm::dvec3> first;
  std::vector<int32_t> group_of;
  std::vector<SparseShares> shares;  ///< per group
  std::vector<char> has_shares;      ///< per group
  std::vector<uint64_t> revisions;   ///< per group
  uint64_t next_revision = 1;
  uint64_t draws = 0;
  bool doorways = false;  ///< groups also light a few receivers of the rooms either side

  float uniform() { return uniform01(7, 0, draws++); }
  uint32_t below(uint32_t n) { return std::min(uint32_t(uniform() * float(n)), n - 1); }

  uint32_t rooms() const { return uint32_t(receivers.size() / kRoomReceivers); }
  void newShares(uint32_t g) {
    const uint32_t room = g / (kRoomReceivers / kGroupReceivers);
    SparseShares s;
    const float keep = 0.3f + 0.6f * uniform();
    for (uint32_t i = 0; i < kRoomReceivers; ++i) {
      if (uniform() >= keep) continue;
      s.receivers.push_back(room * kRoomReceivers + i);
      s.shares.push_back(0.9f * uniform() / float(kRoomReceivers));
    }
    if (doorways) {
      std::vector<std::pair<uint32_t, float>> entries;
      for (size_t i = 0; i < s.receivers.size(); ++i)
        entries.push_back({s.receivers[i], s.shares[i]});
      for (int side : {-1, 1}) {
        const int64_t next = int64_t(room) + side;
        if (next < 0 || next >= int64_t(rooms())) continue;
        for (uint32_t i = 0; i < 3; ++i)
          entries.push_back({uint32_t(next) * kRoomReceivers + i, 0.05f});
      }
      std::sort(entries.begin(), entries.end());
      s = {};
      for (auto [r, share] : entries) {
        s.receivers.push_back(r);
        s.shares.push_back(share);
      }
    }
    shares[g] = s;
    has_shares[g] = 1;
    revisions[g] = next_revision++;
  }
  void addRoom(bool lit) {
    const uint32_t first_group = uint32_t(shares.size());
    for (uint32_t i = 0; i < kRoomReceivers; ++i) {
      Receiver r;
      r.area_m2 = 0.5f + uniform();
      r.albedo = Rgb{0.05f + 0.9f * uniform(), 0.05f + 0.9f * uniform(), 0.05f + 0.9f * uniform()};
      receivers.push_back(r);
      group_of.push_back(i % 10 == 9 ? -1 : int32_t(first_group + i / kGroupReceivers));
      first.push_back(lit ? glm::dvec3(uniform(), uniform(), uniform()) * 100.0 : glm::dvec3(0.0));
    }
    for (uint32_t g = 0; g < kRoomReceivers / kGroupReceivers; ++g) {
      shares.emplace_back();
      has_shares.push_back(0);
      revisions.push_back(0);
      newShares(first_group + g);
      if (g % 3 == 2) has_shares.back() = 0;  // not cached yet: wanted
    }
  }
  std::vector<const SparseShares*> shooters() const {
    std::vector<const SparseShares*> out(shares.size(), nullptr);
    for (size_t g = 0; g < shares.size(); ++g) {
      if (has_shares[g]) out[g] = &shares[g];
    }
    return out;
  }
  std::vector<uint64_t> shooterRevisions() const {
    std::vector<uint64_t> out(revisions);
    for (size_t g = 0; g < out.size(); ++g) {
      if (!has_shares[g]) out[g] = 0;
    }
    return out;
  }

  /// One random change of the kind a frame brings.
  void change() {
    const uint32_t room = below(rooms()), r = room * kRoomReceivers + below(kRoomReceivers);
    const uint32_t g =
        room * (kRoomReceivers / kGroupReceivers) + below(kRoomReceivers / kGroupReceivers);
    switch (below(8)) {
      case 0:  // an emitter refreshed: new deltas over part of a room
        for (uint32_t i = 0; i < kRoomReceivers; i += 1 + below(4)) {
          first[room * kRoomReceivers + i] +=
              glm::dvec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 50.0;
        }
        break;
      case 1:  // a room back to as baked
        for (uint32_t i = 0; i < kRoomReceivers; ++i)
          first[room * kRoomReceivers + i] = glm::dvec3(0.0);
        break;
      case 2: newShares(g); break;
      case 3: has_shares[g] = !has_shares[g]; break;
      case 4: receivers[r].albedo.g = 0.05f + 0.9f * uniform(); break;
      case 5:  // hidden or shown again
        receivers[r].area_m2 = receivers[r].area_m2 > 0 ? 0.0f : 0.5f + uniform();
        break;
      case 6: group_of[r] = group_of[r] < 0 ? int32_t(g) : -1; break;
      case 7:
        if (rooms() < 12) addRoom(true);
        break;
    }
  }
};

double largestLum(const std::vector<glm::dvec3>& v) {
  double m = 0;
  for (const glm::dvec3& c : v) m = std::max({m, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
  return m;
}

void expectSameSolve(const BounceResult& got, const BounceResult& want, int step) {
  ASSERT_EQ(got.received.size(), want.received.size()) << "step " << step;
  ASSERT_EQ(got.wanted.size(), want.wanted.size()) << "step " << step;
  EXPECT_EQ(got.rounds, want.rounds) << "step " << step;
  const double tolerance = 1e-9 * std::max(largestLum(want.received), 1e-30);
  for (size_t r = 0; r < want.received.size(); ++r) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(got.received[r][c], want.received[r][c], tolerance)
          << "step " << step << " receiver " << r;
    }
  }
  double wanted_scale = 1e-30;
  for (double w : want.wanted) wanted_scale = std::max(wanted_scale, w);
  for (size_t g = 0; g < want.wanted.size(); ++g) {
    ASSERT_NEAR(got.wanted[g], want.wanted[g], 1e-9 * wanted_scale)
        << "step " << step << " group " << g;
    ASSERT_EQ(got.wanted[g] > 0, want.wanted[g] > 0) << "step " << step << " group " << g;
  }
  EXPECT_NEAR(got.unshot_share, want.unshot_share, 1e-9) << "step " << step;
}

void matchThroughChanges(const BounceSettings& settings) {
  Level level;
  for (int i = 0; i < 6; ++i) level.addRoom(i % 2 == 0);
  BounceSolver solver;
  int incremental = 0;
  for (int step = 0; step < 400; ++step) {
    level.change();
    const BounceResult& got = solver.solve(level.receivers, level.first, level.group_of,
                                           level.shooters(), level.shooterRevisions(), settings);
    incremental += solver.lastFromNothing() ? 0 : 1;
    const BounceResult want =
        bounceDeltas(level.receivers, level.first, level.group_of, level.shooters(), settings);
    expectSameSolve(got, want, step);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Most solves reused the rounds (else this tested the solve from nothing twice).
  EXPECT_GT(incremental, 200);
}

BounceSettings exact() {
  BounceSettings settings;
  settings.min_shot_share = 0;
  return settings;
}

TEST(BounceSolver, MatchesASolveFromNothingThroughRandomChanges) { matchThroughChanges(exact()); }

TEST(BounceSolver, MatchesWhenRoundsStopEarlyAndLate) {
  // A high stop share makes the number of rounds follow the changes: rounds
  // that stop or stop being the last.
  BounceSettings settings = exact();
  settings.stop_share = 0.2;
  settings.max_bounces = 6;
  matchThroughChanges(settings);
}

TEST(BounceSolver, AChangeInOneRoomCostsThatRoom) {
  // 64 rooms in a row, each group lighting its room and the doorways either
  // side, deltas in every room: an exact solve ripples a change in room 17
  // through the doorways, one room further each round; changes below
  // min_shot_share of the first round stay unshot (ambient).
  size_t work[2] = {0, 0};
  std::vector<BounceResult> results;
  for (int exactly = 0; exactly < 2; ++exactly) {
    Level level;
    level.doorways = true;
    for (int i = 0; i < 64; ++i) level.addRoom(true);
    for (uint32_t g = 0; g < level.shares.size(); ++g) level.has_shares[g] = 1;
    BounceSolver solver;
    const BounceSettings settings = exactly ? exact() : BounceSettings{};
    solver.solve(level.receivers, level.first, level.group_of, level.shooters(),
                 level.shooterRevisions(), settings);
    ASSERT_TRUE(solver.lastFromNothing());
    const size_t from_nothing = solver.lastWork();
    // One emitter refreshed in room 17: its deltas, and one group's shares.
    for (uint32_t i = 0; i < kRoomReceivers; i += 3) level.first[17 * kRoomReceivers + i] *= 0.5;
    level.newShares(17 * (kRoomReceivers / kGroupReceivers) + 4);
    results.push_back(solver.solve(level.receivers, level.first, level.group_of, level.shooters(),
                                   level.shooterRevisions(), settings));
    EXPECT_FALSE(solver.lastFromNothing());
    work[exactly] = solver.lastWork();
    EXPECT_LT(work[exactly] * 16, from_nothing) << work[exactly] << " vs " << from_nothing;
    const BounceResult want =
        bounceDeltas(level.receivers, level.first, level.group_of, level.shooters(), exact());
    if (exactly) {
      expectSameSolve(results.back(), want, 0);
    } else {
      // Off by what went unshot: at most min_shot_share of the first
      // round's |flux| per group and round (the first round's |flux| is
      // below 100 lm x 3 x 0.95 per receiver), spread as ambient.
      const double first_round = 3 * 100.0 * double(level.receivers.size());
      const double bound =
          settings.min_shot_share * first_round * double(level.shares.size()) * want.rounds;
      for (size_t r = 0; r < want.received.size(); ++r) {
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(results.back().received[r][c], want.received[r][c], bound) << r;
      }
    }
  }
  // Here 2,060 against 3,046 shooting every change.
  EXPECT_LT(work[0] * 4, work[1] * 3) << work[0] << " vs " << work[1] << " shooting every change";
}

TEST(BounceSolver, BackToTheBakeIsExactlyZero) {
  Level level;
  for (int i = 0; i < 4; ++i) level.addRoom(true);
  BounceSolver solver;
  const BounceSettings settings;
  for (int step = 0; step < 20; ++step) {
    level.change();
    solver.solve(level.receivers, level.first, level.group_of, level.shooters(),
                 level.shooterRevisions(), settings);
  }
  std::fill(level.first.begin(), level.first.end(), glm::dvec3(0.0));
  const BounceResult& got = solver.solve(level.receivers, level.first, level.group_of,
                                         level.shooters(), level.shooterRevisions(), settings);
  for (const glm::dvec3& r : got.received) EXPECT_EQ(r, glm::dvec3(0.0));
  for (double w : got.wanted) EXPECT_EQ(w, 0.0);
  EXPECT_EQ(got.unshot_share, 0.0);
}

}  // namespace
}  // namespace svit::gl

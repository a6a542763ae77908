// Emitter importance of importance caching (runtime/src/lighting/emitter_importance.h):
// direct and reflected light on visible pixels, out-of-date share sets, and
// the block-indexed sums against an every-share oracle. Pure CPU.

#include <gtest/gtest.h>

#include <algorithm>

#include "indexmaps/sample_random.h"
#include "lighting/emitter_importance.h"

namespace svit::gl {
namespace {

// Two rooms: receivers 0-1 in the viewed room, 2-3 in the other. Group 0
// (receivers 0-1) and group 1 (2-3) shoot.
ViewWeights twoRooms() {
  ViewWeights v;
  v.weight = {10, 10, 0, 0};
  v.reflectance = {0.5, 0.5, 0.5, 0.5};
  v.group_of = {0, 0, 1, 1};
  v.group_shares = {nullptr, nullptr};
  return v;
}

TEST(EmitterImportance, DirectLightOnVisiblePixels) {
  SparseShares here{{0, 1}, {0.25f, 0.25f}, {}, {}}, there{{2, 3}, {0.5f, 0.5f}, {}, {}};
  const std::vector<double> imp =
      emitterImportance(twoRooms(), {{100, {&here}, -1}, {100, {&there}, -1}});
  // 100 lm x (0.25 + 0.25) x 10 = 500, plus its light reflected by group 0,
  // whose V is borrowed from the emitter itself: 100 x 0.5 x 0.5 x 5 = 125.
  EXPECT_NEAR(imp[0], 625, 1e-9);
  EXPECT_NEAR(imp[1], 0, 1e-12);
}

TEST(EmitterImportance, ThroughASecondaryEmitterThatLightsTheView) {
  // The other room's lamp lights only receivers 2-3; their group 1 shoots
  // half its flux onto receiver 0 (a doorway).
  SparseShares lamp{{2, 3}, {0.5f, 0.5f}, {}, {}}, wall{{0}, {0.5f}, {}, {}};
  ViewWeights v = twoRooms();
  v.group_shares = {nullptr, &wall};
  const std::vector<double> imp = emitterImportance(v, {{100, {&lamp}, -1}});
  // V_1 = 0.5 x 10 = 5 per lm; reflected 100 x 1 x 0.5 = 50 lm -> 250.
  EXPECT_NEAR(imp[0], 250, 1e-9);
}

TEST(EmitterImportance, AnOutOfDateCacheCountsItsLargerShareSet) {
  SparseShares door_shut{{2}, {0.5f}, {}, {}}, door_open{{0, 2}, {0.3f, 0.2f}, {}, {}};
  const std::vector<double> imp =
      emitterImportance(twoRooms(), {{10, {&door_shut, &door_open}, -1}});
  // At least what the open door's set puts on visible pixels directly: 10 lm x 0.3 x 10.
  EXPECT_GE(imp[0], 30.0 - 1e-9);
}

/// The importance of emitter_importance.h as its formulas read, every
/// share of every set visited: the oracle for the skipping one.
std::vector<double> everyShareImportance(const ViewWeights& v,
                                         const std::vector<ImportanceQuery>& queries) {
  const size_t groups = v.group_shares.size();
  auto direct = [&](const SparseShares& s) {
    double sum = 0;
    for (size_t i = 0; i < s.receivers.size(); ++i)
      sum += double(s.shares[i]) * v.weight[s.receivers[i]];
    return sum;
  };
  std::vector<double> per_lumen(groups, 0.0), borrowed(groups, 0.0), weight(groups, 0.0);
  for (size_t g = 0; g < groups; ++g) {
    if (v.group_shares[g]) per_lumen[g] = direct(*v.group_shares[g]);
  }
  // A view below 1e-3 of the largest (a group's own, a set's direct) is none.
  double largest = 0;
  for (double p : per_lumen) largest = std::max(largest, p);
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) largest = std::max(largest, direct(*s));
  }
  const double negligible = 1e-3 * largest;
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      const double d = direct(*s) < negligible ? 0.0 : direct(*s);
      for (size_t i = 0; i < s->receivers.size(); ++i) {
        const int32_t g = v.group_of[s->receivers[i]];
        if (g < 0 || v.group_shares[size_t(g)]) continue;
        const double w = q.flux * double(s->shares[i]) * v.reflectance[s->receivers[i]];
        borrowed[size_t(g)] += w * d;
        weight[size_t(g)] += w;
      }
    }
  }
  for (size_t g = 0; g < groups; ++g) {
    if (!v.group_shares[g] && weight[g] > 0) per_lumen[g] = borrowed[g] / weight[g];
    if (per_lumen[g] < negligible) per_lumen[g] = 0;
  }
  std::vector<double> out;
  for (const ImportanceQuery& q : queries) {
    double best = 0;
    for (const SparseShares* s : q.shares) {
      double per_flux = direct(*s);
      for (size_t i = 0; i < s->receivers.size(); ++i) {
        const int32_t g = v.group_of[s->receivers[i]];
        if (g >= 0)
          per_flux += double(s->shares[i]) * v.reflectance[s->receivers[i]] * per_lumen[size_t(g)];
      }
      best = std::max(best, per_flux);
    }
    if (q.shares.empty() && q.own_group >= 0) best = per_lumen[size_t(q.own_group)];
    out.push_back(q.flux * best);
  }
  return out;
}

TEST(EmitterImportance, IndexedSharesSkipWhatTheViewCannotSee) {
  // 16 rooms of 100 receivers, groups of 5; the view sees part of room 3.
  // Half the groups have shares of their own, the rest borrow. Every
  // emitter lights its room, and some also a doorway into the next room.
  constexpr uint32_t kRooms = 16, kRoom = 100, kGroup = 5;
  uint64_t draw = 0;
  auto uniform = [&] { return uniform01(11, 0, draw++); };
  ViewWeights v;
  for (uint32_t r = 0; r < kRooms * kRoom; ++r) {
    v.weight.push_back(r / kRoom == 3 && uniform() < 0.6f ? 20.0 * uniform() : 0.0);
    v.reflectance.push_back(0.1 + 0.8 * uniform());
    v.group_of.push_back(r % 10 == 9 ? -1 : int32_t(r / kGroup));
  }
  auto lightRoom = [&](uint32_t room, bool doorway) {
    SparseShares s;
    for (uint32_t i = 0; i < kRoom; ++i) {
      if (uniform() < 0.5f) continue;
      s.receivers.push_back(room * kRoom + i);
      s.shares.push_back(0.9f * uniform() / float(kRoom));
    }
    if (doorway && room + 1 < kRooms) {
      for (uint32_t i = 0; i < 3; ++i) {
        s.receivers.push_back((room + 1) * kRoom + i);
        s.shares.push_back(0.01f);
      }
    }
    return s;
  };
  std::vector<SparseShares> group_sets, emitter_sets;
  for (uint32_t g = 0; g < kRooms * kRoom / kGroup; ++g)
    group_sets.push_back(lightRoom(g * kGroup / kRoom, g % 7 == 0));
  for (uint32_t e = 0; e < 3 * kRooms; ++e) emitter_sets.push_back(lightRoom(e / 3, e % 2 == 0));
  // A lamp lighting only what the view does not see in its room: no direct
  // view, yet it weighs in the borrowed V of the groups it lights.
  SparseShares unseen;
  for (uint32_t r = 3 * kRoom; r < 4 * kRoom; ++r) {
    if (v.weight[r] != 0) continue;
    unseen.receivers.push_back(r);
    unseen.shares.push_back(0.02f);
  }
  emitter_sets.push_back(unseen);
  auto importance = [&](bool indexed, bool oracle) {
    std::vector<SparseShares> groups = group_sets, emitters = emitter_sets;
    if (indexed) {
      for (SparseShares& s : groups) s.indexBlocks();
      for (SparseShares& s : emitters) s.indexBlocks();
    }
    ViewWeights view = v;
    view.group_shares.assign(groups.size(), nullptr);
    for (size_t g = 0; g < groups.size(); g += 2) view.group_shares[g] = &groups[g];
    std::vector<ImportanceQuery> queries;
    for (size_t e = 0; e < emitters.size(); ++e)
      queries.push_back({100.0 + double(e), {&emitters[e]}, -1});
    // borrowing shooters
    for (size_t g = 1; g < groups.size(); g += 2) queries.push_back({5.0, {}, int32_t(g)});
    if (oracle) return everyShareImportance(view, queries);
    // The batch reuses groupView's direct sums; one query at a time sums
    // them again: the same numbers, bit for bit.
    const std::vector<double> all = emitterImportance(view, queries);
    const GroupView group_view = groupView(view, queries);
    for (size_t i = 0; i < queries.size(); ++i)
      EXPECT_EQ(importanceOf(group_view, queries[i]), all[i]) << "query " << i;
    return all;
  };
  const std::vector<double> oracle = importance(false, true), plain = importance(false, false),
                            indexed = importance(true, false);
  ASSERT_EQ(plain.size(), oracle.size());
  EXPECT_EQ(indexed, plain);  // skipping adds exactly nothing
  int lit = 0, dark = 0;
  for (size_t i = 0; i < plain.size(); ++i) {
    // Sums over blocks against sums over every share: rounding apart.
    EXPECT_NEAR(plain[i], oracle[i], 1e-12 * oracle[i]) << "query " << i;
    (plain[i] > 0 ? lit : dark) += 1;
  }
  // Both kinds occur: rooms 2-4 matter (doorways), the rest add nothing.
  EXPECT_GT(lit, 6);
  EXPECT_GT(dark, 30);
}

}  // namespace
}  // namespace svit::gl

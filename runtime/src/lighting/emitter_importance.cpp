// Importance of emitters for a view; see emitter_importance.h.

#include "emitter_importance.h"

#include <algorithm>
#include <unordered_map>

namespace svit::gl {
namespace {

/// A per-lumen view below this share of the largest (a group's, or an
/// emitter's direct) counts as none: the light of a wall three doorways
/// away. Per lumen, an emitter lighting only such walls shows under 1e-3
/// of what the most visible light shows; at equal flux refreshInterval
/// gives that 32 frames (its default cap) anyway. Counting them would make
/// every pass visit the shares of every room a line of doorways connects.
constexpr double kNegligibleView = 1e-3;

/// Calls visit(i) for every share i of `s` whose receiver lies in a marked
/// block (every share of a set not indexed), in ascending order.
template <typename Visit>
void forEachMarked(const SparseShares& s, const std::vector<char>& marks, Visit visit) {
  if (s.blocks.empty()) {
    for (size_t i = 0; i < s.receivers.size(); ++i) visit(i);
    return;
  }
  for (size_t k = 0; k < s.blocks.size(); ++k) {
    if (s.blocks[k] >= marks.size() || !marks[s.blocks[k]]) continue;
    const size_t end = k + 1 < s.blocks.size() ? s.block_begin[k + 1] : s.receivers.size();
    for (size_t i = s.block_begin[k]; i < end; ++i) visit(i);
  }
}

/// The blocks holding a receiver `holds` says yes to.
template <typename Holds>
std::vector<char> blocksWhere(size_t receivers, Holds holds) {
  std::vector<char> blocks((receivers + kShareBlockReceivers - 1) / kShareBlockReceivers, 0);
  for (size_t r = 0; r < receivers; ++r) {
    if (holds(r)) blocks[r / kShareBlockReceivers] = 1;
  }
  return blocks;
}

/// sum s_r w_r, over the weighted blocks only (elsewhere w_r = 0).
double weighted(const SparseShares& s, const std::vector<double>& weight,
                const std::vector<char>& weighted_blocks) {
  double sum = 0;
  forEachMarked(s, weighted_blocks, [&](size_t i) {
    if (s.receivers[i] < weight.size()) sum += double(s.shares[i]) * weight[s.receivers[i]];
  });
  return sum;
}

}  // namespace

namespace {

// The direct view of each distinct share set, summed once: a group's own
// shares are its emitter's current ones, which that emitter's query holds
// too.
class DirectViews {
 public:
  DirectViews(const ViewWeights& view, const std::vector<char>& weighted_blocks)
      : view_(view), weighted_blocks_(weighted_blocks) {}
  double of(const SparseShares* s) {
    const auto [it, fresh] = direct_of_.try_emplace(s, 0.0);
    if (fresh) it->second = weighted(*s, view_.weight, weighted_blocks_);
    return it->second;
  }

 private:
  const ViewWeights& view_;
  const std::vector<char>& weighted_blocks_;
  std::unordered_map<const SparseShares*, double> direct_of_;
};

// The group receiver `r` borrows a view for (one with no shares of its
// own), or -1.
struct Borrowers {
  const ViewWeights& view;
  const std::vector<char>& has_own;
  int32_t of(uint32_t r) const {
    if (r >= view.group_of.size()) return -1;
    const int32_t g = view.group_of[r];
    return g < 0 || size_t(g) >= has_own.size() || has_own[size_t(g)] ? -1 : g;
  }
};

// The groups lit by a set of non-zero direct view (`direct`, per set of
// the queries) on a receiver that reflects: the only ones that borrow.
std::vector<char> borrowingGroups(const ViewWeights& view,
                                  const std::vector<ImportanceQuery>& queries,
                                  const std::vector<double>& direct, const Borrowers& borrowers) {
  std::vector<char> borrows(borrowers.has_own.size(), 0);
  size_t k = 0;
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      if (direct[k++] == 0 || q.flux == 0) continue;
      for (uint32_t r : s->receivers) {
        const int32_t g = borrowers.of(r);
        if (g >= 0 && r < view.reflectance.size() && view.reflectance[r] != 0)
          borrows[size_t(g)] = 1;
      }
    }
  }
  return borrows;
}

// Borrowed V: the flux-weighted mean direct view of the emitters lighting
// a group that has no shares of its own, into per_lumen. Only the
// borrowing groups' receivers are visited (for the mean's weights, in
// query order).
void borrowViews(const ViewWeights& view, const std::vector<ImportanceQuery>& queries,
                 const std::vector<double>& direct, const Borrowers& borrowers,
                 const std::vector<char>& borrows, std::vector<double>& per_lumen) {
  const size_t groups = borrows.size();
  const std::vector<char> borrowing_blocks = blocksWhere(view.weight.size(), [&](size_t r) {
    const int32_t g = borrowers.of(uint32_t(r));
    return g >= 0 && borrows[size_t(g)];
  });
  std::vector<double> borrowed(groups, 0.0), borrowed_weight(groups, 0.0);
  size_t k = 0;
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      const double d = direct[k++];
      if (s == nullptr) continue;
      forEachMarked(*s, borrowing_blocks, [&](size_t i) {
        const uint32_t r = s->receivers[i];
        const int32_t g = borrowers.of(r);
        if (g < 0) return;
        const double w = q.flux * double(s->shares[i]) * view.reflectance[r];
        borrowed[size_t(g)] += w * d;
        borrowed_weight[size_t(g)] += w;
      });
    }
  }
  for (size_t g = 0; g < groups; ++g) {
    if (!borrowers.has_own[g] && borrowed_weight[g] > 0)
      per_lumen[g] = borrowed[g] / borrowed_weight[g];
  }
}

// What each receiver reflects towards the view per lumen it receives.
void reflectedView(const ViewWeights& view, GroupView& out) {
  const size_t groups = out.per_lumen.size(), n = view.weight.size();
  out.reflected.assign(n, 0.0);
  for (size_t r = 0; r < n && r < view.group_of.size(); ++r) {
    const int32_t g = view.group_of[r];
    if (g >= 0 && size_t(g) < groups)
      out.reflected[r] = view.reflectance[r] * out.per_lumen[size_t(g)];
  }
  out.reflected_blocks = blocksWhere(n, [&](size_t r) { return out.reflected[r] != 0; });
}

}  // namespace

GroupView groupView(const ViewWeights& view, const std::vector<ImportanceQuery>& queries) {
  const size_t groups = view.group_shares.size(), n = view.weight.size();
  GroupView out;
  out.per_lumen.assign(groups, 0.0);
  out.weight = view.weight;
  out.weighted_blocks = blocksWhere(n, [&](size_t r) { return view.weight[r] != 0; });
  DirectViews direct_views(view, out.weighted_blocks);
  std::vector<char> has_own(groups, 0);
  for (size_t g = 0; g < groups; ++g) {
    if (view.group_shares[g] == nullptr) continue;
    out.per_lumen[g] = direct_views.of(view.group_shares[g]);
    has_own[g] = 1;
  }
  double largest = 0;
  for (double v : out.per_lumen) largest = std::max(largest, v);
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      out.direct.push_back(s == nullptr ? 0.0 : direct_views.of(s));
      largest = std::max(largest, out.direct.back());
    }
  }
  const double negligible = kNegligibleView * largest;
  std::vector<double> direct = out.direct;  // what borrowing counts: negligible views cut
  for (double& d : direct) {
    if (d < negligible) d = 0;
  }
  const Borrowers borrowers{view, has_own};
  const std::vector<char> borrows = borrowingGroups(view, queries, direct, borrowers);
  borrowViews(view, queries, direct, borrowers, borrows, out.per_lumen);
  for (size_t g = 0; g < groups; ++g) {
    if (out.per_lumen[g] < negligible) out.per_lumen[g] = 0;
  }
  reflectedView(view, out);
  return out;
}

namespace {

// A query's importance from the direct view of each of its sets
// (`direct(k, set)`, k counting its sets).
template <typename Direct>
double importanceWith(const GroupView& group_view, const ImportanceQuery& q, Direct direct) {
  const size_t groups = group_view.per_lumen.size();
  double best = 0;
  bool any = false;
  for (size_t k = 0; k < q.shares.size(); ++k) {
    const SparseShares* s = q.shares[k];
    if (s == nullptr) continue;
    any = true;
    // Direct, and through the groups it lights.
    best = std::max(
        best, direct(k, *s) + weighted(*s, group_view.reflected, group_view.reflected_blocks));
  }
  if (!any && q.own_group >= 0 && size_t(q.own_group) < groups)
    best = group_view.per_lumen[size_t(q.own_group)];
  return q.flux * best;
}

}  // namespace

double importanceOf(const GroupView& group_view, const ImportanceQuery& q) {
  return importanceWith(group_view, q, [&](size_t, const SparseShares& s) {
    return weighted(s, group_view.weight, group_view.weighted_blocks);
  });
}

std::vector<double> importanceOfAll(const GroupView& group_view,
                                    const std::vector<ImportanceQuery>& queries) {
  std::vector<double> importance(queries.size(), 0.0);
  size_t first = 0;  // the query's first set in group_view.direct
  for (size_t i = 0; i < queries.size(); ++i) {
    if (first + queries[i].shares.size() > group_view.direct.size()) {
      importance[i] = importanceOf(group_view, queries[i]);  // not the queries groupView had
    } else {
      importance[i] = importanceWith(group_view, queries[i], [&](size_t k, const SparseShares&) {
        return group_view.direct[first + k];
      });
    }
    first += queries[i].shares.size();
  }
  return importance;
}

std::vector<double> emitterImportance(const ViewWeights& view,
                                      const std::vector<ImportanceQuery>& queries) {
  return importanceOfAll(groupView(view, queries), queries);
}

}  // namespace svit::gl

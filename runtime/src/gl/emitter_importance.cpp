// Importance of emitters for a view; see emitter_importance.h.

#include "emitter_importance.h"

#include <algorithm>

namespace svit::gl {
namespace {

/// Whether a share set may land in a marked block (not indexed: may).
bool landsIn(const SparseShares& s, const std::vector<char>& blocks) {
  if (s.blocks.empty()) return !s.receivers.empty();
  for (uint32_t b : s.blocks) {
    if (b < blocks.size() && blocks[b]) return true;
  }
  return false;
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

/// sum s_r w_r; a set landing in no weighted block is exactly zero.
double weighted(const SparseShares& s, const std::vector<double>& weight, const std::vector<char>& weighted_blocks) {
  if (!landsIn(s, weighted_blocks)) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < s.receivers.size(); ++i) {
    if (s.receivers[i] < weight.size()) sum += double(s.shares[i]) * weight[s.receivers[i]];
  }
  return sum;
}

}  // namespace

GroupView groupView(const ViewWeights& view, const std::vector<ImportanceQuery>& queries) {
  const size_t groups = view.group_shares.size(), n = view.weight.size();
  GroupView out;
  out.per_lumen.assign(groups, 0.0);
  out.weighted_blocks = blocksWhere(n, [&](size_t r) { return view.weight[r] != 0; });
  std::vector<char> has_own(groups, 0);
  for (size_t g = 0; g < groups; ++g) {
    if (view.group_shares[g] == nullptr) continue;
    out.per_lumen[g] = weighted(*view.group_shares[g], view.weight, out.weighted_blocks);
    has_own[g] = 1;
  }
  auto borrowerOf = [&](uint32_t r) -> int32_t {
    if (r >= view.group_of.size()) return -1;
    const int32_t g = view.group_of[r];
    return g < 0 || size_t(g) >= groups || has_own[size_t(g)] ? -1 : g;
  };
  // Borrowed V: the flux-weighted mean direct view of the emitters lighting
  // a group that has no shares of its own. Only groups lit by a set of
  // non-zero direct view borrow anything; the sets that light them (for
  // the mean's weights) are visited in query order, the rest skipped.
  std::vector<double> direct;
  std::vector<char> borrows(groups, 0);
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      direct.push_back(s == nullptr ? 0.0 : weighted(*s, view.weight, out.weighted_blocks));
      if (direct.back() == 0 || q.flux == 0) continue;
      for (uint32_t r : s->receivers) {
        const int32_t g = borrowerOf(r);
        if (g >= 0 && r < view.reflectance.size() && view.reflectance[r] != 0) borrows[size_t(g)] = 1;
      }
    }
  }
  const std::vector<char> borrowing_blocks = blocksWhere(n, [&](size_t r) {
    const int32_t g = borrowerOf(uint32_t(r));
    return g >= 0 && borrows[size_t(g)];
  });
  std::vector<double> borrowed(groups, 0.0), borrowed_weight(groups, 0.0);
  size_t k = 0;
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      const double d = direct[k++];
      if (s == nullptr || (d == 0 && !landsIn(*s, borrowing_blocks))) continue;
      for (size_t i = 0; i < s->receivers.size(); ++i) {
        const uint32_t r = s->receivers[i];
        const int32_t g = borrowerOf(r);
        if (g < 0) continue;
        const double w = q.flux * double(s->shares[i]) * view.reflectance[r];
        borrowed[size_t(g)] += w * d;
        borrowed_weight[size_t(g)] += w;
      }
    }
  }
  for (size_t g = 0; g < groups; ++g) {
    if (!has_own[g] && borrowed_weight[g] > 0) out.per_lumen[g] = borrowed[g] / borrowed_weight[g];
  }
  out.reflecting_blocks = blocksWhere(n, [&](size_t r) {
    const int32_t g = r < view.group_of.size() ? view.group_of[r] : -1;
    return g >= 0 && size_t(g) < groups && out.per_lumen[size_t(g)] != 0;
  });
  return out;
}

double importanceOf(const ViewWeights& view, const GroupView& group_view, const ImportanceQuery& q) {
  const size_t groups = group_view.per_lumen.size();
  double best = 0;
  bool any = false;
  for (const SparseShares* s : q.shares) {
    if (s == nullptr) continue;
    any = true;
    double per_flux = weighted(*s, view.weight, group_view.weighted_blocks);  // direct
    if (landsIn(*s, group_view.reflecting_blocks)) {
      for (size_t i = 0; i < s->receivers.size(); ++i) {
        const uint32_t r = s->receivers[i];
        if (r >= view.group_of.size()) continue;
        const int32_t g = view.group_of[r];
        if (g >= 0 && size_t(g) < groups) {
          per_flux += double(s->shares[i]) * view.reflectance[r] * group_view.per_lumen[size_t(g)];
        }
      }
    }
    best = std::max(best, per_flux);
  }
  if (!any && q.own_group >= 0 && size_t(q.own_group) < groups) best = group_view.per_lumen[size_t(q.own_group)];
  return q.flux * best;
}

std::vector<double> emitterImportance(const ViewWeights& view, const std::vector<ImportanceQuery>& queries) {
  const GroupView group_view = groupView(view, queries);
  std::vector<double> importance(queries.size(), 0.0);
  for (size_t k = 0; k < queries.size(); ++k) importance[k] = importanceOf(view, group_view, queries[k]);
  return importance;
}

}  // namespace svit::gl

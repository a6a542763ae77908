// Importance of emitters for a view; see emitter_importance.h.

#include "emitter_importance.h"

#include <algorithm>

namespace svit::gl {
namespace {

double weighted(const SparseShares& s, const std::vector<double>& weight) {
  double sum = 0;
  for (size_t i = 0; i < s.receivers.size(); ++i) {
    if (s.receivers[i] < weight.size()) sum += double(s.shares[i]) * weight[s.receivers[i]];
  }
  return sum;
}

}  // namespace

std::vector<double> groupView(const ViewWeights& view, const std::vector<ImportanceQuery>& queries) {
  const size_t groups = view.group_shares.size();
  std::vector<double> group_view(groups, 0.0);
  std::vector<char> has_own(groups, 0);
  for (size_t g = 0; g < groups; ++g) {
    if (view.group_shares[g] == nullptr) continue;
    group_view[g] = weighted(*view.group_shares[g], view.weight);
    has_own[g] = 1;
  }
  // Borrowed V: the flux-weighted mean direct view of the emitters lighting
  // a group that has no shares of its own.
  std::vector<double> borrowed(groups, 0.0), borrowed_weight(groups, 0.0);
  for (const ImportanceQuery& q : queries) {
    for (const SparseShares* s : q.shares) {
      if (s == nullptr) continue;
      const double direct = weighted(*s, view.weight);
      for (size_t i = 0; i < s->receivers.size(); ++i) {
        const uint32_t r = s->receivers[i];
        if (r >= view.group_of.size()) continue;
        const int32_t g = view.group_of[r];
        if (g < 0 || size_t(g) >= groups || has_own[size_t(g)]) continue;
        const double w = q.flux * double(s->shares[i]) * view.reflectance[r];
        borrowed[size_t(g)] += w * direct;
        borrowed_weight[size_t(g)] += w;
      }
    }
  }
  for (size_t g = 0; g < groups; ++g) {
    if (!has_own[g] && borrowed_weight[g] > 0) group_view[g] = borrowed[g] / borrowed_weight[g];
  }
  return group_view;
}

double importanceOf(const ViewWeights& view, const std::vector<double>& group_view, const ImportanceQuery& q) {
  const size_t groups = group_view.size();
  double best = 0;
  bool any = false;
  for (const SparseShares* s : q.shares) {
    if (s == nullptr) continue;
    any = true;
    double per_flux = weighted(*s, view.weight);  // direct
    for (size_t i = 0; i < s->receivers.size(); ++i) {
      const uint32_t r = s->receivers[i];
      if (r >= view.group_of.size()) continue;
      const int32_t g = view.group_of[r];
      if (g >= 0 && size_t(g) < groups) per_flux += double(s->shares[i]) * view.reflectance[r] * group_view[size_t(g)];
    }
    best = std::max(best, per_flux);
  }
  if (!any && q.own_group >= 0 && size_t(q.own_group) < groups) best = group_view[size_t(q.own_group)];
  return q.flux * best;
}

std::vector<double> emitterImportance(const ViewWeights& view, const std::vector<ImportanceQuery>& queries) {
  const std::vector<double> group_view = groupView(view, queries);
  std::vector<double> importance(queries.size(), 0.0);
  for (size_t k = 0; k < queries.size(); ++k) importance[k] = importanceOf(view, group_view, queries[k]);
  return importance;
}

}  // namespace svit::gl

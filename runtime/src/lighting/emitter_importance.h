#pragma once
// Importance of emitters for a view (thesis 5.9-5.10), from their cached
// form factors: how much of the image an emitter's light accounts for, so
// the scheduler can refresh the ones that matter. CPU only, over per-patch
// sums: O(cached shares landing where the view looks).
//
// The view weight of a receiver is pixels x reflectance / area: irradiance
// E on it shows as E x that many "pixel-lux" of exitance. An emitter of
// flux F with shares s_r puts F s_r / A_r of irradiance on receiver r, so
// its direct importance is F x sum_r s_r w_r; its light reflected by r
// (rho_r F s_r) reaches the view again through r's shooter group g, whose
// own shares give V_g = sum_q s_gq w_q per unit flux. A group with no
// cached shares yet borrows V from the emitters that light it (a secondary
// emitter mostly lights what its own light source lights). A V (or an
// emitter's direct view) below 1e-3 of the largest counts as none.

#include <cstdint>
#include <vector>

#include "bounce_solver.h"

namespace svit::gl {

/// What the receivers and shooter groups look like from the view.
struct ViewWeights {
  std::vector<double> weight;       ///< per receiver: pixels x reflectance / area, 1/m2
  std::vector<double> reflectance;  ///< per receiver: albedo luminance
  std::vector<int32_t> group_of;    ///< per receiver: the group it reflects through, -1 none
  std::vector<const SparseShares*> group_shares;  ///< per group: cached shares, null none
};

/// One emitter to rank: its flux and the share sets it may light by (the
/// importance is the largest over them: a cache that may be out of date
/// counts what it lit before and what the static level lets it light).
struct ImportanceQuery {
  double flux = 0;  ///< luminance, lm (>= 0)
  std::vector<const SparseShares*> shares;
  int32_t own_group = -1;  ///< a static patch group: its borrowed V when it has no shares
};

/// What the groups' light shows, and where a pass over share sets must
/// look (per block of kShareBlockReceivers receivers): share sets landing
/// in no such block add exactly zero and are skipped, so a view costs what
/// it sees, not the level.
struct GroupView {
  std::vector<double> per_lumen;  ///< per group: what its light shows per lumen
  /// per receiver: ViewWeights::weight (a lumen there, seen directly)
  std::vector<double> weight;
  std::vector<char> weighted_blocks;  ///< per block: holds a receiver of view weight != 0
  /// Per receiver: what a lumen arriving there shows once reflected through
  /// its group (reflectance x per_lumen).
  std::vector<double> reflected;
  std::vector<char> reflected_blocks;  ///< per block: holds a receiver of reflected != 0
  /// Per share set of the queries groupView was given, in their order:
  /// its direct view, sum s_r w_r (importanceOfAll's, summed once).
  std::vector<double> direct;
};

/// Per group: what its light shows per lumen (its own shares, or borrowed
/// from the queries lighting it).
GroupView groupView(const ViewWeights& view, const std::vector<ImportanceQuery>& queries);

/// Importance (flux x pixel weight: lm/m2 x pixels) of one query, given
/// groupView(): direct plus reflected view of its best set; the same, bit
/// for bit, whether the shares are indexed (SparseShares::blocks) or not.
double importanceOf(const GroupView& group_view, const ImportanceQuery& query);

/// importanceOf for each of the queries groupView() was given, in order
/// (their direct views taken from it, not summed again).
std::vector<double> importanceOfAll(const GroupView& group_view,
                                    const std::vector<ImportanceQuery>& queries);

/// Importance of each query, in order (groupView + importanceOfAll).
std::vector<double> emitterImportance(const ViewWeights& view,
                                      const std::vector<ImportanceQuery>& queries);

}  // namespace svit::gl

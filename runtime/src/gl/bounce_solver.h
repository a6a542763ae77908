#pragma once
// Bounces of the runtime's flux deltas (thesis 5.3 steps 6-8, 5.5): what
// receivers got in the first round they reflect (albedo x flux) through
// their cached index-map shares, round after round while the energy is
// worth it; what cannot be shot (no cached shares yet, or rounds left over)
// is spread as ambient over all receivers. CPU work over per-patch sums
// only: O(rounds x cached shares).

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "receivers.h"

namespace svit::gl {

/// Which receivers one emitter lights and with what share of its flux.
struct SparseShares {
  std::vector<uint32_t> receivers;  ///< ascending
  std::vector<float> shares;        ///< same length, each in (0, 1]
  double total() const;
};

struct BounceSettings {
  int max_bounces = 4;
  double stop_share = 0.005;  ///< stop when a round's |flux| falls below this share of the first's
  bool ambient = true;
};

struct BounceResult {
  std::vector<glm::dvec3> received;  ///< per receiver: delta flux received, all rounds + ambient, lm
  /// Per group: |reflected delta flux| (luminance) it could not shoot for
  /// lack of cached shares; the caller refreshes the largest.
  std::vector<double> wanted;
  int rounds = 0;
  double unshot_share = 0;  ///< ambient-compensated |flux| / all |flux| reflected
};

/// `first` is the delta flux each receiver gets from the primary emitters.
/// Receivers reflect as groups (hierarchical shooting): `group_of[r]` is the
/// group receiver r shoots with (-1: none), `group_shares[g]` the group's
/// current shares (null: none cached yet). Receivers of zero area take no part.
BounceResult bounceDeltas(const std::vector<Receiver>& receivers, const std::vector<glm::dvec3>& first,
                          const std::vector<int32_t>& group_of,
                          const std::vector<const SparseShares*>& group_shares, const BounceSettings& settings);

}  // namespace svit::gl

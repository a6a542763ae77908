#pragma once
// Bounces of the runtime's flux deltas (thesis 5.3 steps 6-8, 5.5): what
// receivers got in the first round they reflect (albedo x flux) through
// their cached index-map shares, round after round while the energy is
// worth it; what cannot be shot (no cached shares yet, or rounds left over)
// is spread as ambient over all receivers. CPU work over per-patch sums.
//
// The solver keeps every round of the last solve and solves again from
// what changed since (deltas of `first`, groups whose shares changed,
// receivers that changed albedo, group or took part or not): the rounds
// are linear in `first` for fixed shares, so the new rounds are the old
// plus the rounds of the change. A frame that refreshed a few emitters
// costs their rooms, not the level, although every room has deltas.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "receivers/receivers.h"

namespace svit::gl {

/// Receivers per block of SparseShares::blocks.
constexpr uint32_t kShareBlockReceivers = 64;

/// Which receivers one emitter lights and with what share of its flux.
struct SparseShares {
  std::vector<uint32_t> receivers;  ///< ascending
  std::vector<float> shares;        ///< same length, each in (0, 1]
  /// The receivers in runs by block of kShareBlockReceivers ids: the
  /// blocks (ascending, distinct) and where each one's run begins in
  /// `receivers`, so that a pass over every emitter's shares visits only
  /// the blocks it looks at (emitter_importance.h). Empty with receivers:
  /// not indexed, every share visited.
  std::vector<uint32_t> blocks, block_begin;
  double total() const;
  /// Bytes its vectors hold (capacity).
  size_t bytes() const;
  /// Sets `blocks` and `block_begin` from `receivers`.
  void indexBlocks();
};

struct BounceSettings {
  int max_bounces = 4;
  double stop_share = 0.005;  ///< stop when a round's |flux| falls below this share of the first's
  /// A group shoots a change of its reflected flux only above this share of
  /// the first round's |flux|; smaller ones go unshot (ambient) until they
  /// add up. 0: shoot every change (exact).
  double min_shot_share = 1e-6;
  bool ambient = true;
};

struct BounceResult {
  /// per receiver: delta flux received, all rounds + ambient, lm
  std::vector<glm::dvec3> received;
  /// Per group: |reflected delta flux| (luminance) it could not shoot for
  /// lack of cached shares; the caller refreshes the largest.
  std::vector<double> wanted;
  int rounds = 0;
  double unshot_share = 0;  ///< ambient-compensated |flux| / all |flux| reflected
};

/// Solves the bounces again and again as their inputs change.
/// `first` is the delta flux each receiver gets from the primary emitters.
/// Receivers reflect as groups (hierarchical shooting): `group_of[r]` is the
/// group receiver r shoots with (-1: none), `group_shares[g]` the group's
/// current shares (null: none cached yet) and `group_revisions[g]` a number
/// that changes whenever those shares do (the solver keeps a copy of the
/// shares it shot with, to take back what they carried). Receivers of zero
/// area take no part. Receivers and groups may be appended between solves,
/// never removed. With min_shot_share 0 the result equals a solve from
/// nothing up to rounding (relative 1e-12 over thousands of solves); above,
/// it differs by the changes left unshot, at most min_shot_share of the
/// first round per group and round, spread as ambient. A change of
/// settings, or a round that stops being the last (or becomes it), solves
/// from nothing.
/// Thread-safe: no.
class BounceSolver {
 public:
  const BounceResult& solve(const std::vector<Receiver>& receivers,
                            const std::vector<glm::dvec3>& first,
                            const std::vector<int32_t>& group_of,
                            const std::vector<const SparseShares*>& group_shares,
                            const std::vector<uint64_t>& group_revisions,
                            const BounceSettings& settings);

  /// Receivers touched plus shares shot by the last solve: its work.
  size_t lastWork() const { return work_; }
  /// Whether the last solve solved from nothing.
  bool lastFromNothing() const { return from_nothing_; }
  /// Bytes it keeps between solves.
  size_t bytes() const;

 private:
  struct Round {
    std::vector<glm::dvec3> in, out;    ///< per receiver: received, reflected
    std::vector<glm::dvec3> group_out;  ///< per group: reflected by its members
    std::vector<glm::dvec3> shot;       ///< per group: what of it went through its shares
    double abs_out = 0;                 ///< sum of |out| (luminance)
    bool last = false;                  ///< everything reflected goes unshot
  };
  struct ReceiverTerms {  ///< what a receiver's reflection depends on besides what it received
    bool takes_part = false;
    Rgb albedo;
    int32_t group = -1;
  };

  /// What one solve is given besides the first bounce.
  struct SolveInputs {
    const std::vector<Receiver>& receivers;
    const std::vector<int32_t>& group_of;
    const std::vector<const SparseShares*>& group_shares;
    const std::vector<uint64_t>& group_revisions;
  };

  void forget(size_t receivers, size_t groups);
  void grow(size_t receivers, size_t groups);
  /// One incremental solve; false (state half-updated) when a round's last
  /// flag flipped. Its stages: the receivers and groups whose terms or
  /// shares changed, the first bounce's change seeded, then per round the
  /// change received and reflected, then shot; last, what was solved for kept.
  bool resolve(const std::vector<Receiver>& receivers, const std::vector<glm::dvec3>& first,
               const std::vector<int32_t>& group_of,
               const std::vector<const SparseShares*>& group_shares,
               const std::vector<uint64_t>& group_revisions);
  static ReceiverTerms termsOf(const SolveInputs& in, size_t r);
  bool sharesChanged(const SolveInputs& in, size_t g) const;
  std::vector<uint32_t> changedReceivers(const SolveInputs& in) const;
  std::vector<uint32_t> reshotGroups(const SolveInputs& in) const;
  void seedFirstDeltas(const std::vector<glm::dvec3>& first, size_t receivers);
  void appendRound(size_t receivers, size_t groups);
  void reflectRound(Round& round, const std::vector<uint32_t>& changed, const SolveInputs& in);
  void shootRound(Round& round, const std::vector<uint32_t>& reshot, bool last,
                  const SolveInputs& in);
  void keepSolved(const std::vector<uint32_t>& changed, const std::vector<uint32_t>& reshot,
                  const SolveInputs& in);
  void shoot(const SparseShares& shares, const glm::dvec3& flux);
  void finish(const std::vector<Receiver>& receivers,
              const std::vector<const SparseShares*>& group_shares);

  BounceSettings settings_;
  std::vector<Round> rounds_;
  std::vector<glm::dvec3> first_;        ///< the last solve's first
  std::vector<ReceiverTerms> terms_;     ///< per receiver, as last solved
  std::vector<SparseShares> shot_with_;  ///< per group: the shares last shot with
  std::vector<char> shot_none_;          ///< per group: it had no shares
  std::vector<uint64_t> revision_;       ///< per group: of shot_with_
  glm::dvec3 unshot_{0.0};
  /// since the last solve from nothing: the scale of rounding residues
  double largest_first_round_ = 0;
  // Scratch of one round: the next round's incoming deltas (zero outside
  // `next_list_`), the groups' reflected deltas (zero outside their list).
  std::vector<glm::dvec3> delta_in_, next_in_, delta_group_;
  std::vector<uint32_t> in_list_, next_list_, group_list_;
  std::vector<char> in_mark_, next_mark_, group_mark_, wanted_mark_;
  std::vector<uint32_t> wanted_list_;
  BounceResult result_;
  size_t work_ = 0;
  bool from_nothing_ = false;
};

/// One solve from nothing (tests, tools).
BounceResult bounceDeltas(const std::vector<Receiver>& receivers,
                          const std::vector<glm::dvec3>& first,
                          const std::vector<int32_t>& group_of,
                          const std::vector<const SparseShares*>& group_shares,
                          const BounceSettings& settings);

}  // namespace svit::gl

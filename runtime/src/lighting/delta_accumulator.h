#pragma once
// The emitters' first-round deltas summed per receiver (thesis 5.3): each
// emitter's light as coefficients of its two share sets (DeltaTerms), and
// the sums kept by adding what changed since the last solve, so a frame
// costs the emitters it refreshed, switched or dimmed, not every emitter's
// shares.

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "emitter.h"

namespace svit::gl {

class DeltaAccumulator {
 public:
  /// Per receiver: the sum of every emitter's DeltaTerms over its shares.
  /// the bounce's first round, lm
  const std::vector<glm::dvec3>& firstFlux() const { return first_flux_; }
  /// runtime lights' direct flux, lm
  const std::vector<glm::dvec3>& directFlux() const { return direct_flux_; }
  /// masked baked lights' share of firstFlux (Emitter::masked), lm: their
  /// direct light, which static surfaces shade per pixel
  const std::vector<glm::dvec3>& maskedFlux() const { return masked_flux_; }
  /// Counts every setting of an Emitter::current.
  uint64_t revisions() const { return revisions_; }

  /// Takes an emitter's terms on `current` out of the sums; call before
  /// replacing or dropping `current`.
  void retractCurrent(Emitter& e);
  /// Replaces its current shares (retracting the old ones); it is then up to date.
  void setCurrent(Emitter& e, SparseShares shares);
  /// Brings the sums over `receiver_count` receivers up to date with every
  /// emitter's terms now (`terms_of`).
  void sum(std::vector<Emitter>& emitters, size_t receiver_count,
           const std::function<DeltaTerms(const Emitter&)>& terms_of);

 private:
  std::vector<glm::dvec3> first_flux_, direct_flux_, masked_flux_;
  uint64_t revisions_ = 0;
};

}  // namespace svit::gl

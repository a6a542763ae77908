#include "delta_accumulator.h"

#include <algorithm>

namespace svit::gl {
namespace {

void addShares(std::vector<glm::dvec3>& to, const SparseShares& shares, const glm::dvec3& flux) {
  if (flux == glm::dvec3(0.0)) return;
  for (size_t i = 0; i < shares.receivers.size(); ++i)
    to[shares.receivers[i]] += flux * double(shares.shares[i]);
}

}  // namespace

void DeltaAccumulator::retractCurrent(Emitter& e) {
  if (!e.hasCurrent() || e.summed.current_revision != e.current_revision) return;
  addShares(first_flux_, e.current, -e.summed.on_current);
  if (e.masked) addShares(masked_flux_, e.current, -e.summed.on_current);
  addShares(direct_flux_, e.current, -e.summed.direct);
  e.summed.on_current = e.summed.direct = glm::dvec3(0.0);
  e.summed.current_revision = 0;
}

void DeltaAccumulator::setCurrent(Emitter& e, SparseShares shares) {
  retractCurrent(e);
  e.current = std::move(shares);
  e.current_revision = ++revisions_;
  e.markCurrent();
}

void DeltaAccumulator::sum(std::vector<Emitter>& emitters, size_t receiver_count,
                           const std::function<DeltaTerms(const Emitter&)>& terms_of) {
  first_flux_.resize(receiver_count, glm::dvec3(0.0));  // receivers are only ever appended
  direct_flux_.resize(receiver_count, glm::dvec3(0.0));
  masked_flux_.resize(receiver_count, glm::dvec3(0.0));
  for (Emitter& e : emitters) {
    const DeltaTerms now = terms_of(e);
    DeltaTerms& was = e.summed;
    if (now == was) continue;
    if (was.current_revision != now.current_revision &&
        (was.on_current != glm::dvec3(0.0) || was.direct != glm::dvec3(0.0))) {
      // A current replaced without retractCurrent: what it carried is
      // unknown, so sum every emitter again.
      std::fill(first_flux_.begin(), first_flux_.end(), glm::dvec3(0.0));
      std::fill(direct_flux_.begin(), direct_flux_.end(), glm::dvec3(0.0));
      std::fill(masked_flux_.begin(), masked_flux_.end(), glm::dvec3(0.0));
      for (Emitter& other : emitters) other.summed = DeltaTerms{};
      sum(emitters, receiver_count, terms_of);
      return;
    }
    const bool same_current = was.current_revision == now.current_revision;
    const glm::dvec3 on_current = same_current ? was.on_current : glm::dvec3(0.0);
    const glm::dvec3 direct = same_current ? was.direct : glm::dvec3(0.0);
    if (e.hasCurrent()) {
      addShares(first_flux_, e.current, now.on_current - on_current);
      if (e.masked) addShares(masked_flux_, e.current, now.on_current - on_current);
      addShares(direct_flux_, e.current, now.direct - direct);
    }
    addShares(first_flux_, e.baseline, now.on_baseline - was.on_baseline);
    if (e.masked) addShares(masked_flux_, e.baseline, now.on_baseline - was.on_baseline);
    was = now;
  }
}

}  // namespace svit::gl

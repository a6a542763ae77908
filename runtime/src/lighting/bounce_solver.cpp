#include "bounce_solver.h"

#include <algorithm>
#include <cmath>

#include "scene/numeric.h"

namespace svit::gl {
namespace {

/// A group's reflected flux below this share of the largest first round
/// since the last solve from nothing is the residue of sums kept by adding
/// deltas (relative rounding 1e-16 per addition), not flux it wants shot.
constexpr double kResidueShare = 1e-12;

void mark(uint32_t i, std::vector<char>& marks, std::vector<uint32_t>& list) {
  if (marks[i]) return;
  marks[i] = 1;
  list.push_back(i);
}

}  // namespace

double SparseShares::total() const {
  double sum = 0;
  for (float s : shares) sum += s;
  return sum;
}

size_t SparseShares::bytes() const {
  return (receivers.capacity() + blocks.capacity() + block_begin.capacity()) * sizeof(uint32_t) +
         shares.capacity() * sizeof(float);
}

void SparseShares::indexBlocks() {
  blocks.clear();
  block_begin.clear();
  for (size_t i = 0; i < receivers.size(); ++i) {
    const uint32_t block = receivers[i] / kShareBlockReceivers;
    if (!blocks.empty() && blocks.back() == block) continue;
    blocks.push_back(block);
    block_begin.push_back(uint32_t(i));
  }
}

size_t BounceSolver::bytes() const {
  size_t vectors =
      first_.capacity() + delta_in_.capacity() + next_in_.capacity() + delta_group_.capacity();
  for (const Round& round : rounds_) {
    vectors += round.in.capacity() + round.out.capacity() + round.group_out.capacity() +
               round.shot.capacity();
  }
  size_t bytes = vectors * sizeof(glm::dvec3) + terms_.capacity() * sizeof(ReceiverTerms);
  for (const SparseShares& s : shot_with_) bytes += s.bytes();
  return bytes;
}

void BounceSolver::forget(size_t receivers, size_t groups) {
  rounds_.clear();
  first_.clear();
  terms_.clear();
  shot_with_.clear();
  shot_none_.clear();
  revision_.clear();
  delta_in_.clear();
  next_in_.clear();
  delta_group_.clear();
  in_list_.clear();
  next_list_.clear();
  group_list_.clear();
  wanted_list_.clear();
  in_mark_.clear();
  next_mark_.clear();
  group_mark_.clear();
  wanted_mark_.clear();
  unshot_ = glm::dvec3(0.0);
  largest_first_round_ = 0;
  result_ = BounceResult{};
  grow(receivers, groups);
}

void BounceSolver::grow(size_t receivers, size_t groups) {
  const glm::dvec3 zero(0.0);
  first_.resize(receivers, zero);
  terms_.resize(receivers);
  delta_in_.resize(receivers, zero);
  next_in_.resize(receivers, zero);
  in_mark_.resize(receivers, 0);
  next_mark_.resize(receivers, 0);
  for (Round& round : rounds_) {
    round.in.resize(receivers, zero);
    round.out.resize(receivers, zero);
    round.group_out.resize(groups, zero);
    round.shot.resize(groups, zero);
  }
  shot_with_.resize(groups);
  shot_none_.resize(groups, 1);
  revision_.resize(groups, 0);
  delta_group_.resize(groups, zero);
  group_mark_.resize(groups, 0);
  wanted_mark_.resize(groups, 0);
  result_.wanted.resize(groups, 0.0);
}

const BounceResult& BounceSolver::solve(const std::vector<Receiver>& receivers,
                                        const std::vector<glm::dvec3>& first,
                                        const std::vector<int32_t>& group_of,
                                        const std::vector<const SparseShares*>& group_shares,
                                        const std::vector<uint64_t>& group_revisions,
                                        const BounceSettings& settings) {
  const size_t n = receivers.size(), groups = group_shares.size();
  // Nothing differs from the bake: solve that from nothing, exactly zero
  // (instead of the residues of taking every delta back).
  const bool none = std::all_of(first.begin(), first.end(),
                                [](const glm::dvec3& f) { return f == glm::dvec3(0.0); });
  from_nothing_ = none || rounds_.empty() || n < first_.size() || groups < shot_none_.size() ||
                  settings.max_bounces != settings_.max_bounces ||
                  settings.stop_share != settings_.stop_share ||
                  settings.min_shot_share != settings_.min_shot_share;
  settings_ = settings;
  work_ = 0;
  if (from_nothing_) {
    forget(n, groups);
  } else {
    grow(n, groups);
  }
  if (!resolve(receivers, first, group_of, group_shares, group_revisions)) {
    // A round stopped being the last or became it: the rounds kept are no
    // longer the rounds to update. Solve from nothing, where none can flip.
    from_nothing_ = true;
    forget(n, groups);
    resolve(receivers, first, group_of, group_shares, group_revisions);
  }
  finish(receivers, group_shares);
  return result_;
}

BounceSolver::ReceiverTerms BounceSolver::termsOf(const SolveInputs& in, size_t r) {
  return ReceiverTerms{in.receivers[r].area_m2 > 0, in.receivers[r].albedo, in.group_of[r]};
}

bool BounceSolver::sharesChanged(const SolveInputs& in, size_t g) const {
  const bool none = in.group_shares[g] == nullptr;
  return none != bool(shot_none_[g]) || (!none && in.group_revisions[g] != revision_[g]);
}

// Receivers whose own terms changed are visited every round; the rest
// only where what they receive changed.
std::vector<uint32_t> BounceSolver::changedReceivers(const SolveInputs& in) const {
  std::vector<uint32_t> changed;
  for (size_t r = 0; r < in.receivers.size(); ++r) {
    const ReceiverTerms now = termsOf(in, r);
    const ReceiverTerms& was = terms_[r];
    const bool same_albedo =
        !now.takes_part || (now.albedo.r == was.albedo.r && now.albedo.g == was.albedo.g &&
                            now.albedo.b == was.albedo.b);
    if (now.takes_part != was.takes_part || now.group != was.group || !same_albedo)
      changed.push_back(uint32_t(r));
  }
  return changed;
}

std::vector<uint32_t> BounceSolver::reshotGroups(const SolveInputs& in) const {
  std::vector<uint32_t> reshot;
  for (size_t g = 0; g < in.group_shares.size(); ++g) {
    if (sharesChanged(in, g)) reshot.push_back(uint32_t(g));
  }
  return reshot;
}

void BounceSolver::seedFirstDeltas(const std::vector<glm::dvec3>& first, size_t receivers) {
  for (size_t r = 0; r < receivers; ++r) {
    const glm::dvec3 delta = first[r] - first_[r];
    if (delta == glm::dvec3(0.0)) continue;
    delta_in_[r] = delta;
    mark(uint32_t(r), in_mark_, in_list_);
  }
}

void BounceSolver::appendRound(size_t receivers, size_t groups) {
  Round fresh;
  fresh.in.assign(receivers, glm::dvec3(0.0));
  fresh.out.assign(receivers, glm::dvec3(0.0));
  fresh.group_out.assign(groups, glm::dvec3(0.0));
  fresh.shot.assign(groups, glm::dvec3(0.0));
  rounds_.push_back(std::move(fresh));
}

// Receive the change, reflect anew; what a receiver reflected before
// leaves its old group, what it reflects now joins its new one.
void BounceSolver::reflectRound(Round& round, const std::vector<uint32_t>& changed,
                                const SolveInputs& in) {
  for (uint32_t r : changed) mark(r, in_mark_, in_list_);
  std::sort(in_list_.begin(), in_list_.end());
  for (uint32_t r : in_list_) {
    in_mark_[r] = 0;
    round.in[r] += delta_in_[r];
    delta_in_[r] = glm::dvec3(0.0);
    const ReceiverTerms now = termsOf(in, r);
    const glm::dvec3 out = now.takes_part
                               ? round.in[r] * glm::dvec3(now.albedo.r, now.albedo.g, now.albedo.b)
                               : glm::dvec3(0.0);
    const glm::dvec3 old_out = round.out[r];
    const int32_t old_group = terms_[r].group;
    if (out == old_out && now.group == old_group) continue;
    round.abs_out += absLuminanceOf(out) - absLuminanceOf(old_out);
    round.out[r] = out;
    for (auto [group, flux] : {std::pair{old_group, -old_out}, std::pair{now.group, out}}) {
      if (flux == glm::dvec3(0.0)) continue;
      if (group < 0) {
        unshot_ += flux;
      } else {
        delta_group_[size_t(group)] += flux;
        mark(uint32_t(group), group_mark_, group_list_);
      }
    }
  }
  work_ += in_list_.size();
  in_list_.clear();
}

// Shoot the groups' change; a group whose shares changed takes back what
// its old shares carried and shoots all it reflects through the new. A
// change too small to be worth shooting (min_shot_share) stays with the
// group and goes unshot until it adds up, so a room's change does not
// ripple through every doorway of the level at a vanishing share of its
// size. In the dense solver's order (ascending groups).
void BounceSolver::shootRound(Round& round, const std::vector<uint32_t>& reshot, bool last,
                              const SolveInputs& in) {
  const double min_shot = settings_.min_shot_share * rounds_[0].abs_out;
  for (uint32_t g : reshot) mark(g, group_mark_, group_list_);
  std::sort(group_list_.begin(), group_list_.end());
  for (uint32_t g : group_list_) {
    group_mark_[g] = 0;
    const glm::dvec3 old_out = round.group_out[g], out = old_out + delta_group_[g];
    delta_group_[g] = glm::dvec3(0.0);
    round.group_out[g] = out;
    mark(g, wanted_mark_, wanted_list_);
    const glm::dvec3 old_shot = round.shot[g];
    glm::dvec3 shot = old_shot;
    const SparseShares* shares = in.group_shares[g];
    if (last) {
      shot = glm::dvec3(0.0);
    } else if (sharesChanged(in, g)) {
      if (!shot_none_[g]) shoot(shot_with_[g], -old_shot);
      shot = shares ? out : glm::dvec3(0.0);
      if (shares) shoot(*shares, shot);
    } else if (shares && absLuminanceOf(out - old_shot) > min_shot) {
      shoot(*shares, out - old_shot);
      shot = out;
    }
    // Unshot: all a group reflects minus what went through its shares.
    unshot_ += (out - shot) - (old_out - old_shot);
    round.shot[g] = shot;
  }
  group_list_.clear();
}

// Keeps what this solve was solved for, for the next to compare with.
void BounceSolver::keepSolved(const std::vector<uint32_t>& changed,
                              const std::vector<uint32_t>& reshot, const SolveInputs& in) {
  for (uint32_t r : changed) terms_[r] = termsOf(in, r);
  for (uint32_t g : reshot) {
    const SparseShares* now = in.group_shares[g];
    shot_none_[g] = now == nullptr;
    shot_with_[g] = now ? *now : SparseShares{};
    revision_[g] = in.group_revisions[g];
    mark(g, wanted_mark_, wanted_list_);
  }
}

bool BounceSolver::resolve(const std::vector<Receiver>& receivers,
                           const std::vector<glm::dvec3>& first,
                           const std::vector<int32_t>& group_of,
                           const std::vector<const SparseShares*>& group_shares,
                           const std::vector<uint64_t>& group_revisions) {
  const size_t n = receivers.size(), groups = group_shares.size();
  const SolveInputs in{receivers, group_of, group_shares, group_revisions};
  const std::vector<uint32_t> changed = changedReceivers(in);
  const std::vector<uint32_t> reshot = reshotGroups(in);
  seedFirstDeltas(first, n);
  const size_t kept_rounds = rounds_.size();
  for (size_t k = 0;; ++k) {
    if (k == rounds_.size()) appendRound(n, groups);
    Round& round = rounds_[k];
    reflectRound(round, changed, in);
    const bool last = int(k) >= settings_.max_bounces ||
                      round.abs_out <= settings_.stop_share * rounds_[0].abs_out ||
                      !(round.abs_out > 0);
    if (k < kept_rounds && last != round.last) return false;
    round.last = last;
    shootRound(round, reshot, last, in);
    if (last) break;
    std::swap(delta_in_, next_in_);
    std::swap(in_list_, next_list_);
    std::swap(in_mark_, next_mark_);
  }
  keepSolved(changed, reshot, in);
  first_ = first;
  largest_first_round_ = std::max(largest_first_round_, rounds_[0].abs_out);
  return true;
}

void BounceSolver::shoot(const SparseShares& shares, const glm::dvec3& flux) {
  if (flux == glm::dvec3(0.0)) return;
  // What a share misses (escapes, absorbing backs) is simply lost, as in
  // the bake.
  for (size_t i = 0; i < shares.receivers.size(); ++i) {
    const uint32_t r = shares.receivers[i];
    mark(r, next_mark_, next_list_);
    next_in_[r] += flux * double(shares.shares[i]);
  }
  work_ += shares.receivers.size();
}

void BounceSolver::finish(const std::vector<Receiver>& receivers,
                          const std::vector<const SparseShares*>& group_shares) {
  const size_t n = receivers.size();
  const double residue = kResidueShare * largest_first_round_;
  for (uint32_t g : wanted_list_) {
    wanted_mark_[g] = 0;
    double wanted = 0;
    if (group_shares[g] == nullptr) {
      for (const Round& round : rounds_) wanted += absLuminanceOf(round.group_out[g]);
    }
    result_.wanted[g] = wanted > residue ? wanted : 0.0;
  }
  wanted_list_.clear();
  result_.rounds = int(rounds_.size());
  double reflected = 0;
  for (const Round& round : rounds_) reflected += round.abs_out;
  result_.unshot_share = reflected > 0 ? absLuminanceOf(unshot_) / reflected : 0.0;
  result_.received.assign(n, glm::dvec3(0.0));
  for (const Round& round : rounds_) {
    for (size_t r = 0; r < n; ++r) {
      if (terms_[r].takes_part) result_.received[r] += round.in[r];
    }
  }
  if (settings_.ambient && absLuminanceOf(unshot_) > residue) {
    // Thesis 5.5: unshot flux lands somewhere and keeps bouncing; spread it
    // uniformly with the geometric series of the mean albedo.
    double area = 0, albedo_area = 0;
    for (const Receiver& r : receivers) {
      if (!r.shares_ambient) continue;
      area += r.area_m2;
      albedo_area += r.area_m2 * luminanceOf(glm::dvec3(r.albedo.r, r.albedo.g, r.albedo.b));
    }
    if (area > 0) {
      const double mean_albedo = std::min(albedo_area / area, 0.999);
      const glm::dvec3 irradiance = unshot_ / area / (1 - mean_albedo);
      for (size_t r = 0; r < n; ++r) {
        if (receivers[r].shares_ambient)
          result_.received[r] += irradiance * double(receivers[r].area_m2);
      }
    }
  }
}

BounceResult bounceDeltas(const std::vector<Receiver>& receivers,
                          const std::vector<glm::dvec3>& first,
                          const std::vector<int32_t>& group_of,
                          const std::vector<const SparseShares*>& group_shares,
                          const BounceSettings& settings) {
  BounceSolver solver;
  return solver.solve(receivers, first, group_of, group_shares,
                      std::vector<uint64_t>(group_shares.size(), 0), settings);
}

}  // namespace svit::gl

#include "bounce_solver.h"

#include <algorithm>
#include <cmath>

namespace svit::gl {
namespace {

double lum(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
double absLum(const glm::dvec3& c) { return 0.2126 * std::abs(c.x) + 0.7152 * std::abs(c.y) + 0.0722 * std::abs(c.z); }

}  // namespace

double SparseShares::total() const {
  double sum = 0;
  for (float s : shares) sum += s;
  return sum;
}

BounceResult bounceDeltas(const std::vector<Receiver>& receivers, const std::vector<glm::dvec3>& first,
                          const std::vector<int32_t>& group_of,
                          const std::vector<const SparseShares*>& group_shares, const BounceSettings& settings) {
  const size_t n = receivers.size(), groups = group_shares.size();
  BounceResult result;
  result.received.assign(n, glm::dvec3(0.0));
  result.wanted.assign(groups, 0.0);
  // Sparse rounds: only the receivers with flux this round and the groups
  // they feed are visited, so a change in one room costs that room, not the
  // level. `incoming` is zero outside `active`, `next` outside `next_active`.
  std::vector<glm::dvec3> incoming = first, next(n, glm::dvec3(0.0)), group_out(groups, glm::dvec3(0.0));
  std::vector<uint32_t> active, next_active, active_groups;
  std::vector<char> in_next(n, 0), in_groups(groups, 0);
  for (size_t r = 0; r < n; ++r) {
    if (first[r] != glm::dvec3(0.0)) active.push_back(uint32_t(r));
  }
  glm::dvec3 unshot(0.0);
  double reflected_total = 0, first_round = -1;
  for (int round = 0;; ++round) {
    // Receive this round, then reflect.
    double round_abs = 0;
    for (uint32_t r : active) {
      if (!(receivers[r].area_m2 > 0)) continue;
      result.received[r] += incoming[r];
      const Rgb& rho = receivers[r].albedo;
      incoming[r] *= glm::dvec3(rho.r, rho.g, rho.b);  // now the reflected flux
      round_abs += absLum(incoming[r]);
    }
    reflected_total += round_abs;
    if (first_round < 0) first_round = round_abs;
    const bool last = round >= settings.max_bounces || round_abs <= settings.stop_share * first_round ||
                      !(round_abs > 0);
    for (uint32_t r : active) {
      const glm::dvec3& out = incoming[r];
      if (out == glm::dvec3(0.0)) continue;
      if (group_of[r] < 0) {
        unshot += out;
        continue;
      }
      const size_t g = size_t(group_of[r]);
      if (!in_groups[g]) {
        in_groups[g] = 1;
        active_groups.push_back(uint32_t(g));
      }
      group_out[g] += out;
    }
    std::sort(active_groups.begin(), active_groups.end());  // the dense solver's order
    next_active.clear();
    for (uint32_t g : active_groups) {
      const glm::dvec3 out = group_out[g];
      group_out[g] = glm::dvec3(0.0);
      in_groups[g] = 0;
      if (out == glm::dvec3(0.0)) continue;
      const SparseShares* shares = group_shares[g];
      if (last || shares == nullptr) {
        unshot += out;
        if (shares == nullptr) result.wanted[g] += absLum(out);
        continue;
      }
      // What a share misses (escapes, absorbing backs) is simply lost, as
      // in the bake.
      for (size_t i = 0; i < shares->receivers.size(); ++i) {
        const uint32_t r = shares->receivers[i];
        if (!in_next[r]) {
          in_next[r] = 1;
          next_active.push_back(r);
        }
        next[r] += out * double(shares->shares[i]);
      }
    }
    active_groups.clear();
    result.rounds = round + 1;
    if (last) break;
    for (uint32_t r : active) incoming[r] = glm::dvec3(0.0);
    std::swap(incoming, next);
    std::swap(active, next_active);
    for (uint32_t r : active) in_next[r] = 0;
  }
  result.unshot_share = reflected_total > 0 ? absLum(unshot) / reflected_total : 0.0;
  if (settings.ambient && unshot != glm::dvec3(0.0)) {
    // Thesis 5.5: unshot flux lands somewhere and keeps bouncing; spread it
    // uniformly with the geometric series of the mean albedo.
    double area = 0, albedo_area = 0;
    for (const Receiver& r : receivers) {
      area += r.area_m2;
      albedo_area += r.area_m2 * lum(glm::dvec3(r.albedo.r, r.albedo.g, r.albedo.b));
    }
    if (area > 0) {
      const double mean_albedo = std::min(albedo_area / area, 0.999);
      const glm::dvec3 irradiance = unshot / area / (1 - mean_albedo);
      for (size_t r = 0; r < n; ++r) result.received[r] += irradiance * double(receivers[r].area_m2);
    }
  }
  return result;
}

}  // namespace svit::gl

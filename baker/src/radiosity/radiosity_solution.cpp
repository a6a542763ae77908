// Reading the radiosity solution back: per-element means, the error
// estimate and series, and interpolation through vertex radiosities (the
// thesis's two modes: through vertices, and per element with a centre
// vertex), with hard edges kept hard.

#include <algorithm>
#include <cmath>
#include <functional>

#include "lit_backs.h"
#include "radiosity_state.h"
#include "util/double_math.h"

namespace svit::baker {
namespace {

// Barycentrics of 2-D point p in triangle (a, b, c): weights of b and c.
glm::dvec2 barycentric2d(const float (&t)[3][2], double px, double py, int i0, int i1, int i2) {
  const double x0 = t[i0][0], y0 = t[i0][1];
  const double x1 = t[i1][0] - x0, y1 = t[i1][1] - y0, x2 = t[i2][0] - x0, y2 = t[i2][1] - y0;
  const double det = x1 * y2 - x2 * y1;
  const double qx = px - x0, qy = py - y0;
  return {(qx * y2 - x2 * qy) / det, (x1 * qy - qx * y1) / det};
}

}  // namespace

double RadiositySolver::State::halfWeight(SolutionHalf half) const {
  switch (distinctHalf(half)) {
    case SolutionHalf::kOdd: return weight_sum_odd;
    case SolutionHalf::kEven: return weight_sum - weight_sum_odd;
    case SolutionHalf::kWhole: break;
  }
  return weight_sum;
}

const std::vector<glm::dvec3>& RadiositySolver::State::currentLevels(
    std::vector<glm::dvec3>& scratch, SolutionHalf half) const {
  const double weight = halfWeight(half);
  if (weight <= 0) return e_pass;
  scratch.resize(e_sum.size());
  switch (distinctHalf(half)) {
    case SolutionHalf::kOdd:
      for (size_t n = 0; n < e_sum.size(); ++n) scratch[n] = e_sum_odd[n] / weight;
      break;
    case SolutionHalf::kEven:
      for (size_t n = 0; n < e_sum.size(); ++n) scratch[n] = (e_sum[n] - e_sum_odd[n]) / weight;
      break;
    case SolutionHalf::kWhole:
      for (size_t n = 0; n < e_sum.size(); ++n) scratch[n] = e_sum[n] / weight;
      break;
  }
  return scratch;
}

void RadiositySolver::State::forEachLeafLevel(
    const std::vector<glm::dvec3>& levels,
    const std::function<void(const TreeNode&, int, const glm::dvec3&)>& visit) const {
  // Depth-first from the object roots carrying the sum of the levels above.
  std::vector<std::pair<int, glm::dvec3>> stack;
  for (int root : tree->objectRoots()) stack.push_back({root, glm::dvec3(0.0)});
  while (!stack.empty()) {
    const auto [n, above] = stack.back();
    stack.pop_back();
    const TreeNode& node = tree->node(n);
    const glm::dvec3 here = above + levels[size_t(n)];
    if (node.isLeaf()) {
      visit(node, n, here);
    } else {
      stack.push_back({node.child[0], here});
      stack.push_back({node.child[1], here});
    }
  }
}

// The unshot flux's ambient estimate (thesis 5.5) is spread over the leaves
// that received light, and none goes to leaves nothing reached: a space
// sealed from every light (a closed room, the inside of a hollow wall)
// stays black, as it is. The leaves that did receive light share all of
// it, so the ambient flux is the same as spread over every surface.
glm::dvec3 RadiositySolver::State::litLeafAmbient(const std::vector<glm::dvec3>& levels,
                                                  const glm::dvec3& ambient) const {
  if (!(luminanceOf(ambient) > 0)) return glm::dvec3(0.0);
  double all_m2 = 0, lit_m2 = 0;
  forEachLeafLevel(levels, [&](const TreeNode& leaf, int, const glm::dvec3& here) {
    all_m2 += leaf.area_m2;
    if (luminanceOf(here) > 0) lit_m2 += leaf.area_m2;
  });
  return lit_m2 > 0 ? ambient * (all_m2 / lit_m2) : glm::dvec3(0.0);
}

std::vector<glm::dvec3> RadiositySolver::State::elementMeans(const std::vector<glm::dvec3>& levels,
                                                             const glm::dvec3& ambient) const {
  // Each leaf adds area * (levels above it, and its ambient) to its element.
  const glm::dvec3 lit_ambient = litLeafAmbient(levels, ambient);
  std::vector<glm::dvec3> sums(geometry->triangleCount() * 2, glm::dvec3(0.0));
  forEachLeafLevel(levels, [&](const TreeNode& leaf, int, const glm::dvec3& here) {
    const glm::dvec3 with_ambient = luminanceOf(here) > 0 ? here + lit_ambient : here;
    sums[size_t(leaf.triangle) * 2 + leaf.side] += leaf.area_m2 * with_ambient;
  });
  for (size_t e = 0; e < sums.size(); ++e) {
    const int root = tree->elementRoot(uint32_t(e / 2), e % 2 == 0);
    sums[e] = root >= 0 ? sums[e] / tree->node(root).area_m2 : glm::dvec3(0.0);
  }
  return sums;
}

glm::dvec3 RadiositySolver::State::answerAmbient(SolutionHalf half) const {
  const double weight = halfWeight(half);
  if (!(weight > 0)) return currentAmbient();
  switch (distinctHalf(half)) {
    case SolutionHalf::kOdd: return ambient_sum_odd / weight;
    case SolutionHalf::kEven: return (ambient_sum - ambient_sum_odd) / weight;
    case SolutionHalf::kWhole: break;
  }
  return ambient_sum / weight;
}

std::vector<glm::dvec3> RadiositySolver::State::currentMeans() const {
  std::vector<glm::dvec3> scratch;
  return elementMeans(currentLevels(scratch), answerAmbient());
}

double RadiositySolver::State::referenceError(const std::vector<glm::dvec3>& means,
                                              const std::vector<Rgb>& against) const {
  double area = 0, difference = 0, reference_sum = 0;
  for (size_t t = 0; t < geometry->triangleCount() && t < against.size(); ++t) {
    const double a = geometry->areas_m2[t];
    const double x = luminanceOf(means[t * 2]), y = luminanceOf(against[t]);
    area += a;
    difference += a * (x - y) * (x - y);
    reference_sum += a * y;
  }
  return reference_sum > 0 ? std::sqrt(difference / area) / (reference_sum / area) : 0.0;
}

double RadiositySolver::State::estimateError(const std::vector<glm::dvec3>& means) const {
  const glm::dvec3 ambient = answerAmbient();
  double area = 0, mean_sum = 0, variance_sum = 0;
  const uint32_t passes = stats.passes_completed;
  for (size_t e = 0; e < means.size(); ++e) {
    const int root = tree->elementRoot(uint32_t(e / 2), e % 2 == 0);
    if (root < 0) continue;
    const double a = tree->node(root).area_m2;
    area += a;
    mean_sum += a * luminanceOf(means[e]);
    if (passes >= 2) {
      // Passes are independent; pass p has variance sigma^2 / w_p, so
      // sum w_p (x_p - mean)^2 / (P - 1) estimates sigma^2 and the
      // weighted mean has variance sigma^2 / sum w_p.
      const double s1 = element_s1[e], s2 = element_s2[e];
      const double spread = std::max(0.0, s2 - s1 * s1 / weight_sum);
      variance_sum += a * spread / double(passes - 1) / weight_sum;
    }
  }
  if (!(mean_sum > 0)) return emitted_y > 0 ? 1.0 : 0.0;
  const double mean = mean_sum / area;
  double statistical;
  if (passes >= 2) {
    statistical = std::sqrt(variance_sum / area) / mean;
  } else {
    // Before two passes exist: Poisson error of the mean hits per element.
    const double hits_per_element =
        double(stats.hits) / double(std::max<size_t>(1, stats.elements));
    statistical = 1.0 / std::sqrt(1.0 + hits_per_element);
  }
  // The ambient share is an approximation, not a measurement: count all of it.
  const double ambient_share = luminanceOf(ambient) / mean;
  return std::min(1.0, std::sqrt(statistical * statistical + ambient_share * ambient_share));
}

void RadiositySolver::State::recordPoint(double t_s) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<glm::dvec3> means = currentMeans();
  last_estimate = estimateError(means);
  ErrorPoint point;
  point.t_s = t_s;
  point.est_rel_error = last_estimate;
  point.rays = stats.rays;
  if (!reference.empty()) point.ref_rel_error = referenceError(means, reference);
  series.push_back(point);
  last_point_s = t_s;
  last_point_cost_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<Rgb> RadiositySolver::triangleIrradiance(bool front) const {
  const State& s = *state_;
  const std::vector<glm::dvec3> means = s.currentMeans();
  std::vector<Rgb> out(s.geometry->triangleCount());
  for (size_t t = 0; t < out.size(); ++t) out[t] = rgb(means[t * 2 + (front ? 0 : 1)]);
  return out;
}

std::vector<Rgb> RadiositySolver::triangleRadiosity(bool front) const {
  const State& s = *state_;
  std::vector<Rgb> irradiance = triangleIrradiance(front);
  for (size_t t = 0; t < irradiance.size(); ++t) {
    const int root = s.tree->elementRoot(uint32_t(t), front);
    if (root < 0) continue;
    const TreeNode& node = s.tree->node(root);
    const glm::dvec3 albedo = node.reflectance_area / node.area_m2;
    const glm::dvec3 emitted = node.emitted_flux / node.area_m2;  // exitance pi*L
    const Rgb& e = irradiance[t];
    irradiance[t] = rgb(emitted + albedo * glm::dvec3(e.r, e.g, e.b));
  }
  return irradiance;
}

void RadiositySolver::prepareQueries(SolutionHalf half) const {
  const State& s = *state_;
  const ElementTree& tree = *s.tree;
  // Leaf values (per half) and vertex -> leaves incidence, rebuilt when the
  // solution changed.
  std::vector<glm::dvec3>& leaf_value = s.leaf_values[size_t(half)];
  uint64_t& leaf_value_version = s.leaf_values_version[size_t(half)];
  const bool incidence_stale = s.vertex_leaves_version != s.version;
  if (leaf_value_version == s.version && !incidence_stale) return;
  std::vector<glm::dvec3> scratch;
  const std::vector<glm::dvec3>& levels = s.currentLevels(scratch, half);
  const glm::dvec3 lit_ambient = s.litLeafAmbient(levels, s.answerAmbient(half));
  leaf_value.assign(tree.nodes().size(), glm::dvec3(0.0));
  if (incidence_stale) s.vertex_leaves.assign(tree.vertexCount(), {});
  s.forEachLeafLevel(levels, [&](const TreeNode& leaf, int n, const glm::dvec3& here) {
    leaf_value[size_t(n)] = luminanceOf(here) > 0 ? here + lit_ambient : here;
    if (incidence_stale)
      for (uint32_t vertex : leaf.vertex) s.vertex_leaves[vertex].push_back(n);
  });
  if (incidence_stale) {
    for (auto& list : s.vertex_leaves) std::sort(list.begin(), list.end());
    s.vertex_leaves_version = s.version;
  }
  leaf_value_version = s.version;
}

bool RadiositySolver::hasSolutionHalves() const {
  return state_->distinctHalf(SolutionHalf::kOdd) == SolutionHalf::kOdd;
}

Rgb RadiositySolver::irradianceAt(uint32_t triangle, bool front, double u, double v,
                                  InterpolationMode mode, SolutionHalf half) const {
  const State& s = *state_;
  const ElementTree& tree = *s.tree;
  const int root = tree.elementRoot(triangle, front);
  if (root < 0) return {0, 0, 0};
  if (!s.reach.reaches(s.pointOn(triangle, u, v), s.sideNormal(triangle, front)))
    return {0, 0, 0};  // sealed from every light: what the element holds came from elsewhere
  prepareQueries(half);
  const std::vector<glm::dvec3>& leaf_value = s.leaf_values[size_t(half)];
  const int leaf = tree.locateLeaf(root, u, v);
  const TreeNode& node = tree.node(leaf);
  const double cos_hard = std::cos(s.settings.hard_edge_rad);
  // Vertex radiosity: area-weighted mean of the leaves around the vertex on
  // the same side of any hard edge (normals within hard_edge_rad).
  auto vertexValue = [&](uint32_t vertex) {
    glm::dvec3 sum(0.0);
    double area = 0;
    for (int other : s.vertex_leaves[vertex]) {
      const TreeNode& o = tree.node(other);
      if (glm::dot(o.normal, node.normal) < cos_hard) continue;
      sum += o.area_m2 * leaf_value[size_t(other)];
      area += o.area_m2;
    }
    return area > 0 ? sum / area : leaf_value[size_t(leaf)];
  };
  const glm::dvec3 corner[3] = {vertexValue(node.vertex[0]), vertexValue(node.vertex[1]),
                                vertexValue(node.vertex[2])};
  if (mode == InterpolationMode::kVertex) {
    const glm::dvec2 b = barycentric2d(node.bary, u, v, 0, 1, 2);
    return rgb((1.0 - b.x - b.y) * corner[0] + b.x * corner[1] + b.y * corner[2]);
  }
  // Element with a centre vertex: three sub-triangles (centre, k, k+1); the
  // centre carries the element's own value.
  float fan[4][2];
  for (int k = 0; k < 3; ++k) {
    fan[k][0] = node.bary[k][0];
    fan[k][1] = node.bary[k][1];
  }
  fan[3][0] = (node.bary[0][0] + node.bary[1][0] + node.bary[2][0]) / 3.0f;
  fan[3][1] = (node.bary[0][1] + node.bary[1][1] + node.bary[2][1]) / 3.0f;
  double best_score = kNoLowerBound;
  glm::dvec3 best(0.0);
  for (int k = 0; k < 3; ++k) {
    const float sub[3][2] = {
        {fan[3][0], fan[3][1]}, {fan[k][0], fan[k][1]}, {fan[(k + 1) % 3][0], fan[(k + 1) % 3][1]}};
    const glm::dvec2 b = barycentric2d(sub, u, v, 0, 1, 2);
    const double score = std::min({1.0 - b.x - b.y, b.x, b.y});
    if (score > best_score) {
      best_score = score;
      best = (1.0 - b.x - b.y) * leaf_value[size_t(leaf)] + b.x * corner[k] +
             b.y * corner[(k + 1) % 3];
    }
  }
  return rgb(best);
}

void RadiositySolver::setReference(std::vector<Rgb> front_irradiance) {
  state_->reference = std::move(front_irradiance);
}

double RadiositySolver::relativeErrorAgainst(const std::vector<Rgb>& reference) const {
  return state_->referenceError(state_->currentMeans(), reference);
}

double RadiositySolver::estimatedRelativeError() const {
  return state_->estimateError(state_->currentMeans());
}
const std::vector<ErrorPoint>& RadiositySolver::errorSeries() const { return state_->series; }
const ElementTree& RadiositySolver::tree() const { return *state_->tree; }

SolverStats RadiositySolver::stats() const {
  SolverStats out = state_->stats;
  out.nodes = state_->tree->nodes().size();
  out.leaves = state_->tree->leafCount();
  out.captured_fraction =
      state_->surface_rays > 0 ? double(state_->surface_hits) / double(state_->surface_rays) : 1.0;
  const LightReachStats& reach = state_->reach.stats();
  out.leak_guard = reach.enabled;
  out.leak_guard_voxel_m = reach.voxel_m;
  out.leak_guard_reached = reach.reached_fraction;
  out.leak_guard_seconds = reach.seconds;
  out.leak_guard_pockets_opened = reach.sealed_pockets_opened;
  return out;
}

LightReachVerdict RadiositySolver::lightReach(const Vec3& point, const Vec3& normal) const {
  return state_->reach.verdict(dvec(point), dvec(normal));
}

std::vector<uint8_t> RadiositySolver::litBacks(LitBacksStats* stats) const {
  LitBacks backs = findLitBacks(*state_->geometry, *state_->caster, state_->lights, state_->reach,
                                state_->threads);
  if (stats) *stats = backs.stats;
  return std::move(backs.lit);
}

}  // namespace svit::baker

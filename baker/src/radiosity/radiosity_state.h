#pragma once
// The solver's state, shared by radiosity_solver.cpp (shooting) and
// radiosity_solution.cpp (reading the solution back); internal.

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <set>
#include <vector>

#include <glm/glm.hpp>

#include "element_tree.h"
#include "light_reach.h"
#include "light_sources.h"
#include "svit/baker/radiosity.h"
#include "util/double_math.h"

namespace svit::baker {

// One batch's rays and hits (radiosity_batch.cpp).
struct BatchRays;
struct BinnedHits;
struct SubtreeHits;
class ByteReader;
class ByteWriter;

struct RadiositySolver::State {
  const Scene* scene = nullptr;
  const BakeGeometry* geometry = nullptr;
  const RayCaster* caster = nullptr;
  RadiositySettings settings;
  int threads = 1;
  std::unique_ptr<ElementTree> tree;
  std::vector<LightSource> lights;
  /// Where light can arrive (light_reach.h): no light leaves or is read
  /// from surface points it does not reach.
  LightReach reach;
  std::vector<int> emitting_roots;  ///< object roots with emitted flux

  // Per node, grown with the tree. Irradiance (lux) received at the node's
  // own level: it applies uniformly to every leaf below (lazy push-down).
  std::vector<glm::dvec3> e_pass;     ///< this pass
  std::vector<glm::dvec3> e_unshot;   ///< part of e_pass not reflected onwards yet
  std::vector<glm::dvec3> e_sum;      ///< sum over completed passes of weight * e_pass
  std::vector<glm::dvec3> e_sum_odd;  ///< the part of e_sum from odd passes (SolutionHalf)
  std::set<int> pending;              ///< nodes with unshot energy (ordered: deterministic)
  /// Leaves split by the subdivision criterion, in order: replayed on a
  /// fresh tree they rebuild this one node for node (radiosity_snapshot.cpp).
  std::vector<int> subdivided;

  // The current pass.
  bool started = false;
  uint32_t pass = 0;
  uint32_t batch = 0;
  double pass_rays = 0;    ///< nominal rays of this pass for the emitted flux (its weight)
  double ray_flux_y = 0;   ///< luminous flux per ray, lm
  double shot_pass_y = 0;  ///< luminous flux shot so far in this pass
  std::vector<double> light_unshot;     ///< fraction of each light's flux not yet shot
  std::vector<double> emission_unshot;  ///< fraction of each emitting root's flux not yet shot

  // Completed passes.
  double weight_sum = 0;
  glm::dvec3 ambient_sum{0.0};
  double weight_sum_odd = 0;  ///< the parts of weight_sum and ambient_sum from odd passes
  glm::dvec3 ambient_sum_odd{0.0};
  std::vector<double> element_s1, element_s2;  ///< per element (triangle side): sum w*x, sum w*x^2

  // Scene constants.
  double emitted_y = 0;         ///< luminous flux of all sources, lm
  double total_area_m2 = 0;     ///< all element sides
  glm::dvec3 mean_albedo{0.0};  ///< area-weighted over element sides
  uint64_t surface_rays = 0;    ///< rays leaving surfaces (for the captured fraction)
  uint64_t surface_hits = 0;

  SolverStats stats;
  std::vector<ErrorPoint> series;
  double last_estimate = 1.0;
  double last_point_s = -1.0;
  /// an error point costs O(nodes): keep them under ~5% of the time
  double last_point_cost_s = 0.0;
  std::vector<Rgb> reference;
  uint64_t version = 0;  ///< bumped whenever the solution or tree changes

  // Caches for interpolation, each valid for the `version` beside it.
  /// per SolutionHalf, per node (leaves filled): irradiance incl. ambient
  mutable std::array<std::vector<glm::dvec3>, 3> leaf_values;
  mutable std::array<uint64_t, 3> leaf_values_version{~0ull, ~0ull, ~0ull};
  mutable std::vector<std::vector<int>> vertex_leaves;
  mutable uint64_t vertex_leaves_version = ~0ull;

  void growNodeArrays();
  void startPass();
  void endPass();
  /// Shoots one batch of the current pass, or ends the pass (endPass) when
  /// less than pass_end_rays rays' worth of flux is left unshot.
  void runBatch();
  // The stages of runBatch, in order (radiosity_batch.cpp).
  void collectShooters(BatchRays& b) const;
  void allocateRays(BatchRays& b, double unshot) const;
  void takeShotFlux(double fraction, double unshot);
  void castRays(BatchRays& b) const;
  void generateRay(BatchRays& b, size_t j) const;
  void findInsideOrigins(BatchRays& b) const;
  BinnedHits binHits(const BatchRays& b);
  void subdivideDenseLeaves(BinnedHits& binned);
  SubtreeHits sumSubtreeHits(const BinnedHits& binned);
  void depositHits(SubtreeHits& subtrees);
  void returnInsideFlux(const BatchRays& b, const BinnedHits& binned);
  glm::dvec3 currentAmbient() const;
  /// World point at barycentric (u, v) of `triangle`.
  glm::dvec3 pointOn(uint32_t triangle, double u, double v) const {
    const glm::dvec3 c0 = dvec(geometry->corner(triangle, 0));
    return c0 + u * (dvec(geometry->corner(triangle, 1)) - c0) +
           v * (dvec(geometry->corner(triangle, 2)) - c0);
  }
  /// Unit normal of the side of `triangle` asked about.
  glm::dvec3 sideNormal(uint32_t triangle, bool front) const {
    const glm::dvec3 n = dvec(geometry->normals[triangle]);
    return front ? n : -n;
  }
  /// `half`, or the whole while the halves are not distinct solutions.
  SolutionHalf distinctHalf(SolutionHalf half) const {
    return stats.passes_completed >= 2 ? half : SolutionHalf::kWhole;
  }
  /// The weight of the completed passes `half` is made of.
  double halfWeight(SolutionHalf half) const;
  /// Irradiance per node at the node's own level for the current answer
  /// (of `half`).
  const std::vector<glm::dvec3>& currentLevels(std::vector<glm::dvec3>& scratch,
                                               SolutionHalf half = SolutionHalf::kWhole) const;
  /// Calls `visit(leaf, leaf index, sum of the levels from its object root
  /// down to it)` for every leaf.
  void forEachLeafLevel(
      const std::vector<glm::dvec3>& levels,
      const std::function<void(const TreeNode&, int, const glm::dvec3&)>& visit) const;
  /// The ambient irradiance of each leaf that received light for `levels`
  /// (those that received none get none), the same flux as `ambient` on all.
  glm::dvec3 litLeafAmbient(const std::vector<glm::dvec3>& levels, const glm::dvec3& ambient) const;
  /// Mean irradiance per element (triangle side) for `levels` + their ambient.
  std::vector<glm::dvec3> elementMeans(const std::vector<glm::dvec3>& levels,
                                       const glm::dvec3& ambient) const;
  /// Ambient irradiance of the current answer (averaged over passes, those
  /// of `half`, once any completed).
  glm::dvec3 answerAmbient(SolutionHalf half = SolutionHalf::kWhole) const;
  /// elementMeans of the current answer.
  std::vector<glm::dvec3> currentMeans() const;
  double estimateError(const std::vector<glm::dvec3>& means) const;
  /// Area-weighted RMS relative error of front `means` against per-triangle `against`.
  double referenceError(const std::vector<glm::dvec3>& means,
                        const std::vector<Rgb>& against) const;
  void recordPoint(double t_s);
  // What snapshot() writes and restore() reads beyond the tree
  // (radiosity_snapshot.cpp).
  void putShooting(ByteWriter& w) const;
  void getShooting(ByteReader& r);
  /// The arrays read back have the sizes the rebuilt tree and geometry give them.
  bool shootingFits() const;
  /// Splits the leaves `splits` lists, in order, as the shooting did.
  Status replaySubdivisions(const std::vector<int>& splits);
  double unshotY() const;
};

}  // namespace svit::baker

#pragma once
// Hierarchical Monte Carlo radiosity with clusters and adaptive subdivision
// (thesis ch. 4, static part): progressive shooting of equal-flux rays,
// sparse hits propagated up to clusters, dense uneven hits subdividing the
// receiver, resumable and anytime, bit-identical for a seed whatever the
// thread count.

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/baker/ray_caster.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::baker {

/// What the leak guard tells of a surface point (RadiositySolver::lightReach).
enum class LightReachVerdict { kReached, kUnreached, kWalledIn };

struct RadiositySettings {
  uint64_t seed = 1;
  /// Worker threads for ray generation and casting; 0 = all cores. Results
  /// do not depend on it.
  int threads = 0;
  /// SUBDIV of the thesis criterion (4.3.1):
  /// dist(centroid, meanHit) * hits * SUBDIV > perimeter && perimeter > MIN_PERIMETER.
  double subdiv = 1.0;
  /// MIN_PERIMETER in metres; 0 = 2% of the scene's bounding-box diagonal.
  double min_perimeter_m = 0.0;
  /// Sparse hits spread over clusters: a node hands a batch's hits in its
  /// subtree down to its children only when the larger child expects at
  /// least this many of them (by area); otherwise they are deposited at the
  /// node and spread over its leaves by area. Decided from the node's count
  /// alone, so spreading is unbiased for uniform light.
  uint32_t min_hits_per_element = 8;
  /// Rays of the first pass for the emitted flux; each later pass has
  /// `pass_growth` times more. Small, so a coarse answer exists at once.
  uint32_t first_pass_rays = 4096;
  double pass_growth = 2.0;
  /// Rays per batch at most (stop rules are checked between batches).
  uint32_t max_batch_rays = 1u << 16;
  /// A pass ends when the unshot flux is less than this many rays carry;
  /// the rest is compensated as ambient light (thesis 5.5).
  double pass_end_rays = 32.0;
  /// An emitter splits while one half emits more than this many times the other.
  double emitter_split_ratio = 2.0;
  /// Vertex radiosity averages only elements whose normals differ by less (rad).
  double hard_edge_rad = 0.5235987755982988;  // 30 degrees
  /// The leak guard (light_reach.h) voxelizes the level at a 512th of its
  /// diagonal and stays off where that voxel is coarser than this (metres),
  /// as it would close doors and windows; 0 turns it off.
  double leak_guard_max_voxel_m = 0.25;
};

/// Progress reported between batches.
struct SolverProgress {
  double elapsed_s = 0;
  uint32_t passes_completed = 0;
  uint64_t rays = 0;
  double est_rel_error = 1.0;
  double shot_fraction = 0.0;  ///< of the current pass's energy
};

/// When improve() stops; the first rule met wins. Checked between batches.
struct StopRule {
  double max_seconds = std::numeric_limits<double>::infinity();  ///< this call's wall time
  double target_est_rel_error = 0.0;  ///< stop once the estimate is at or below (needs 2 passes)
  double target_shot_fraction = 2.0;  ///< stop once the current pass has shot this share (<= 1)
  /// stop once this many passes completed
  uint32_t max_passes = std::numeric_limits<uint32_t>::max();
  /// Check the error and shot-fraction targets only when a pass has just
  /// ended, so where the solver stops depends on the seed alone, never on
  /// the clock (error points between pass ends are taken by wall time).
  bool targets_at_pass_ends = false;
  uint64_t max_rays = std::numeric_limits<uint64_t>::max();  ///< over the solver's life
  const std::atomic<bool>* cancel = nullptr;                 ///< set from any thread to cancel
  /// Called between batches; returning false cancels.
  std::function<bool(const SolverProgress&)> progress;
};

/// How an ErrorPoint's estimate was made (report.json names it).
enum class ErrorEstimate {
  kSolverPasses,  ///< the solver's: spread of its passes per element, and the ambient share
  /// the lightmap's: pages of the even lighting passes against those of the
  /// odd ones (each gathering from its own half of the solver's passes)
  kSplitHalfPages,
  /// the lightmap's: spread of the texel values over passes, scaled by the
  /// split-half's ratio to it at the nearest pass that measured both
  kScaledTexelSpread,
  kTexelSpread,  ///< the lightmap's: spread of the texel values over passes, unscaled
};

/// One point of the error-versus-time series (what report.json carries).
struct ErrorPoint {
  double t_s = 0;              ///< solver wall time so far
  double est_rel_error = 1.0;  ///< estimate, made as `estimate` says
  /// Split-half points: the page filter's estimated bias, relative, the
  /// part of est_rel_error the halves cannot see (lightmap_error.h); else NaN.
  double est_filter_bias = std::numeric_limits<double>::quiet_NaN();
  double ref_rel_error = std::numeric_limits<double>::quiet_NaN();  ///< with a reference
  uint64_t rays = 0;
  ErrorEstimate estimate = ErrorEstimate::kSolverPasses;
};

struct SolverStats {
  uint64_t rays = 0;
  uint64_t hits = 0;
  uint64_t back_absorbed = 0;  ///< hits on the black back of single-sided surfaces
  /// Reflected rays that started inside a solid (a back face ahead and along
  /// the origin's normal): their flux was shot again from the visible part.
  uint64_t inside_origin_rays = 0;
  uint64_t batches = 0;
  uint32_t passes_completed = 0;
  size_t nodes = 0;
  size_t leaves = 0;
  size_t elements = 0;                   ///< triangle sides
  uint64_t subdivisions = 0;             ///< leaves split (criterion and conformity)
  uint64_t hit_elements = 0;             ///< leaves that received hits, summed over batches
  uint64_t propagation_visits = 0;       ///< nodes touched by upward propagation
  uint64_t propagation_bound = 0;        ///< sum over hit leaves of (depth + 1)
  double cast_seconds = 0;               ///< inside the ray caster
  double seconds = 0;                    ///< solver wall time
  std::string compensation = "ambient";  ///< how unshot energy is estimated (thesis 5.5)
  double captured_fraction = 1;          ///< surface rays that hit the scene (1 = closed)
  /// The leak guard (where light can reach, flooded on a voxel grid): off
  /// when the level is too large for its voxels to keep doors open.
  bool leak_guard = false;
  double leak_guard_voxel_m = 0;
  double leak_guard_reached = 0;  ///< share of the free voxels light reaches
  double leak_guard_seconds = 0;
  size_t leak_guard_pockets_opened = 0;  ///< sealed spaces too small to be rooms
};

/// Which solution a query reads: the whole, or the half made of the
/// solver's even or odd passes. The halves are independent estimates of the
/// same answer, so a final gather that reads each in turn puts the
/// solution's noise into its passes' spread, where the lightmap's error
/// estimate sees it (bake.cpp); with fewer than two completed passes each
/// half is the whole.
enum class SolutionHalf { kWhole, kEven, kOdd };

enum class InterpolationMode {
  kVertex,         ///< linear between vertex radiosities (area-weighted means)
  kElementCentre,  ///< per element, fanned around a centre vertex carrying the element's own value
};

class ElementTree;

/// What RadiositySolver::litBacks found (lit_backs.h).
struct LitBacksStats {
  size_t double_sided = 0;  ///< triangles
  size_t lit = 0;           ///< of them, backs light reaches
  size_t sealed = 0;        ///< dark because the leak guard's flood never reached their back
  size_t rays = 0;
  int rounds = 0;  ///< fixed-point rounds over backs that see other backs
  double seconds = 0;
};

class RadiositySolver {
 public:
  /// Sets up elements, clusters, emitters and light sources for the static
  /// `geometry` of `scene`; `caster` must trace that geometry. All three must
  /// outlive the solver. Errors: bad settings, albedo or emission not finite.
  static Expected<std::unique_ptr<RadiositySolver>> create(const Scene& scene,
                                                           const BakeGeometry& geometry,
                                                           const RayCaster& caster,
                                                           const RadiositySettings& settings);
  ~RadiositySolver();

  /// Everything the solver holds beyond what create() derives from the
  /// scene, as bytes: its settings, the tree's subdivisions, the irradiance
  /// per node, the pass sums, the statistics and the error series. What a
  /// sharded bake hands from its plan to its shards (sharded_bake.h).
  std::vector<uint8_t> snapshot() const;
  /// The solver `snapshot` was taken of, equal to it bit for bit (it answers
  /// the same queries and improve() continues the same way), over the same
  /// `scene`, `geometry` and `caster` (which must outlive it), with
  /// `threads` workers. kInvalidInput when the bytes are short, long, or
  /// were taken over other geometry (the rebuilt tree must match).
  static Expected<std::unique_ptr<RadiositySolver>> restore(const Scene& scene,
                                                            const BakeGeometry& geometry,
                                                            const RayCaster& caster, int threads,
                                                            const std::vector<uint8_t>& snapshot);

  /// Shoots until `stop` says so. Resumable: a later call continues. Returns
  /// kCancelled when cancelled (the solution so far stays usable).
  /// Thread-safe: no; uses `settings.threads` workers inside.
  Status improve(const StopRule& stop);

  /// Mean irradiance (lux, per channel) over each triangle side, in
  /// BakeGeometry order; back sides of single-sided triangles are zero.
  std::vector<Rgb> triangleIrradiance(bool front = true) const;
  /// Mean radiosity (exitance, lm/m2): emission + albedo * irradiance.
  std::vector<Rgb> triangleRadiosity(bool front = true) const;
  /// Irradiance (lux) at barycentric (u, v) of a triangle side, interpolated,
  /// of the solution `half`. Thread-safe after prepareQueries(half) until
  /// the next improve().
  Rgb irradianceAt(uint32_t triangle, bool front, double u, double v, InterpolationMode mode,
                   SolutionHalf half = SolutionHalf::kWhole) const;
  /// Builds the interpolation caches (leaf values, vertex incidence) of
  /// `half` so that irradianceAt may be called from many threads. Not
  /// thread-safe itself.
  void prepareQueries(SolutionHalf half = SolutionHalf::kWhole) const;
  /// Whether the two halves are distinct solutions (two or more completed
  /// passes), so that gathering from them in turn measures the solution's
  /// noise.
  bool hasSolutionHalves() const;
  /// Whether any baked light can arrive at surface point `point` from the
  /// side `normal` faces (kUnreached in a room sealed from every light;
  /// see SolverStats::leak_guard; irradianceAt is 0 there), or kWalledIn
  /// where another surface within a voxel in front of the point hides what
  /// lies beyond (a room's corner, the floor under a wall), which
  /// irradianceAt counts as reached.
  LightReachVerdict lightReach(const Vec3& point, const Vec3& normal) const;
  /// Per triangle: 1 where it is double-sided and some baked light can
  /// reach its back (a sky its rays escape to, a light in sight, a lit side
  /// in view), so the back needs a lightmap of its own; 0 elsewhere. Cast
  /// with the solver's caster and threads; deterministic, independent of
  /// the seed and of the solution.
  std::vector<uint8_t> litBacks(LitBacksStats* stats = nullptr) const;

  /// Per-triangle front irradiance of a reference solution; from then on the
  /// error series also carries the true relative error.
  void setReference(std::vector<Rgb> front_irradiance);
  /// Area-weighted RMS relative error of the front irradiance against `reference`.
  double relativeErrorAgainst(const std::vector<Rgb>& reference) const;

  double estimatedRelativeError() const;
  const std::vector<ErrorPoint>& errorSeries() const;
  SolverStats stats() const;
  const ElementTree& tree() const;

 private:
  RadiositySolver();
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace svit::baker

#pragma once
// The stages of a bake that a whole bake (bake.cpp) and a sharded one
// (sharded_bake.cpp) share: loading, the radiosity, the atlas and its
// texels, the runtime's sections and masks, the lighting settings, and the
// finish (pages, bake file, report, write-then-swap). A sharded bake runs
// the same stages in other processes, so its output is the whole bake's by
// construction.
// Internal.

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake_plan.h"
#include "lightmap/filtered_passes.h"
#include "lightmap/texel_accumulator.h"
#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/radiosity.h"
#include "svit/baker/ray_caster.h"
#include "svit/baker/texel_lighting.h"
#include "svit/scene.h"

namespace svit::baker {

// The bake's clock: elapsed time, the current stage and the seconds each
// stage took, and the progress reports (which also poll `cancel`).
class BakeClock {
 public:
  BakeClock(const std::function<bool(const BakeProgress&)>& progress,
            const std::atomic<bool>* cancel, double budget_s, std::string first_stage = "load")
      : progress_(progress), cancel_(cancel), budget_s_(budget_s), stage_(std::move(first_stage)) {}

  double elapsed() const;
  /// Seconds left of the budget; -1 without one.
  double remaining() const;
  double stageStart() const { return stage_start_; }
  const std::vector<std::pair<std::string, double>>& stageSeconds() const { return stage_seconds_; }

  /// Records the current stage's time and starts `next`.
  void endStage(const std::string& next);
  /// Reports progress in the current stage; false: cancelled.
  bool report(double fraction, double eta) const;

 private:
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  const std::function<bool(const BakeProgress&)>& progress_;
  const std::atomic<bool>* cancel_;
  double budget_s_;
  std::vector<std::pair<std::string, double>> stage_seconds_;
  double stage_start_ = 0;
  std::string stage_;
};

// What every stage of one bake reads.
struct BakeRun {
  const BakeOptions& options;
  BakePlan plan;
  BakeClock clock;
  const std::atomic<bool>* cancel;
  Status cancelled;  ///< what a cancelled bake returns

  bool cancelRequested() const { return cancel && cancel->load(); }
  /// `s`, or the bake's own kCancelled status when `s` is a cancellation.
  Status orCancelled(const Status& s) const {
    return s.code() == StatusCode::kCancelled ? cancelled : s;
  }
};

/// A BakeRun for `options` whose cancellation message names `out_dir`.
BakeRun makeBakeRun(const BakeOptions& options,
                    const std::function<bool(const BakeProgress&)>& progress,
                    const std::atomic<bool>* cancel, const std::string& first_stage = "load");

/// The level as the bake sees it. Not movable: the caster and the solver
/// point into `geometry`.
struct LoadedLevel {
  Scene scene;
  uint64_t level_hash = 0;
  size_t degenerate = 0;  ///< static triangles flattened to zero area, skipped
  /// false: nothing baked emits, every texel is 0 (Scene::warnings says so,
  /// and so does every page's EXR "comments")
  bool emits_light = true;
  BakeGeometry geometry;
  std::unique_ptr<RayCaster> caster;

  LoadedLevel() = default;
  LoadedLevel(const LoadedLevel&) = delete;
  LoadedLevel& operator=(const LoadedLevel&) = delete;
};

/// Loads `level_path` (its sun and sky replaced by `sun_json` / `sky_json`
/// when given: BakeOptions), flattens its static geometry and builds the
/// caster.
Expected<std::unique_ptr<LoadedLevel>> loadBakeLevel(const std::string& level_path,
                                                     const std::string& sun_json = "",
                                                     const std::string& sky_json = "");

/// Radiosity until the plan's error target or time cap (or, with
/// --passes, its error target at a pass end only: deterministic).
Expected<std::unique_ptr<RadiositySolver>> solveRadiosity(BakeRun& run, const LoadedLevel& level);

/// The atlas and the texels it covers.
struct AtlasTexels {
  AtlasSettings settings;
  LightmapAtlas atlas;
  TexelSet texels;
};

/// The chart atlas at the plan's density, with faces for the backs light
/// reaches (solver.litBacks), then its texels ("atlas" and "texels"
/// stages); those no light reaches (solver.lightReach) are buried.
Expected<AtlasTexels> buildAtlasTexels(BakeRun& run, const LoadedLevel& level,
                                       const RadiositySolver& solver);

/// Texel-wise RMS relative error (luminance) of pages `mine` against the
/// `reference` pages at the covered texels: pages against pages, both
/// filtered and stitched as the runtime shows them (raw texel means against
/// a filtered reference would count the filter as error).
double referenceError(const TexelSet& texels, const std::vector<LightmapImage>& mine,
                      const std::vector<LightmapImage>& reference);

/// How the bake's pages are made from its texels (dilation, filter).
PageSettings bakePageSettings(const AtlasTexels& atlas, const BakeOptions& options);
/// The passes in `accumulator` as the pages hold them (the filter of
/// `options` applied crosswise), and their halves' difference filtered
/// alike: build the pages of either with bakePageSettings.
FilteredPasses bakeLighting(const AtlasTexels& atlas, const BakeOptions& options,
                            const TexelAccumulator& accumulator);

/// The texel lighting settings of the plan's pass `pass` (its seed, and
/// the lights whose shadow masks hold their direct light).
TexelLightingSettings passLightingSettings(const BakeRun& run, const LoadedLevel& level,
                                           uint32_t pass);

// What the lighting passes leave: their running mean and the error series
// (the solver's points, then one per pass).
/// How a budget sized the passes (pass_sizing.h).
struct PassSizing {
  bool sized = false;             ///< false: no budget, the plan's rays
  double probe_s = 0;             ///< the probe passes' wall time
  double full_pass_s = 0;         ///< a pass at the plan's rays, from the probes
  double fixed_pass_s = 0;        ///< the part of it that does not shrink with the rays
  double seconds_for_passes = 0;  ///< what the budget leaves them
  uint32_t planned_passes = 0;    ///< that fill those seconds (the clock decides)
  double ray_share = 1;           ///< of the plan's gather and area-light rays, per pass
};

struct LightingPasses {
  TexelAccumulator accumulator;
  std::vector<ErrorPoint> series;
  PassSizing sizing;
  uint32_t gather_rays = 0;  ///< per texel and pass
  double solver_error = 0;   ///< the solver's estimated relative error
  /// bakeLighting of `accumulator`: the texels the pages are built from
  FilteredPasses filtered;
};

/// What the runtime reads besides the lightmaps, and the report's account
/// of it: the runtime's sections and the shadow masks (BakeData's runtime
/// fields; its lightmap fields empty), the sections left out with why, and
/// report.json's "shadow_masks". None of it reads the lighting passes, so
/// it is built before them and a budget's passes get what it leaves.
struct RuntimeParts {
  BakeData data;
  nlohmann::ordered_json left_out = nlohmann::ordered_json::array();
  nlohmann::ordered_json masks;
};

/// The runtime's sections when the level needs them, and the shadow masks
/// of the lights chosen for masking ("runtime" stage: the caller starts it).
Expected<RuntimeParts> buildRuntimeParts(BakeRun& run, const LoadedLevel& level,
                                         const RadiositySolver& solver, const AtlasTexels& atlas);

/// Writes the bake: pages (filtered, stitched, dilated), bake file (the
/// lightmap sections and `runtime`'s), and report.json (with
/// `extra_report` merged in at the top level), into a staging directory
/// swapped in at OUT ("pages", "write" stages). With `reference_pages`,
/// the last pass's true error is measured on the pages written.
Expected<BakeResult> finishBake(BakeRun& run, const LoadedLevel& level,
                                const RadiositySolver& solver, const AtlasTexels& atlas,
                                LightingPasses lighting, RuntimeParts runtime,
                                const std::vector<LightmapImage>& reference_pages,
                                const nlohmann::ordered_json& extra_report);

}  // namespace svit::baker

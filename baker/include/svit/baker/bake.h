#pragma once
// The whole bake, as svit-bake runs it: load, radiosity, atlas, texels,
// lighting passes, pages, bake file, report. Writes into a temporary
// directory beside the output and swaps it in only on success, so a failed
// or cancelled bake leaves the previous output intact.

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "svit/baker/radiosity.h"
#include "svit/status.h"

namespace svit::baker {

/// Most lighting passes a bake runs: the mean's error falls only as
/// 1/sqrt(passes), so later passes buy little.
constexpr uint32_t kMaxBakePasses = 256;

struct BakeOptions {
  std::string level_path;
  std::string out_dir;
  uint64_t seed = 1;
  /// Wall-time budget for the whole bake in seconds; infinity = none (quality decides).
  double time_budget_s = std::numeric_limits<double>::infinity();
  /// Quality in (0, 1]: sets the radiosity error target and lighting passes.
  double quality = 0.5;
  /// Lighting passes, in [1, kMaxBakePasses]; 0: from the quality or the
  /// budget. With a pass count the bake depends on nothing but its inputs
  /// (the radiosity stops on its error target at a pass end, never on the
  /// clock): the same bytes on any machine, and what a sharded bake needs
  /// (sharded_bake.h). Excludes a time budget.
  uint32_t passes = 0;
  double texels_per_m = 0;  ///< 0: chosen from the level's size (about 256k texels)
  int threads = 0;          ///< 0: all cores
  /// a previous bake of the same level and settings, for the true error:
  /// this bake's pages against its pages at the covered texels, after
  /// lighting passes 1, 2, 4, 8, ... and the last (a page build each)
  std::string reference_dir;
  int max_page_size = 2048;
  /// --sun / --sky: the JSON of level.json's "sun" or "sky" object, for a
  /// bare glTF (.gltf/.glb) only; empty: none. The bake then also writes
  /// OUT/level.json (the glTF by absolute path, this sun and sky): the
  /// level it baked, for svit-walk and the runtime.
  std::string sun_json, sky_json;
  /// For a level with dynamic objects: shadow masks of the baked lights and
  /// the sun (shadow_masks.h), whose direct light the runtime then shades
  /// per pixel with the dynamic objects' shadows. false: they stay in the
  /// lightmap (--no-shadow-masks).
  bool shadow_masks = true;
  /// The pages' edge-aware filter of the gathered (indirect) light, which
  /// never crosses a chart or a crease and leaves direct light alone.
  /// false: each texel's indirect light as gathered (--no-filter), to see
  /// what the filter does; the error estimate then measures those pages.
  bool indirect_filter = true;
};

/// Checks option ranges (what the tool reports as bad usage, exit 2).
Status validateBakeOptions(const BakeOptions& options);

/// What the progress callback sees.
struct BakeProgress {
  /// "load", "radiosity", "atlas", "texels", "runtime", "lighting", "pages", "write"
  std::string stage;
  double stage_fraction = 0;  ///< 0..1 within the stage
  double elapsed_s = 0;
  double eta_s = -1;  ///< estimated seconds left for the whole bake, < 0 when unknown
};

struct BakeResult {
  std::string report_json;  ///< also written to OUT/report.json
  double seconds = 0;
  size_t pages = 0;
  size_t covered_texels = 0;
  double est_rel_error = 1;
  double ref_rel_error = std::numeric_limits<double>::quiet_NaN();
  /// report.json's "warnings": what import skipped, a level with no light
  /// source (its lightmaps are black), ...
  std::vector<std::string> warnings;
};

/// Removes the OUT.tmp-<pid> and OUT.old-<pid> directories beside
/// `out_dir` that bakes killed mid-write (SIGKILL, a crash) left behind:
/// only those whose process is gone (kill(pid, 0) fails with ESRCH); a
/// running bake's are kept. Returns the paths removed; kIoError naming the
/// path when one cannot be removed. bakeLevel does not call it (it deletes
/// nothing it did not make); svit-bake does before each bake.
Expected<std::vector<std::string>> removeAbandonedBakeDirectories(const std::string& out_dir);

/// Runs the bake. `progress` is called from the calling thread (returning
/// false cancels); `cancel` may be set from any thread or a signal handler.
/// Returns kCancelled when cancelled, kInvalidInput for bad levels or
/// references or an OUT that is not a previous bake (checked before any
/// work), kIoError for output problems (a full disk, `ulimit -f`: the
/// message names the file and the reason); OUT is untouched unless Ok, and
/// a kill at any moment leaves it the previous bake or the whole new one.
Expected<BakeResult> bakeLevel(const BakeOptions& options,
                               const std::function<bool(const BakeProgress&)>& progress,
                               const std::atomic<bool>* cancel);

}  // namespace svit::baker

// The bake pipeline behind svit-bake (docs/architecture/baker-pipeline.md
// "The bake pipeline"; its command line: docs/architecture.md
// "Command-line contracts").

#include "svit/baker/bake.h"

#include <cmath>
#include <filesystem>

#include "bake_output.h"
#include "bake_stages.h"
#include "lightmap_error.h"
#include "pass_sizing.h"
#include "svit/bake_file.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"
#include "util/double_math.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

// The pages the bake would write from `passes`, against the reference's
// (a page build per call, as long as the bake's "pages" stage).
double pagesReferenceError(const LoadedLevel& level, const AtlasTexels& atlas,
                           const BakeOptions& options, const FilteredPasses& passes,
                           const std::vector<LightmapImage>& reference) {
  const LightmapPages pages = buildLightmapPages(level.geometry, atlas.atlas, atlas.texels,
                                                 passes.mean, bakePageSettings(atlas, options));
  return referenceError(atlas.texels, pages.images, reference);
}

// The pages of the --reference bake, checked to be of the same level; none
// without --reference.
Expected<std::vector<LightmapImage>> readReferencePages(const std::string& reference_dir,
                                                        uint64_t level_hash) {
  std::vector<LightmapImage> reference_pages;
  if (reference_dir.empty()) return reference_pages;
  const std::string reference_file = (fs::path(reference_dir) / "bake.svit").string();
  Expected<BakeData> reference = readBakeFile(reference_file);
  if (!reference.ok())
    return Status(reference.status().code(), "--reference: " + reference.status().message());
  if (reference->level_hash != level_hash) {
    return Status(
        StatusCode::kInvalidInput,
        "--reference: " + reference_file + " is a bake of another level (or of a changed one)");
  }
  for (const BakeLightmapPage& page : reference->pages) {
    Expected<LightmapImage> image = readLightmapExr((fs::path(reference_dir) / page.file).string());
    if (!image.ok())
      return Status(image.status().code(), "--reference: " + image.status().message());
    reference_pages.push_back(std::move(image).value());
  }
  return reference_pages;
}

// --reference pages must have this bake's atlas, texel for texel.
Status checkReferenceAtlas(const std::vector<LightmapImage>& reference_pages,
                           const TexelSet& texels) {
  if (reference_pages.empty()) return Status();
  const bool same = reference_pages.size() == size_t(texels.page_count) &&
                    reference_pages[0].width == texels.page_width &&
                    reference_pages[0].height == texels.page_height;
  if (same) return Status();
  return Status(
      StatusCode::kInvalidInput,
      "--reference: its atlas differs from this bake's (" + std::to_string(reference_pages.size()) +
          " pages of " + std::to_string(reference_pages[0].width) + "x" +
          std::to_string(reference_pages[0].height) + " vs " + std::to_string(texels.page_count) +
          " of " + std::to_string(texels.page_width) + "x" + std::to_string(texels.page_height) +
          "); bake both with the same --texels-per-m");
}

// Lighting passes, averaged: each is an independent estimate, so their
// spread is the lightmap's error estimate (lightmap_error.h). Without a
// budget the quality sets the pass count; with one, passes continue while
// time remains.
Expected<LightingPasses> runLightingPasses(BakeRun& run, const LoadedLevel& level,
                                           const RadiositySolver& solver, const AtlasTexels& atlas,
                                           const std::vector<LightmapImage>& reference_pages) {
  const BakePlan& plan = run.plan;
  LightingPasses out;
  out.solver_error = solver.estimatedRelativeError();
  out.series = solver.errorSeries();
  LightmapErrorEstimator estimator(level, atlas, solver, run.options);
  const double solver_seconds = solver.stats().seconds;
  for (ErrorPoint& p : out.series) p.ref_rel_error = std::numeric_limits<double>::quiet_NaN();
  Expected<PassSizing> sizing =
      sizePassesToBudget(run, level, solver, atlas, finishSeconds(plan, 0.0));
  if (!sizing.ok()) return sizing.status();
  out.sizing = *sizing;
  out.gather_rays = plan.gather_rays;
  const double stage_start = run.clock.stageStart();
  double slowest_pass_s = 0, filter_s = 0;
  for (uint32_t pass = 0; wantLightingPass(plan, pass, run.clock.elapsed(), slowest_pass_s,
                                           finishSeconds(plan, filter_s));
       ++pass) {
    const double pass_start = run.clock.elapsed();
    const TexelLightingSettings lighting_settings = passLightingSettings(run, level, pass);
    // Stage progress: the share of the stage's time used (with a budget),
    // or of the planned passes (without one); never goes backwards.
    const double stage_budget = plan.has_budget ? std::max(1e-3, plan.budget_s - stage_start) : 0.0;
    Expected<std::vector<TexelIrradiance>> lit =
        lightTexels(level.scene, level.geometry, *level.caster, solver, atlas.texels,
                    lighting_settings, run.cancel, [&](size_t done, size_t total) {
                      const double within = double(done) / double(std::max<size_t>(total, 1));
                      const double fraction =
                          plan.has_budget ? (run.clock.elapsed() - stage_start) / stage_budget
                                          : (double(pass) + within) / double(plan.quality_passes);
                      return run.clock.report(std::min(1.0, fraction), run.clock.remaining());
                    });
    if (!lit.ok()) return run.orCancelled(lit.status());
    out.accumulator.add(*lit);
    slowest_pass_s = std::max(slowest_pass_s, run.clock.elapsed() - pass_start);
    ErrorPoint point;
    point.t_s = solver_seconds + (run.clock.elapsed() - stage_start);
    // One filtering of the passes for both measures (and, after the last
    // pass, for the pages).
    const bool measured = measuredPass(pass);
    const double filter_start = run.clock.elapsed();
    out.filtered = measured ? bakeLighting(atlas, run.options, out.accumulator) : FilteredPasses{};
    if (measured) filter_s = run.clock.elapsed() - filter_start;
    estimator.estimate(out.accumulator, out.accumulator.relativeError(),
                       measured ? &out.filtered : nullptr, point);
    point.rays = solver.stats().rays;
    if (!reference_pages.empty() && measured)
      point.ref_rel_error =
          pagesReferenceError(level, atlas, run.options, out.filtered, reference_pages);
    out.series.push_back(point);
  }
  // The last pass unmeasured: its filtering for the pages, and its split-half.
  if (out.accumulator.passes() == 0 ||
      out.series.back().estimate != ErrorEstimate::kSplitHalfPages) {
    out.filtered = bakeLighting(atlas, run.options, out.accumulator);
    if (out.accumulator.passes() > 0)
      estimator.estimate(out.accumulator, out.accumulator.relativeError(), &out.filtered,
                         out.series.back());
  }
  return out;  // finishBake measures the last pass's true error on the pages it writes
}

// --sun/--sky: parsed as a level file's objects; only for a bare glTF,
// whose level has no other place for them (a level .json has its own).
Status validateSunAndSky(const BakeOptions& o) {
  if (o.sun_json.empty() && o.sky_json.empty()) return Status();
  const std::string extension = fs::path(o.level_path).extension().string();
  if (extension != ".gltf" && extension != ".glb" && extension != ".GLTF" && extension != ".GLB") {
    return Status(StatusCode::kInvalidInput, std::string(o.sun_json.empty() ? "--sky" : "--sun") +
                                                 " is for a bare glTF: " + o.level_path +
                                                 " is a level file; give its sun and sky there");
  }
  if (!o.sun_json.empty()) {
    if (Expected<Sun> sun = parseSunJson(o.sun_json, "--sun"); !sun.ok()) return sun.status();
  }
  if (!o.sky_json.empty()) {
    if (Expected<Sky> sky = parseSkyJson(o.sky_json, "--sky"); !sky.ok()) return sky.status();
  }
  return Status();
}

}  // namespace

Status validateBakeOptions(const BakeOptions& o) {
  auto bad = [](const std::string& m) { return Status(StatusCode::kInvalidInput, m); };
  if (o.level_path.empty()) return bad("no level given");
  if (o.out_dir.empty()) return bad("no output directory given (-o OUT)");
  if (!(o.time_budget_s > 0)) return bad("--time must be a positive number of seconds");
  if (!(o.quality > 0 && o.quality <= 1)) return bad("--quality must be in (0, 1]");
  if (!(o.texels_per_m >= 0 && o.texels_per_m <= 4096))
    return bad("--texels-per-m must be in (0, 4096]");
  if (o.threads < 0 || o.threads > 1024) return bad("--threads must be in [0, 1024]");
  if (o.passes > kMaxBakePasses)
    return bad("--passes must be in [1, " + std::to_string(kMaxBakePasses) + "]");
  if (o.passes > 0 && std::isfinite(o.time_budget_s)) {
    return bad(
        "--passes and --time exclude each other: a budget picks the pass count as the bake "
        "runs (report.json's lightmap.lighting_passes says how many it ran)");
  }
  if (o.max_page_size < 16 || o.max_page_size > 16384)
    return bad("page size must be in [16, 16384]");
  return validateSunAndSky(o);
}

Expected<BakeResult> bakeLevel(const BakeOptions& options,
                               const std::function<bool(const BakeProgress&)>& progress,
                               const std::atomic<bool>* cancel) {
  if (Status s = validateBakeOptions(options); !s.ok()) return s;
  BakeRun run = makeBakeRun(options, progress, cancel);

  // Load the level, the --reference bake, and the ray caster. A bad level
  // is reported first: it is the error a user fixes first.
  if (!run.clock.report(0, run.clock.remaining())) return run.cancelled;
  Expected<std::unique_ptr<LoadedLevel>> level =
      loadBakeLevel(options.level_path, options.sun_json, options.sky_json);
  if (!level.ok()) return level.status();
  Expected<std::vector<LightmapImage>> reference_pages =
      readReferencePages(options.reference_dir, (*level)->level_hash);
  if (!reference_pages.ok()) return reference_pages.status();
  run.clock.endStage("radiosity");

  // Then, before the radiosity: OUT must be a previous bake (or nothing)
  // and its directory writable, so a doomed bake fails in seconds.
  if (Status s = checkBakeOutput(bakeOutputPath(options.out_dir)); !s.ok()) return s;
  Expected<std::unique_ptr<RadiositySolver>> solver = solveRadiosity(run, **level);
  if (!solver.ok()) return solver.status();
  run.clock.endStage("atlas");

  Expected<AtlasTexels> atlas = buildAtlasTexels(run, **level, **solver);
  if (!atlas.ok()) return atlas.status();
  if (Status s = checkReferenceAtlas(*reference_pages, atlas->texels); !s.ok()) return s;
  run.clock.endStage("runtime");

  // The runtime's parts before the passes: a budget sizes the passes to
  // what is left after them (pass_sizing.h).
  Expected<RuntimeParts> runtime = buildRuntimeParts(run, **level, **solver, *atlas);
  if (!runtime.ok()) return runtime.status();
  run.clock.endStage("lighting");

  Expected<LightingPasses> lighting =
      runLightingPasses(run, **level, **solver, *atlas, *reference_pages);
  if (!lighting.ok()) return lighting.status();
  return finishBake(run, **level, **solver, *atlas, std::move(*lighting), std::move(*runtime),
                    *reference_pages, nlohmann::ordered_json::object());
}

}  // namespace svit::baker

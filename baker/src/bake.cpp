// The bake pipeline behind svit-bake (docs/architecture.md "Command-line contracts").

#include "svit/baker/bake.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "svit/bake_file.h"
#include "svit/baker/bake_geometry.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/lightmap_pages.h"
#include "svit/baker/ray_caster.h"
#include "svit/baker/runtime_sections.h"
#include "svit/baker/texel_lighting.h"
#include "svit/level.h"
#include "svit/lightmap_image.h"
#include "bake_output.h"
#include "bake_plan.h"
#include "double_math.h"
#include "file_output.h"
#include "random.h"

namespace svit::baker {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

// Running per-texel mean and spread of the lighting passes.
struct TexelAccumulator {
  std::vector<TexelIrradiance> sum;
  std::vector<double> sum_y, sum_y2;
  uint32_t passes = 0;

  void add(const std::vector<TexelIrradiance>& pass) {
    if (sum.empty()) {
      sum.assign(pass.size(), TexelIrradiance{});
      sum_y.assign(pass.size(), 0.0);
      sum_y2.assign(pass.size(), 0.0);
    }
    for (size_t i = 0; i < pass.size(); ++i) {
      sum[i].direct = {sum[i].direct.r + pass[i].direct.r, sum[i].direct.g + pass[i].direct.g,
                       sum[i].direct.b + pass[i].direct.b};
      sum[i].indirect = {sum[i].indirect.r + pass[i].indirect.r,
                         sum[i].indirect.g + pass[i].indirect.g,
                         sum[i].indirect.b + pass[i].indirect.b};
      const double y = luminanceOf(pass[i].direct) + luminanceOf(pass[i].indirect);
      sum_y[i] += y;
      sum_y2[i] += y * y;
    }
    ++passes;
  }
  std::vector<TexelIrradiance> mean() const {
    std::vector<TexelIrradiance> out(sum.size());
    const float k = passes > 0 ? 1.0f / float(passes) : 0.0f;
    for (size_t i = 0; i < sum.size(); ++i) {
      out[i].direct = {sum[i].direct.r * k, sum[i].direct.g * k, sum[i].direct.b * k};
      out[i].indirect = {sum[i].indirect.r * k, sum[i].indirect.g * k, sum[i].indirect.b * k};
    }
    return out;
  }
  // RMS standard error of the texel means over the mean texel value; 1 with
  // fewer than two passes (no spread to measure yet).
  double relativeError() const {
    if (passes < 2 || sum.empty()) return 1.0;
    double variance = 0, mean = 0;
    for (size_t i = 0; i < sum.size(); ++i) {
      const double m = sum_y[i] / passes;
      variance += std::max(0.0, (sum_y2[i] / passes - m * m) * passes / (passes - 1)) / passes;
      mean += m;
    }
    mean /= double(sum.size());
    return mean > 0 ? std::sqrt(variance / double(sum.size())) / mean : 0.0;
  }
};

// Texel-wise RMS relative error (luminance) of covered texels against the reference pages.
double referenceError(const TexelSet& texels, const std::vector<TexelIrradiance>& mean,
                      const std::vector<LightmapImage>& reference) {
  double difference = 0, sum = 0;
  for (size_t i = 0; i < texels.samples.size(); ++i) {
    const TexelSample& s = texels.samples[i];
    const double mine = luminanceOf(mean[i].direct) + luminanceOf(mean[i].indirect);
    const double theirs = luminanceOf(reference[s.page].texel(int(s.x), int(s.y)));
    difference += (mine - theirs) * (mine - theirs);
    sum += theirs;
  }
  const double n = double(std::max<size_t>(1, texels.samples.size()));
  return sum > 0 ? std::sqrt(difference / n) / (sum / n) : 0.0;
}

// The bake file's sections with their sizes and what each holds, for the
// "pay for what is used" audit in report.json.
nlohmann::ordered_json sectionsJson(const BakeData& data) {
  const size_t probes = size_t(data.probes.dims[0]) * data.probes.dims[1] * data.probes.dims[2];
  const std::map<std::string, std::pair<std::string, std::string>> what = {
      {"HEAD", {"header", "level hash, seed"}},
      {"PAGE",
       {"pages", std::to_string(data.pages.size()) + " lightmap pages (names, sizes, hashes)"}},
      {"TUVS",
       {"triangle_uvs",
        std::to_string(data.triangle_uvs.size()) + " static triangles' lightmap coordinates"}},
      {"PTCH",
       {"patches", std::to_string(data.patches.size()) + " patches the runtime's deltas live on"}},
      {"PELM",
       {"patch_elements",
        std::to_string(data.patch_elements.size()) + " elements of those patches"}},
      {"CLST",
       {"clusters", std::to_string(data.clusters.size()) + " cluster-tree nodes over the patches"}},
      {"EMIT",
       {"emitters",
        std::to_string(data.emitters.size()) + " baked emitters with their form factors"}},
      {"PRXY",
       {"proxy", std::to_string(data.proxy.indices.size() / 3) +
                     " LOD-proxy triangles the index maps draw"}},
      {"PROB", {"probes", std::to_string(probes) + " irradiance probes for dynamic objects"}},
  };
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const BakeSectionSize& section : bakeSectionSizes(data)) {
    const auto it = what.find(section.tag);
    out.push_back({{"section", it != what.end() ? it->second.first : section.tag},
                   {"tag", section.tag},
                   {"bytes", section.bytes},
                   {"holds", it != what.end() ? it->second.second : std::string()}});
  }
  return out;
}

nlohmann::ordered_json seriesJson(const std::vector<ErrorPoint>& series, bool with_reference) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const ErrorPoint& p : series) {
    nlohmann::ordered_json point;
    point["t_s"] = p.t_s;
    point["est_rel_error"] = p.est_rel_error;
    if (with_reference)
      point["ref_rel_error"] =
          std::isfinite(p.ref_rel_error) ? nlohmann::ordered_json(p.ref_rel_error) : nullptr;
    out.push_back(point);
  }
  return out;
}

// The bake's clock: elapsed time, the current stage and the seconds each
// stage took, and the progress reports (which also poll `cancel`).
class BakeClock {
 public:
  BakeClock(const std::function<bool(const BakeProgress&)>& progress,
            const std::atomic<bool>* cancel, double budget_s)
      : progress_(progress), cancel_(cancel), budget_s_(budget_s) {}

  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// Seconds left of the budget; -1 without one.
  double remaining() const {
    return std::isfinite(budget_s_) ? std::max(0.0, budget_s_ - elapsed()) : -1.0;
  }
  double stageStart() const { return stage_start_; }
  const std::vector<std::pair<std::string, double>>& stageSeconds() const { return stage_seconds_; }

  /// Records the current stage's time and starts `next`.
  void endStage(const std::string& next) {
    stage_seconds_.push_back({stage_, elapsed() - stage_start_});
    stage_ = next;
    stage_start_ = elapsed();
  }
  /// Reports progress in the current stage; false: cancelled.
  bool report(double fraction, double eta) const {
    if (cancel_ && cancel_->load()) return false;
    if (!progress_) return true;
    return progress_(BakeProgress{stage_, fraction, elapsed(), eta});
  }

 private:
  const Clock::time_point start_ = Clock::now();
  const std::function<bool(const BakeProgress&)>& progress_;
  const std::atomic<bool>* cancel_;
  double budget_s_;
  std::vector<std::pair<std::string, double>> stage_seconds_;
  double stage_start_ = 0;
  std::string stage_ = "load";
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

// Radiosity until the plan's error target or time cap.
Expected<std::unique_ptr<RadiositySolver>> solveRadiosity(BakeRun& run, const Scene& scene,
                                                          const BakeGeometry& geometry,
                                                          const RayCaster& caster) {
  RadiositySettings solver_settings;
  solver_settings.seed = run.options.seed;
  solver_settings.threads = run.options.threads;
  Expected<std::unique_ptr<RadiositySolver>> solver =
      RadiositySolver::create(scene, geometry, caster, solver_settings);
  if (!solver.ok()) return solver.status();
  StopRule stop;
  stop.target_est_rel_error = run.plan.solver_target_est_rel_error;
  stop.max_seconds = run.plan.solver_max_seconds;
  stop.cancel = run.cancel;
  stop.progress = [&](const SolverProgress& p) {
    const double fraction =
        std::min(1.0, std::max(p.elapsed_s / stop.max_seconds,
                               std::log(p.est_rel_error) / std::log(stop.target_est_rel_error)));
    return run.clock.report(std::max(0.0, fraction), run.clock.remaining());
  };
  if (Status s = (*solver)->improve(stop); !s.ok()) return run.orCancelled(s);
  return solver;
}

// The chart atlas at the plan's density.
Expected<LightmapAtlas> buildAtlas(BakeRun& run, const Scene& scene, const BakeGeometry& geometry,
                                   AtlasSettings& atlas_settings) {
  double total_area = 0;
  for (float a : geometry.areas_m2) total_area += a;
  atlas_settings.texels_per_m = atlasTexelsPerM(run.plan, total_area);
  atlas_settings.max_page_size = run.options.max_page_size;
  atlas_settings.threads = run.options.threads;
  if (!run.clock.report(0, run.clock.remaining())) return run.cancelled;
  return buildLightmapAtlas(scene, geometry, atlas_settings);
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

// What the lighting passes leave: their running mean and the error series
// (the solver's points, then one per pass).
struct LightingPasses {
  TexelAccumulator accumulator;
  std::vector<ErrorPoint> series;
  uint32_t gather_rays = 0;  ///< per texel and pass
  double solver_error = 0;   ///< the solver's estimated relative error
};

// Lighting passes, averaged: each is an independent estimate, so their
// spread is the lightmap's error estimate. Without a budget the quality
// sets the pass count; with one, passes continue while time remains.
Expected<LightingPasses> runLightingPasses(BakeRun& run, const Scene& scene,
                                           const BakeGeometry& geometry, const RayCaster& caster,
                                           const RadiositySolver& solver, const TexelSet& texels,
                                           const std::vector<LightmapImage>& reference_pages) {
  const BakePlan& plan = run.plan;
  LightingPasses out;
  out.solver_error = solver.estimatedRelativeError();
  const double solver_error = out.solver_error;
  out.series = solver.errorSeries();
  const double solver_seconds = solver.stats().seconds;
  for (ErrorPoint& p : out.series) p.ref_rel_error = std::numeric_limits<double>::quiet_NaN();
  TexelLightingSettings lighting_settings;
  lighting_settings.threads = run.options.threads;
  lighting_settings.gather_rays = plan.gather_rays;
  lighting_settings.area_light_samples = plan.area_light_samples;
  lighting_settings.sun_samples = plan.sun_samples;
  out.gather_rays = lighting_settings.gather_rays;
  const double stage_start = run.clock.stageStart();
  double pass_seconds = 0;
  for (uint32_t pass = 0; wantLightingPass(plan, pass, run.clock.elapsed(), pass_seconds); ++pass) {
    const double pass_start = run.clock.elapsed();
    lighting_settings.seed = hashIds(run.options.seed, 0x1a7, pass);
    // Stage progress: the share of the stage's time used (with a budget),
    // or of the planned passes (without one); never goes backwards.
    const double stage_budget = plan.has_budget ? std::max(1e-3, plan.budget_s - stage_start) : 0.0;
    Expected<std::vector<TexelIrradiance>> lit =
        lightTexels(scene, geometry, caster, solver, texels, lighting_settings, run.cancel,
                    [&](size_t done, size_t total) {
                      const double within = double(done) / double(std::max<size_t>(total, 1));
                      const double fraction =
                          plan.has_budget ? (run.clock.elapsed() - stage_start) / stage_budget
                                          : (double(pass) + within) / double(plan.quality_passes);
                      return run.clock.report(std::min(1.0, fraction), run.clock.remaining());
                    });
    if (!lit.ok()) return run.orCancelled(lit.status());
    out.accumulator.add(*lit);
    pass_seconds = run.clock.elapsed() - pass_start;
    ErrorPoint point;
    point.t_s = solver_seconds + (run.clock.elapsed() - stage_start);
    const double texel_error = out.accumulator.relativeError();
    point.est_rel_error = std::sqrt(solver_error * solver_error + texel_error * texel_error);
    point.rays = solver.stats().rays;
    if (!reference_pages.empty())
      point.ref_rel_error = referenceError(texels, out.accumulator.mean(), reference_pages);
    out.series.push_back(point);
  }
  return out;
}

// The bake file's lightmap part: the pages' names and hashes, and every
// static triangle's lightmap coordinates.
BakeData lightmapBakeData(const BakeOptions& options, uint64_t level_hash,
                          const BakeGeometry& geometry, const LightmapAtlas& atlas,
                          const LightmapPages& pages) {
  BakeData data;
  data.level_hash = level_hash;
  data.seed = options.seed;
  for (size_t p = 0; p < pages.images.size(); ++p) {
    BakeLightmapPage page;
    page.width = uint32_t(pages.images[p].width);
    page.height = uint32_t(pages.images[p].height);
    page.file = "lightmap-" + std::to_string(p) + ".exr";
    page.texel_hash =
        fnv1a64(pages.images[p].rgb.data(), pages.images[p].rgb.size() * sizeof(float));
    data.pages.push_back(page);
  }
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    BakeTriangleUv uv;
    uv.instance = geometry.instance[t];
    uv.mesh_triangle = geometry.mesh_triangle[t];
    uv.page = atlas.triangle_page[t];
    for (int k = 0; k < 3; ++k) uv.uv[k] = atlas.triangle_uv[t * 3 + size_t(k)];
    data.triangle_uvs.push_back(uv);
  }
  return data;
}

// Adds the runtime's sections to `data` when the level needs them; returns
// the report's list of sections left out.
Expected<nlohmann::ordered_json> addRuntimeSections(BakeRun& run, const Scene& scene,
                                                    const BakeGeometry& geometry,
                                                    const RayCaster& caster,
                                                    const RadiositySolver& solver, BakeData& data) {
  nlohmann::ordered_json left_out = nlohmann::ordered_json::array();
  if (levelNeedsRuntimeSections(scene)) {
    RuntimeSectionSettings runtime_settings;
    runtime_settings.seed = run.options.seed;
    runtime_settings.threads = run.options.threads;
    if (Status s = buildRuntimeSections(scene, geometry, caster, solver, runtime_settings, data,
                                        run.cancel);
        !s.ok()) {
      return run.orCancelled(s);
    }
  } else {
    for (const char* section : {"patches", "clusters", "emitters", "proxy", "probes"}) {
      left_out.push_back({{"section", section},
                          {"reason", "the level has no dynamic objects and no runtime lights"}});
    }
  }
  return left_out;
}

// Lightmap texels written by the pass (valid 1) and by dilation (valid 2).
struct TexelCounts {
  size_t covered = 0, dilated = 0;
};

TexelCounts countTexels(const LightmapPages& pages) {
  TexelCounts counts;
  for (const auto& valid : pages.valid) {
    for (uint8_t v : valid) {
      counts.covered += v == 1;
      counts.dilated += v == 2;
    }
  }
  return counts;
}

// Everything report.json says, but the final stage timings and total.
struct ReportInputs {
  const Scene& scene;
  uint64_t level_hash;
  size_t degenerate;
  const RadiositySolver& solver;
  const AtlasSettings& atlas_settings;
  const LightmapAtlas& atlas;
  const TexelSet& texels;
  const LightmapPages& pages;
  const LightingPasses& lighting;
  const BakeData& data;
  const nlohmann::ordered_json& left_out;
  bool with_reference;
};

nlohmann::ordered_json reportJson(const BakeRun& run, const ReportInputs& in) {
  const BakeOptions& options = run.options;
  const SolverStats stats = in.solver.stats();
  const TexelCounts counts = countTexels(in.pages);
  nlohmann::ordered_json json;
  json["level"] = fs::absolute(options.level_path).lexically_normal().string();
  json["level_hash"] = in.level_hash;
  json["seed"] = options.seed;
  json["quality"] = options.quality;
  json["time_budget_s"] = run.plan.has_budget ? nlohmann::ordered_json(run.plan.budget_s) : nullptr;
  json["texels_per_m"] = in.atlas_settings.texels_per_m;
  json["threads"] = options.threads;
  json["machine"] = "CPU ray casting (Embree 3); no GPU used by the baker";
  nlohmann::ordered_json timings = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : run.clock.stageSeconds()) timings[name] = seconds;
  json["stage_seconds"] = timings;
  json["radiosity"] = {{"rays", stats.rays},
                       {"rays_per_s", stats.seconds > 0 ? double(stats.rays) / stats.seconds : 0.0},
                       {"passes", stats.passes_completed},
                       {"elements", stats.elements},
                       {"leaves", stats.leaves},
                       {"subdivisions", stats.subdivisions},
                       {"est_rel_error", in.lighting.solver_error},
                       {"compensation", stats.compensation},
                       {"captured_fraction", stats.captured_fraction},
                       {"back_absorbed_rays", stats.back_absorbed},
                       {"inside_origin_rays", stats.inside_origin_rays}};
  json["lightmap"] = {
      {"pages", in.pages.images.size()},
      {"page_width", in.texels.page_width},
      {"page_height", in.texels.page_height},
      {"atlas", in.atlas.authored ? "TEXCOORD_1" : "xatlas"},
      {"covered_texels", counts.covered},
      {"dilated_texels", counts.dilated},
      {"lighting_passes", in.lighting.accumulator.passes},
      {"gather_rays_per_texel", in.lighting.accumulator.passes * in.lighting.gather_rays}};
  nlohmann::ordered_json warnings = in.scene.warnings;
  if (in.degenerate > 0) {
    warnings.push_back(
        std::to_string(in.degenerate) +
        " static triangles flattened to zero area by their instance transform; skipped");
  }
  json["warnings"] = warnings;
  json["sections_written"] = sectionsJson(in.data);
  json["sections_left_out"] = in.left_out;
  json["error_vs_time"] = seriesJson(in.lighting.series, in.with_reference);
  return json;
}

// Writes the pages, the bake file and report.json into a fresh directory
// beside OUT, then swaps it in; OUT is left as it was on any failure.
Expected<BakeResult> writeBake(BakeRun& run, const LightmapPages& pages, const BakeData& data,
                               const std::vector<ErrorPoint>& series,
                               nlohmann::ordered_json& json) {
  const fs::path out = bakeOutputPath(run.options.out_dir);
  const fs::path staging = stagingDirectory(out);
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec)
    return Status(StatusCode::kIoError, staging.string() + ": cannot create: " + ec.message());
  auto fail = [&](const Status& s) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    if (s.code() == StatusCode::kCancelled) return s;
    return Status(s.code(), s.message() + "; " + out.string() + " left as it was");
  };
  for (size_t p = 0; p < pages.images.size(); ++p) {
    if (Status s = writeLightmapExr(pages.images[p], (staging / data.pages[p].file).string());
        !s.ok())
      return fail(s);
    if (run.cancelRequested()) return fail(run.cancelled);
  }
  if (Status s = writeBakeFile(data, (staging / "bake.svit").string()); !s.ok()) return fail(s);
  BakeResult result;
  result.pages = pages.images.size();
  result.covered_texels = countTexels(pages).covered;
  result.est_rel_error = series.empty() ? 1.0 : series.back().est_rel_error;
  result.ref_rel_error =
      series.empty() ? std::numeric_limits<double>::quiet_NaN() : series.back().ref_rel_error;
  run.clock.endStage("done");
  json["stage_seconds"]["write"] = run.clock.stageSeconds().back().second;
  result.seconds = run.clock.elapsed();
  json["total_seconds"] = result.seconds;
  result.report_json = json.dump(2) + "\n";
  if (Status s = writeFileReplacing((staging / "report.json").string(), result.report_json.data(),
                                    result.report_json.size());
      !s.ok())
    return fail(s);
  if (run.cancelRequested()) return fail(run.cancelled);
  if (Status s = swapIntoPlace(staging, out); !s.ok()) return fail(s);
  return result;
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
  if (o.max_page_size < 16 || o.max_page_size > 16384)
    return bad("page size must be in [16, 16384]");
  return Status();
}

Expected<BakeResult> bakeLevel(const BakeOptions& options,
                               const std::function<bool(const BakeProgress&)>& progress,
                               const std::atomic<bool>* cancel) {
  if (Status s = validateBakeOptions(options); !s.ok()) return s;
  BakeRun run{
      options, planBake(options), BakeClock(progress, cancel, options.time_budget_s), cancel,
      Status(StatusCode::kCancelled, "bake cancelled; " + options.out_dir + " left as it was")};

  // Load the level, the --reference bake, and the ray caster. A bad level
  // is reported first: it is the error a user fixes first.
  if (!run.clock.report(0, run.clock.remaining())) return run.cancelled;
  Expected<Scene> scene = loadLevel(options.level_path);
  if (!scene.ok()) return scene.status();
  const uint64_t level_hash = hashLevel(*scene);
  Expected<std::vector<LightmapImage>> reference_pages =
      readReferencePages(options.reference_dir, level_hash);
  if (!reference_pages.ok()) return reference_pages.status();
  size_t degenerate = 0;
  Expected<BakeGeometry> geometry = flattenStaticGeometry(*scene, &degenerate);
  if (!geometry.ok()) return geometry.status();
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(*geometry);
  if (!caster.ok()) return caster.status();
  run.clock.endStage("radiosity");

  // Then, before the radiosity: OUT must be a previous bake (or nothing)
  // and its directory writable, so a doomed bake fails in seconds.
  if (Status s = checkBakeOutput(bakeOutputPath(options.out_dir)); !s.ok()) return s;
  Expected<std::unique_ptr<RadiositySolver>> solver =
      solveRadiosity(run, *scene, *geometry, **caster);
  if (!solver.ok()) return solver.status();
  run.clock.endStage("atlas");

  AtlasSettings atlas_settings;
  Expected<LightmapAtlas> atlas = buildAtlas(run, *scene, *geometry, atlas_settings);
  if (!atlas.ok()) return atlas.status();
  run.clock.endStage("texels");
  RasterSettings raster_settings;
  raster_settings.threads = options.threads;
  Expected<TexelSet> texels = rasterizeTexels(*geometry, *atlas, **caster, raster_settings);
  if (!texels.ok()) return texels.status();
  if (Status s = checkReferenceAtlas(*reference_pages, *texels); !s.ok()) return s;
  run.clock.endStage("lighting");

  Expected<LightingPasses> lighting =
      runLightingPasses(run, *scene, *geometry, **caster, **solver, *texels, *reference_pages);
  if (!lighting.ok()) return lighting.status();
  run.clock.endStage("pages");
  PageSettings page_settings;
  page_settings.dilation_texels = atlas_settings.padding_texels;
  page_settings.edge_aware_filter = true;  // gather noise; never crosses charts or creases
  const LightmapPages pages =
      buildLightmapPages(*geometry, *atlas, *texels, lighting->accumulator.mean(), page_settings);
  BakeData data = lightmapBakeData(options, level_hash, *geometry, *atlas, pages);
  run.clock.endStage("runtime");

  Expected<nlohmann::ordered_json> left_out =
      addRuntimeSections(run, *scene, *geometry, **caster, **solver, data);
  if (!left_out.ok()) return left_out.status();
  if (!run.clock.report(1, run.clock.remaining())) return run.cancelled;
  run.clock.endStage("write");

  nlohmann::ordered_json json = reportJson(
      run, ReportInputs{*scene, level_hash, degenerate, **solver, atlas_settings, *atlas, *texels,
                        pages, *lighting, data, *left_out, !reference_pages->empty()});
  return writeBake(run, pages, data, lighting->series, json);
}

}  // namespace svit::baker

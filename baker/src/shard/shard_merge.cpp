// `svit-bake merge WORK -o OUT`: the last step of a sharded bake
// (sharded_bake.h). Checks every shard against the plan, puts their texel
// sums side by side, and finishes as a whole bake does (finishBake).

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include <nlohmann/json.hpp>

#include "loaded_plan.h"
#include "pipeline/bake_output.h"
#include "pipeline/bake_stages.h"
#include "pipeline/lightmap_error.h"
#include "svit/baker/sharded_bake.h"
#include "work_file.h"

namespace svit::baker {
namespace {

// Shard `shard`'s result, checked to be whole, of this plan, and of the
// size the plan gives it.
Expected<ShardLighting> readShard(const std::string& work_dir, const LoadedPlan& loaded,
                                  uint32_t shard, size_t texels) {
  const std::string path = workPath(work_dir, shardFileName(shard, ".bin"));
  const std::string rerun =
      "; run svit-bake shard " + work_dir + " " + std::to_string(shard) + " (again)";
  Expected<WorkFile> file = readWorkFile(path, WorkFileKind::kShard);
  if (!file.ok()) return Status(file.status().code(), file.status().message() + rerun);
  if (file->plan_id != loaded.plan_id) {
    return Status(StatusCode::kInvalidInput, path + ": from another plan (plan id " +
                                                 planIdText(file->plan_id) + ", " +
                                                 workPath(work_dir, kPlanFile) + " is " +
                                                 planIdText(loaded.plan_id) + ")" + rerun);
  }
  Expected<ShardLighting> lighting = decodeShard(file->payload, path);
  if (!lighting.ok()) return Status(lighting.status().code(), lighting.status().message() + rerun);
  if (lighting->shard != shard || lighting->shards != loaded.plan.shards ||
      lighting->passes != loaded.plan.passes || lighting->sums.size() != texels) {
    return Status(StatusCode::kInvalidInput,
                  path + ": holds shard " + std::to_string(lighting->shard) + " of " +
                      std::to_string(lighting->shards) + " with " +
                      std::to_string(lighting->sums.size()) + " texels, not shard " +
                      std::to_string(shard) + " of " + std::to_string(loaded.plan.shards) +
                      " with " + std::to_string(texels) + rerun);
  }
  return lighting;
}

// shard-I.json, what a shard's run reported of itself; null when absent or unreadable
// (it is for the report only; the merge does not depend on it).
nlohmann::ordered_json readShardReport(const std::string& work_dir, uint32_t shard) {
  std::ifstream in(workPath(work_dir, shardFileName(shard, ".json")));
  if (!in) return nullptr;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nlohmann::ordered_json json = nlohmann::ordered_json::parse(text, nullptr, false);
  return json.is_object() ? json : nlohmann::ordered_json(nullptr);
}

double numberOr(const nlohmann::ordered_json& json, const char* key, double fallback) {
  if (!json.is_object() || !json.contains(key) || !json[key].is_number()) return fallback;
  return json[key].get<double>();
}

// All shards' sums in texel order, their spreads summed per pass, and their reports.
struct MergedShards {
  std::vector<TexelIrradiance> sums, odd_sums;
  std::array<std::vector<TexelIrradiance>, 2> quarter_sums;
  std::vector<PassSpread> spreads;
  nlohmann::ordered_json reports = nlohmann::ordered_json::array();
  double lighting_seconds = 0;  ///< summed over shards, from their reports
};

Expected<MergedShards> mergeShards(BakeRun& run, const std::string& work_dir,
                                   const LoadedPlan& loaded) {
  const WorkPlan& plan = loaded.plan;
  MergedShards out;
  out.sums.resize(plan.texel_count);
  out.odd_sums.resize(plan.texel_count);
  for (std::vector<TexelIrradiance>& q : out.quarter_sums) q.resize(plan.texel_count);
  out.spreads.resize(plan.passes);
  for (uint32_t shard = 0; shard < plan.shards; ++shard) {
    const std::vector<uint32_t> texels = plan.shardTexels(shard);
    Expected<ShardLighting> lighting = readShard(work_dir, loaded, shard, texels.size());
    if (!lighting.ok()) return lighting.status();
    for (size_t k = 0; k < texels.size(); ++k) {
      out.sums[texels[k]] = lighting->sums[k];
      out.odd_sums[texels[k]] = lighting->odd_sums[k];
      for (int q = 0; q < 2; ++q) out.quarter_sums[q][texels[k]] = lighting->quarter_sums[q][k];
    }
    for (uint32_t p = 0; p < plan.passes; ++p) {
      out.spreads[p].variance_sum += lighting->spreads[p].variance_sum;
      out.spreads[p].mean_sum += lighting->spreads[p].mean_sum;
      out.spreads[p].texels += lighting->spreads[p].texels;
    }
    nlohmann::ordered_json report = readShardReport(work_dir, shard);
    out.lighting_seconds += numberOr(report, "lighting_seconds", 0.0);
    out.reports.push_back(report);
    if (!run.clock.report(double(shard + 1) / double(plan.shards), -1)) return run.cancelled;
  }
  return out;
}

// The whole bake's LightingPasses from the shards: the same mean; an error
// series whose times are the solver's plus the shards' lighting time summed
// (work, not wall time: shards may have run side by side), whose last
// estimate is the split-half (lightmap_error.h), the earlier ones scaled by it.
LightingPasses lightingFromShards(const LoadedPlan& loaded, MergedShards& merged,
                                  const BakeRun& run) {
  LightingPasses out;
  out.accumulator = TexelAccumulator(std::move(merged.sums), std::move(merged.odd_sums),
                                     std::move(merged.quarter_sums), loaded.plan.passes);
  out.gather_rays = run.plan.gather_rays;
  out.solver_error = loaded.solver->estimatedRelativeError();
  out.series = loaded.solver->errorSeries();
  for (ErrorPoint& p : out.series) p.ref_rel_error = std::numeric_limits<double>::quiet_NaN();
  const double solver_seconds = loaded.solver->stats().seconds;
  LightmapErrorEstimator estimator(*loaded.level, loaded.atlas, *loaded.solver, run.options);
  for (uint32_t p = 0; p < loaded.plan.passes; ++p) {
    ErrorPoint point;
    point.t_s = solver_seconds + merged.lighting_seconds * double(p + 1) / loaded.plan.passes;
    point.est_rel_error = estimator.texelSpread(merged.spreads[p].relativeError(p + 1));
    point.estimate = ErrorEstimate::kTexelSpread;
    point.rays = loaded.solver->stats().rays;
    out.series.push_back(point);
  }
  // The passes before the filter starts were unfiltered in the whole bake:
  // their spreads scale by the unfiltered split-half's ratio, measured here
  // on the same sums (scaleEarlier).
  const double last_spread = merged.spreads.back().relativeError(loaded.plan.passes);
  PageSettings unfiltered = bakePageSettings(loaded.atlas, run.options);
  unfiltered.edge_aware_filter = false;
  const FilteredPasses raw =
      filterPasses(loaded.atlas.atlas, loaded.atlas.texels, out.accumulator, unfiltered);
  ErrorPoint raw_point;
  estimator.estimate(out.accumulator, last_spread, &raw, raw_point);
  out.filtered = bakeLighting(loaded.atlas, run.options, out.accumulator);
  estimator.estimate(out.accumulator, last_spread, &out.filtered, out.series.back());
  const size_t two_passes = out.series.size() - loaded.plan.passes + 1;
  estimator.scaleEarlier(out.series, two_passes);
  return out;
}

nlohmann::ordered_json shardedReport(const LoadedPlan& loaded, const MergedShards& merged) {
  nlohmann::ordered_json json;
  json["plan_id"] = planIdText(loaded.plan_id);
  json["shards"] = loaded.plan.shards;
  json["passes"] = loaded.plan.passes;
  json["plan_radiosity_seconds"] = loaded.solver->stats().seconds;
  json["shard_lighting_seconds_total"] = merged.lighting_seconds;
  json["shard_rays_per_pass"] = loaded.plan.shard_cost;
  json["shard_runs"] = merged.reports;
  return nlohmann::ordered_json{{"sharded", json}};
}

}  // namespace

Expected<BakeResult> mergeShardedBake(const std::string& work_dir, const std::string& out_dir,
                                      int threads,
                                      const std::function<bool(const BakeProgress&)>& progress,
                                      const std::atomic<bool>* cancel) {
  if (out_dir.empty())
    return Status(StatusCode::kInvalidInput, "no output directory given (-o OUT)");
  if (threads < 0 || threads > 1024)
    return Status(StatusCode::kInvalidInput, "--threads must be in [0, 1024]");
  Expected<LoadedPlan> loaded = loadPlan(work_dir, threads);
  if (!loaded.ok()) return loaded.status();
  const BakeOptions options = loaded->plan.bakeOptions(out_dir, threads);
  BakeRun run = makeBakeRun(options, progress, cancel, "merge");
  if (Status s = checkBakeOutput(bakeOutputPath(out_dir)); !s.ok()) return s;
  Expected<MergedShards> merged = mergeShards(run, work_dir, *loaded);
  if (!merged.ok()) return merged.status();
  const nlohmann::ordered_json extra = shardedReport(*loaded, *merged);
  run.clock.endStage("runtime");
  Expected<RuntimeParts> runtime =
      buildRuntimeParts(run, *loaded->level, *loaded->solver, loaded->atlas);
  if (!runtime.ok()) return runtime.status();
  return finishBake(run, *loaded->level, *loaded->solver, loaded->atlas,
                    lightingFromShards(*loaded, *merged, run), std::move(*runtime), {}, extra);
}

}  // namespace svit::baker

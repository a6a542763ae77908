// `svit-bake plan`: the first step of a sharded bake (sharded_bake.h;
// docs/sharded-bakes.md). Solves the radiosity and builds the atlas and its
// texels once, deals the texels to shards by the rays they cast, and writes
// it all to WORK/ in one swap.
//
// Why the merge is the whole bake bit for bit: a texel's light depends on
// its index, the pass seed and the solution alone (lightTexelList), a shard
// sums its texels' passes in pass order as the whole bake does, the
// solution reaches shards and merge through RadiositySolver::snapshot
// unchanged, and the merge finishes with the whole bake's own finishBake.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "loaded_plan.h"
#include "pipeline/bake_output.h"
#include "pipeline/bake_stages.h"
#include "scene/file_output.h"
#include "svit/baker/sharded_bake.h"
#include "work_file.h"
#include "work_plan.h"

namespace svit::baker {
namespace {

namespace fs = std::filesystem;

// Texels are dealt to shards in chunks of this many consecutive texels:
// small enough that dealing balances and interleaves shards in space, large
// enough that each shard's texels stay coherent for the ray caster.
constexpr uint32_t kChunkTexels = 256;
// A texel's fixed cost (sample setup, summing), in rays: a texel that casts
// few rays is not free.
constexpr uint64_t kTexelOverheadRays = 4;

Status badInput(const std::string& message) { return Status(StatusCode::kInvalidInput, message); }

}  // namespace

Status validatePlanOptions(const BakeOptions& options, uint32_t shards) {
  if (Status s = validateBakeOptions(options); !s.ok()) return s;
  if (shards < 1 || shards > kMaxShards) {
    return badInput("--shards must be in [1, " + std::to_string(kMaxShards) + "], not " +
                    std::to_string(shards));
  }
  if (std::isfinite(options.time_budget_s)) {
    return badInput(
        "--time cannot plan a sharded bake: a budget picks the pass count as a bake runs; give "
        "--passes (a timed bake's report.json says how many it ran: lightmap.lighting_passes)");
  }
  if (!options.sun_json.empty() || !options.sky_json.empty()) {
    return badInput(
        "--sun and --sky are for whole bakes; plan a level .json that has them (the OUT/level.json "
        "a bake with --sun/--sky writes is one)");
  }
  if (!options.reference_dir.empty())
    return badInput(
        "--reference is for whole bakes; give it to svit-bake on the merged OUT's level");
  return Status();
}

namespace {

// WORK must be missing, empty, or a previous plan: a plan replaces only what
// a plan made.
Status checkWorkDirectory(const fs::path& work) {
  std::error_code ec;
  const std::string parent = work.parent_path().string();
  if (!fs::exists(work, ec)) return checkWritableDirectory(parent);
  if (!fs::is_directory(work, ec))
    return badInput(work.string() + ": exists and is not a directory; not replaced");
  if (fs::is_empty(work, ec) || fs::exists(work / kPlanFile, ec))
    return checkWritableDirectory(parent);
  return badInput(work.string() +
                  ": neither empty nor a svit-bake plan (no plan.bin); not replaced");
}

// Deals the texels' chunks to shards: each chunk, in texel order, to the
// shard with the least estimated cost so far (ties: the lowest index), so
// shards balance by rays cast and each spans the whole level.
void dealChunks(const std::vector<uint32_t>& texel_rays, WorkPlan& plan) {
  const size_t chunks = (texel_rays.size() + kChunkTexels - 1) / kChunkTexels;
  plan.chunk_texels = kChunkTexels;
  plan.chunk_shard.assign(chunks, 0);
  plan.shard_cost.assign(plan.shards, 0);
  for (size_t c = 0; c < chunks; ++c) {
    uint64_t cost = 0;
    const size_t end = std::min(texel_rays.size(), (c + 1) * kChunkTexels);
    for (size_t j = c * kChunkTexels; j < end; ++j) cost += texel_rays[j] + kTexelOverheadRays;
    const auto cheapest = std::min_element(plan.shard_cost.begin(), plan.shard_cost.end());
    plan.chunk_shard[c] = uint32_t(cheapest - plan.shard_cost.begin());
    *cheapest += cost;
  }
}

WorkPlan makeWorkPlan(const BakeOptions& planned, uint32_t shards, const LoadedLevel& level,
                      const TexelSet& texels) {
  WorkPlan plan;
  plan.level_path = planned.level_path;
  plan.level_hash = level.level_hash;
  plan.seed = planned.seed;
  plan.quality = planned.quality;
  plan.passes = planned.passes;
  plan.texels_per_m = planned.texels_per_m;
  plan.max_page_size = planned.max_page_size;
  plan.shards = shards;
  plan.texel_count = texels.samples.size();
  return plan;
}

// plan.json: the plan for people and job scripts (the steps read plan.bin).
std::string planSummaryJson(const WorkPlan& plan, uint64_t plan_id, double seconds) {
  nlohmann::ordered_json json;
  json["level"] = plan.level_path;
  json["level_hash"] = plan.level_hash;
  json["plan_id"] = planIdText(plan_id);
  json["seed"] = plan.seed;
  json["quality"] = plan.quality;
  json["passes"] = plan.passes;
  json["shards"] = plan.shards;
  json["texels"] = plan.texel_count;
  json["chunk_texels"] = plan.chunk_texels;
  json["shard_rays_per_pass"] = plan.shard_cost;
  json["plan_seconds"] = seconds;
  json["next"] = "svit-bake shard WORK I for I in 0.." + std::to_string(plan.shards - 1) +
                 " (any order, any host), then svit-bake merge WORK -o OUT";
  return json.dump(2) + "\n";
}

using NamedFile = std::pair<std::string, std::vector<uint8_t>>;

// Writes `files` into a staging directory beside WORK and swaps it in, so
// WORK is the previous plan (with its shards) or the whole new one.
Status writePlanFiles(const fs::path& work, const std::vector<NamedFile>& files) {
  const fs::path staging = stagingDirectory(work);
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  if (ec)
    return Status(StatusCode::kIoError, staging.string() + ": cannot create: " + ec.message());
  Status status;
  for (const auto& [name, bytes] : files) {
    if (status.ok())
      status = writeFileReplacing((staging / name).string(), bytes.data(), bytes.size());
  }
  if (status.ok()) status = swapIntoPlace(staging, work);
  if (status.ok()) return status;
  fs::remove_all(staging, ec);
  return Status(status.code(), status.message() + "; " + work.string() + " left as it was");
}

// The plan's work files, each for plan id `plan_id`.
std::vector<NamedFile> planFiles(WorkPlan& plan, const RadiositySolver& solver,
                                 const AtlasTexels& atlas, double seconds) {
  const std::vector<uint8_t> solution = solver.snapshot();
  const std::vector<uint8_t> texels = encodeAtlasTexels(atlas);
  plan.solution_checksum = payloadChecksum(solution);
  plan.texels_checksum = payloadChecksum(texels);
  const std::vector<uint8_t> plan_payload = encodePlan(plan);
  const uint64_t plan_id = payloadChecksum(plan_payload);
  const std::string summary = planSummaryJson(plan, plan_id, seconds);
  return {{kPlanFile, encodeWorkFile(WorkFileKind::kPlan, plan_id, plan_payload)},
          {kSolutionFile, encodeWorkFile(WorkFileKind::kSolution, plan_id, solution)},
          {kTexelsFile, encodeWorkFile(WorkFileKind::kTexels, plan_id, texels)},
          {"plan.json", std::vector<uint8_t>(summary.begin(), summary.end())}};
}

}  // namespace

Expected<ShardPlanResult> planShardedBake(const BakeOptions& options, uint32_t shards,
                                          const std::function<bool(const BakeProgress&)>& progress,
                                          const std::atomic<bool>* cancel) {
  if (Status s = validatePlanOptions(options, shards); !s.ok()) return s;
  BakeOptions planned = options;
  planned.level_path = fs::absolute(options.level_path).lexically_normal().string();
  if (planned.passes == 0) planned.passes = planBake(options).quality_passes;
  BakeRun run = makeBakeRun(planned, progress, cancel);

  // Load and check WORK, then the bake's own first stages.
  if (!run.clock.report(0, -1)) return run.cancelled;
  Expected<std::unique_ptr<LoadedLevel>> level = loadBakeLevel(planned.level_path);
  if (!level.ok()) return level.status();
  const fs::path work = bakeOutputPath(options.out_dir);
  if (Status s = checkWorkDirectory(work); !s.ok()) return s;
  run.clock.endStage("radiosity");
  Expected<std::unique_ptr<RadiositySolver>> solver = solveRadiosity(run, **level);
  if (!solver.ok()) return solver.status();
  run.clock.endStage("atlas");
  Expected<AtlasTexels> atlas = buildAtlasTexels(run, **level, **solver);
  if (!atlas.ok()) return atlas.status();
  run.clock.endStage("plan");

  // Deal the texels by the rays they cast, and write.
  WorkPlan plan = makeWorkPlan(planned, shards, **level, atlas->texels);
  dealChunks(texelRayCounts((*level)->scene, (*level)->geometry, *(*level)->caster, **solver,
                            atlas->texels, passLightingSettings(run, **level, 0)),
             plan);
  if (run.cancelRequested()) return run.cancelled;
  run.clock.endStage("write");
  if (Status s = writePlanFiles(work, planFiles(plan, **solver, *atlas, run.clock.elapsed()));
      !s.ok())
    return s;
  ShardPlanResult result;
  result.shards = shards;
  result.passes = plan.passes;
  result.texels = plan.texel_count;
  result.shard_rays = plan.shard_cost;
  result.seconds = run.clock.elapsed();
  return result;
}

}  // namespace svit::baker

// `svit-bake shard WORK I`: lights one shard of a plan (sharded_bake.h).
// Its result (shard-I.bin) holds only what the plan and the shard index
// decide, so a rerun anywhere writes the same bytes; the time, memory and
// host of this run go beside it, to shard-I.json.

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>

#include <nlohmann/json.hpp>

#include "loaded_plan.h"
#include "pipeline/bake_stages.h"
#include "scene/file_output.h"
#include "svit/baker/sharded_bake.h"
#include "work_file.h"

namespace svit::baker {
namespace {

uint64_t peakRssBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return uint64_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

std::string hostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

// Every pass over the shard's texels, summed in pass order as a whole bake
// sums them, with the spread after each pass.
Expected<ShardLighting> lightShard(BakeRun& run, const LoadedPlan& loaded, uint32_t shard,
                                   const std::vector<uint32_t>& texels) {
  const LoadedLevel& level = *loaded.level;
  ShardLighting out;
  out.shard = shard;
  out.shards = loaded.plan.shards;
  out.passes = loaded.plan.passes;
  TexelAccumulator accumulator;
  for (uint32_t pass = 0; pass < loaded.plan.passes; ++pass) {
    Expected<std::vector<TexelIrradiance>> lit = lightTexelList(
        level.scene, level.geometry, *level.caster, *loaded.solver, loaded.atlas.texels, texels,
        passLightingSettings(run, level, pass), run.cancel, [&](size_t done, size_t total) {
          const double within = double(done) / double(std::max<size_t>(total, 1));
          return run.clock.report((double(pass) + within) / double(loaded.plan.passes), -1);
        });
    if (!lit.ok()) return run.orCancelled(lit.status());
    accumulator.add(*lit);
    out.spreads.push_back(accumulator.spread());
  }
  out.sums = accumulator.sums();
  out.odd_sums = accumulator.oddSums();
  out.quarter_sums = accumulator.quarterSums();
  return out;
}

std::string shardReportJson(const ShardRunResult& result, double lighting_seconds) {
  nlohmann::ordered_json json;
  json["shard"] = result.shard;
  json["shards"] = result.shards;
  json["texels"] = result.texels;
  json["seconds"] = result.seconds;
  json["lighting_seconds"] = lighting_seconds;
  json["peak_rss_bytes"] = result.peak_rss_bytes;
  json["host"] = hostName();
  return json.dump(2) + "\n";
}

}  // namespace

Expected<ShardRunResult> runBakeShard(const std::string& work_dir, uint32_t shard, int threads,
                                      const std::function<bool(const BakeProgress&)>& progress,
                                      const std::atomic<bool>* cancel) {
  const auto start = std::chrono::steady_clock::now();
  if (threads < 0 || threads > 1024)
    return Status(StatusCode::kInvalidInput, "--threads must be in [0, 1024]");
  Expected<LoadedPlan> loaded = loadPlan(work_dir, threads);
  if (!loaded.ok()) return loaded.status();
  if (shard >= loaded->plan.shards) {
    return Status(StatusCode::kInvalidInput, "shard " + std::to_string(shard) + " out of range: " +
                                                 workPath(work_dir, kPlanFile) + " has shards 0.." +
                                                 std::to_string(loaded->plan.shards - 1));
  }
  const BakeOptions options = loaded->plan.bakeOptions(work_dir, threads);
  BakeRun run = makeBakeRun(options, progress, cancel, "lighting");
  run.cancelled = Status(StatusCode::kCancelled,
                         "shard " + std::to_string(shard) + " cancelled; nothing written");
  const std::vector<uint32_t> texels = loaded->plan.shardTexels(shard);
  Expected<ShardLighting> lighting = lightShard(run, *loaded, shard, texels);
  if (!lighting.ok()) return lighting.status();
  const double lighting_seconds = run.clock.elapsed();

  ShardRunResult result;
  result.shard = shard;
  result.shards = loaded->plan.shards;
  result.texels = texels.size();
  result.path = workPath(work_dir, shardFileName(shard, ".bin"));
  if (Status s =
          writeWorkFile(result.path, WorkFileKind::kShard, loaded->plan_id, encodeShard(*lighting));
      !s.ok())
    return s;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.peak_rss_bytes = peakRssBytes();
  const std::string report = shardReportJson(result, lighting_seconds);
  if (Status s = writeFileReplacing(workPath(work_dir, shardFileName(shard, ".json")),
                                    report.data(), report.size());
      !s.ok())
    return s;
  return result;
}

}  // namespace svit::baker

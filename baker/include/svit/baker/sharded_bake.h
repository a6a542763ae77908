#pragma once
// A bake cut into independent jobs that any job runner schedules (GNU
// parallel, a Slurm array, a Kubernetes Indexed Job; docs/sharded-bakes.md):
//   plan  — solves the radiosity once and writes WORK/ (the plan, the
//           solution, the atlas with its texels, and who lights which);
//   shard — lights shard I's texels for every pass, writes WORK/shard-I.bin;
//   merge — checks every shard and writes OUT exactly as bakeLevel would.
// A sharded bake is defined by passes, not wall time (BakeOptions::passes),
// so the merged OUT is bit-identical to `bakeLevel` with the same seed and
// passes, for any shard count, order or host. Every step writes
// atomically: a killed step leaves what was there before.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "svit/baker/bake.h"
#include "svit/status.h"

namespace svit::baker {

/// Most shards a plan cuts a bake into.
constexpr uint32_t kMaxShards = 4096;

struct ShardPlanResult {
  uint32_t shards = 0;
  uint32_t passes = 0;
  size_t texels = 0;
  std::vector<uint64_t> shard_rays;  ///< per shard, the rays its texels cast per pass
  double seconds = 0;
};

/// Checks what planShardedBake refuses before any work: bad bake options,
/// shards outside [1, kMaxShards], a time budget or a --reference (a budget
/// picks passes as a bake runs; a plan cannot). kInvalidInput saying which.
Status validatePlanOptions(const BakeOptions& options, uint32_t shards);

/// Plans `options` (level, seed, quality, passes, texels per metre, page
/// size; `out_dir` is WORK) as `shards` shards. Without options.passes the
/// quality's pass count is fixed in the plan. Errors (nothing written):
/// validatePlanOptions's, a bad level, a WORK that is neither missing,
/// empty nor a previous plan. A previous plan in
/// WORK is replaced whole, with its shards (they belong to it).
Expected<ShardPlanResult> planShardedBake(const BakeOptions& options, uint32_t shards,
                                          const std::function<bool(const BakeProgress&)>& progress,
                                          const std::atomic<bool>* cancel);

struct ShardRunResult {
  uint32_t shard = 0, shards = 0;
  size_t texels = 0;
  double seconds = 0;
  uint64_t peak_rss_bytes = 0;
  std::string path;  ///< WORK/shard-I.bin
};

/// Lights shard `shard` of the plan in `work_dir` with `threads` workers
/// (0: all cores; the result does not depend on it) and writes
/// WORK/shard-I.bin (same bytes on every run) and WORK/shard-I.json (its
/// time, memory and host). Errors name the file: a missing or damaged
/// plan, a shard index out of range, a level changed since the plan.
Expected<ShardRunResult> runBakeShard(const std::string& work_dir, uint32_t shard, int threads,
                                      const std::function<bool(const BakeProgress&)>& progress,
                                      const std::atomic<bool>* cancel);

/// Checks that every shard of the plan in `work_dir` is present, complete,
/// of this plan and undamaged, then assembles and writes `out_dir` like
/// bakeLevel (pages, seams, dilation, runtime sections, report.json with a
/// "sharded" section). Errors name the first shard file that is missing,
/// foreign (another plan), truncated or damaged; OUT is untouched unless Ok.
Expected<BakeResult> mergeShardedBake(const std::string& work_dir, const std::string& out_dir,
                                      int threads,
                                      const std::function<bool(const BakeProgress&)>& progress,
                                      const std::atomic<bool>* cancel);

}  // namespace svit::baker

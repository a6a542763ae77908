#pragma once
// A sharded bake's plan as its shards and its merge read it back from WORK
// (sharded_bake.h): the plan, the level as it is now (checked against the
// plan's hash), the restored radiosity solution and the atlas with its
// texels, each file checked to be whole and of this plan. Internal.

#include <cstdint>
#include <memory>
#include <string>

#include "pipeline/bake_stages.h"
#include "svit/baker/radiosity.h"
#include "work_plan.h"

namespace svit::baker {

inline constexpr const char* kPlanFile = "plan.bin";
inline constexpr const char* kSolutionFile = "solution.bin";
inline constexpr const char* kTexelsFile = "texels.bin";

/// WORK/`name`.
std::string workPath(const std::string& work_dir, const std::string& name);
/// "shard-I" + `extension` (".bin", ".json").
std::string shardFileName(uint32_t shard, const char* extension);

/// A plan id as 16 hex digits, as plan.json and the errors show it.
std::string planIdText(uint64_t plan_id);

/// `level` outlives `solver` (declared first, destroyed last).
struct LoadedPlan {
  WorkPlan plan;
  uint64_t plan_id = 0;
  std::unique_ptr<LoadedLevel> level;
  std::unique_ptr<RadiositySolver> solver;
  AtlasTexels atlas;
};

/// Reads the plan in `work_dir` and what it names, with `threads` workers
/// for the solver. Errors name the file and what is wrong with it: missing,
/// truncated, damaged, of another plan, or a level changed since.
Expected<LoadedPlan> loadPlan(const std::string& work_dir, int threads);

}  // namespace svit::baker

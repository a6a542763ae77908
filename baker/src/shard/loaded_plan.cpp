// Reading a sharded bake's plan back (loaded_plan.h).

#include "loaded_plan.h"

#include <cstdio>
#include <filesystem>

#include "work_file.h"

namespace svit::baker {
namespace {

Status badInput(const std::string& message) { return Status(StatusCode::kInvalidInput, message); }

// The payload of WORK/`name`, of `kind`, which must belong to plan `plan_id`
// and have checksum `checksum`.
Expected<std::vector<uint8_t>> readPlanPart(const std::string& work_dir, const char* name,
                                            WorkFileKind kind, uint64_t plan_id,
                                            uint64_t checksum) {
  const std::string path = workPath(work_dir, name);
  Expected<WorkFile> file = readWorkFile(path, kind);
  if (!file.ok()) return file.status();
  if (file->plan_id != plan_id || payloadChecksum(file->payload) != checksum)
    return badInput(path + ": belongs to another plan than " + workPath(work_dir, kPlanFile));
  return std::move(file->payload);
}

Status readPlanFile(const std::string& work_dir, LoadedPlan& out) {
  const std::string path = workPath(work_dir, kPlanFile);
  Expected<WorkFile> file = readWorkFile(path, WorkFileKind::kPlan);
  if (!file.ok()) return file.status();
  Expected<WorkPlan> plan = decodePlan(file->payload, path);
  if (!plan.ok()) return plan.status();
  out.plan = std::move(plan).value();
  out.plan_id = payloadChecksum(file->payload);
  return Status();
}

Status readLevel(const std::string& work_dir, LoadedPlan& out) {
  Expected<std::unique_ptr<LoadedLevel>> level = loadBakeLevel(out.plan.level_path);
  if (!level.ok()) return level.status();
  out.level = std::move(level).value();
  if (out.level->level_hash == out.plan.level_hash) return Status();
  return badInput(out.plan.level_path + ": changed since " + workPath(work_dir, kPlanFile) +
                  " was made (its level hash differs); plan again");
}

Status readSolution(const std::string& work_dir, int threads, LoadedPlan& out) {
  Expected<std::vector<uint8_t>> solution = readPlanPart(
      work_dir, kSolutionFile, WorkFileKind::kSolution, out.plan_id, out.plan.solution_checksum);
  if (!solution.ok()) return solution.status();
  Expected<std::unique_ptr<RadiositySolver>> solver = RadiositySolver::restore(
      out.level->scene, out.level->geometry, *out.level->caster, threads, *solution);
  if (!solver.ok()) {
    return Status(solver.status().code(),
                  workPath(work_dir, kSolutionFile) + ": " + solver.status().message());
  }
  out.solver = std::move(solver).value();
  return Status();
}

Status readAtlasTexels(const std::string& work_dir, LoadedPlan& out) {
  const std::string path = workPath(work_dir, kTexelsFile);
  Expected<std::vector<uint8_t>> texels = readPlanPart(work_dir, kTexelsFile, WorkFileKind::kTexels,
                                                       out.plan_id, out.plan.texels_checksum);
  if (!texels.ok()) return texels.status();
  Expected<AtlasTexels> atlas = decodeAtlasTexels(*texels, path);
  if (!atlas.ok()) return atlas.status();
  out.atlas = std::move(atlas).value();
  if (out.atlas.texels.samples.size() != out.plan.texel_count ||
      out.atlas.atlas.frontCount() != out.level->geometry.triangleCount())
    return badInput(path + ": does not fit the plan's level");
  return Status();
}

}  // namespace

std::string workPath(const std::string& work_dir, const std::string& name) {
  return (std::filesystem::path(work_dir) / name).string();
}

std::string planIdText(uint64_t plan_id) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(plan_id));
  return text;
}

std::string shardFileName(uint32_t shard, const char* extension) {
  return "shard-" + std::to_string(shard) + extension;
}

Expected<LoadedPlan> loadPlan(const std::string& work_dir, int threads) {
  LoadedPlan out;
  if (Status s = readPlanFile(work_dir, out); !s.ok()) return s;
  if (Status s = readLevel(work_dir, out); !s.ok()) return s;
  if (Status s = readSolution(work_dir, threads, out); !s.ok()) return s;
  if (Status s = readAtlasTexels(work_dir, out); !s.ok()) return s;
  return out;
}

}  // namespace svit::baker

#pragma once
// The sharded bake's work files (sharded_bake.h): plan.bin, solution.bin,
// texels.bin and shard-I.bin in WORK/. Each is a header (magic, format
// version, kind, the plan's id, payload size and FNV-1a 64 checksum) and a
// payload of byte_stream.h values, written with writeFileReplacing (a
// reader sees the old file or the whole new one). Reading checks all of it,
// so a missing, truncated, damaged or foreign file is an error naming it.
// Internal.

#include <cstdint>
#include <string>
#include <vector>

#include "svit/status.h"

namespace svit::baker {

enum class WorkFileKind : uint32_t { kPlan = 1, kSolution = 2, kTexels = 3, kShard = 4 };

/// A work file's payload and the plan id its header carries.
struct WorkFile {
  uint64_t plan_id = 0;
  std::vector<uint8_t> payload;
};

/// FNV-1a 64 of `payload`: what a header carries and what a plan's id is made of.
uint64_t payloadChecksum(const std::vector<uint8_t>& payload);

/// The bytes of a work file of `kind` for plan `plan_id` holding `payload`.
std::vector<uint8_t> encodeWorkFile(WorkFileKind kind, uint64_t plan_id,
                                    const std::vector<uint8_t>& payload);

/// Writes `payload` as a work file of `kind` for plan `plan_id` at `path`.
Status writeWorkFile(const std::string& path, WorkFileKind kind, uint64_t plan_id,
                     const std::vector<uint8_t>& payload);

/// Reads the work file at `path`, which must be of `kind`. Errors name
/// `path` and say what is wrong: missing, not a work file, another format
/// version, another kind, truncated (bytes found of bytes expected),
/// damaged (checksum mismatch). The plan id is the caller's to check.
Expected<WorkFile> readWorkFile(const std::string& path, WorkFileKind kind);

}  // namespace svit::baker

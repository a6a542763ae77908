#pragma once
// What a sharded bake's work files hold (sharded_bake.h, work_file.h): the
// plan (options, level, shard layout), the atlas with its texels, and a
// shard's lit texels; each with its payload codec. Decoding checks sizes
// and ranges, so a payload that passed its checksum but does not fit (a bug,
// or a file from another build) is an error, not a crash. Internal.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lightmap/texel_accumulator.h"
#include "pipeline/bake_stages.h"
#include "svit/baker/bake.h"
#include "svit/baker/lightmap_atlas.h"
#include "svit/baker/texel_lighting.h"
#include "work_file.h"

namespace svit::baker {

/// The plan: what every shard and the merge bake, and who lights which texels.
struct WorkPlan {
  // The bake's options (the rest are defaults; threads are each step's own).
  std::string level_path;  ///< absolute
  uint64_t level_hash = 0;
  uint64_t seed = 1;
  double quality = 0.5;
  uint32_t passes = 1;
  double texels_per_m = 0;
  int32_t max_page_size = 2048;

  uint32_t shards = 1;
  uint64_t texel_count = 0;
  uint32_t chunk_texels = 256;        ///< texels per chunk, the unit shards are dealt
  std::vector<uint32_t> chunk_shard;  ///< per chunk of consecutive texels: its shard
  std::vector<uint64_t> shard_cost;   ///< per shard: the rays its texels cast per pass
  uint64_t solution_checksum = 0;     ///< of solution.bin's payload
  uint64_t texels_checksum = 0;       ///< of texels.bin's payload

  /// The options a step bakes with (`threads` its own, OUT `out_dir`).
  BakeOptions bakeOptions(const std::string& out_dir, int threads) const;
  /// Shard `shard`'s texels (indices into the texel set), in order.
  std::vector<uint32_t> shardTexels(uint32_t shard) const;
};

std::vector<uint8_t> encodePlan(const WorkPlan& plan);
/// kInvalidInput naming `path` when the payload does not fit.
Expected<WorkPlan> decodePlan(const std::vector<uint8_t>& payload, const std::string& path);

std::vector<uint8_t> encodeAtlasTexels(const AtlasTexels& atlas);
Expected<AtlasTexels> decodeAtlasTexels(const std::vector<uint8_t>& payload,
                                        const std::string& path);

/// A shard's result: nothing of the machine or the clock, so a rerun
/// anywhere writes the same bytes (timings go to shard-I.json).
struct ShardLighting {
  uint32_t shard = 0;
  uint32_t shards = 0;
  uint32_t passes = 0;
  std::vector<TexelIrradiance> sums;      ///< per texel of the shard, in its order: sum over passes
  std::vector<TexelIrradiance> odd_sums;  ///< the same over the odd passes (1, 3, ...)
  /// the same over passes 2, 6, ... and over passes 3, 7, ...
  std::array<std::vector<TexelIrradiance>, 2> quarter_sums;
  std::vector<PassSpread> spreads;  ///< after each pass, over the shard's texels
};

std::vector<uint8_t> encodeShard(const ShardLighting& shard);
Expected<ShardLighting> decodeShard(const std::vector<uint8_t>& payload, const std::string& path);

}  // namespace svit::baker

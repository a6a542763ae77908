#pragma once
// A benchmark's bakes: made once per settings and reused while the stamp
// beside them matches (bench_runtime_error, bench_picture).

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "runtime/runtime_test_util.h"
#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/level.h"

namespace svit::test {

// Bakes `level` into `dir` (quality-bound, seed 7 unless told: deterministic;
// a time budget makes it machine-dependent) unless a bake with the same
// stamp is there.
inline BakedLevel bakeOnce(const std::string& level, const std::string& dir, double quality,
                           uint64_t seed = 7, double time_s = 0, bool shadow_masks = true) {
  std::ostringstream stamp;
  stamp << level << " quality " << quality << " seed " << seed << " time " << time_s
        << (shadow_masks ? "" : " no-shadow-masks");
  std::ifstream old(dir + "/stamp");
  const std::string previous((std::istreambuf_iterator<char>(old)),
                             std::istreambuf_iterator<char>());
  if (previous != stamp.str() || !std::filesystem::exists(dir + "/bake.svit")) {
    baker::BakeOptions options;
    options.level_path = level;
    options.out_dir = dir;
    options.quality = quality;
    options.seed = seed;
    if (time_s > 0) options.time_budget_s = time_s;
    options.shadow_masks = shadow_masks;
    const auto t0 = std::chrono::steady_clock::now();
    Expected<baker::BakeResult> result = baker::bakeLevel(options, nullptr, nullptr);
    SVIT_SETUP_CHECK(result.ok(), result.status().message());
    std::printf("baked %s in %.1f s\n", dir.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::ofstream(dir + "/stamp") << stamp.str();
  }
  BakedLevel out;
  out.dir = dir;
  Expected<Scene> scene = loadLevel(level);
  SVIT_SETUP_CHECK(scene.ok(), scene.status().message());
  out.scene = std::move(scene).value();
  Expected<BakeData> bake = readBakeFile(dir + "/bake.svit");
  SVIT_SETUP_CHECK(bake.ok(), bake.status().message());
  out.bake = std::move(bake).value();
  return out;
}

}  // namespace svit::test

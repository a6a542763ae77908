#pragma once
// Bakes for the runtime's GL tests: each level baked once per test binary
// into a temporary directory, at a quality that keeps the tests quick.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <unistd.h>
#include <string>

#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/level.h"
#include "svit/scene.h"

namespace svit::test {

struct BakedLevel {
  Scene scene;
  BakeData bake;
  std::string dir;
};

/// Bakes `level_path` (once per process, keyed by `key`) and loads it back.
inline const BakedLevel& bakedLevel(const std::string& key, const std::string& level_path, double quality = 0.3,
                                    double seconds = 30) {
  static std::map<std::string, BakedLevel> cache;
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const std::string dir = (std::filesystem::temp_directory_path() / ("svit_runtime_test_" + key + "_" +
                                                                      std::to_string(::getpid())))
                              .string();
  baker::BakeOptions options;
  options.level_path = level_path;
  options.out_dir = dir;
  options.quality = quality;
  options.time_budget_s = seconds;
  options.seed = 7;
  Expected<baker::BakeResult> result = baker::bakeLevel(options, nullptr, nullptr);
  EXPECT_TRUE(result.ok()) << result.status().message();
  BakedLevel level;
  level.dir = dir;
  Expected<Scene> scene = loadLevel(level_path);
  EXPECT_TRUE(scene.ok()) << scene.status().message();
  if (scene.ok()) level.scene = std::move(scene).value();
  Expected<BakeData> bake = readBakeFile(dir + "/bake.svit");
  EXPECT_TRUE(bake.ok()) << bake.status().message();
  if (bake.ok()) level.bake = std::move(bake).value();
  return cache.emplace(key, std::move(level)).first->second;
}

inline std::string cornellLevel() { return std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/level.json"; }
inline std::string cornellGltf() {
  return std::string(SVIT_SHARED_SCENES_DIR) + "/cornell_box_original/CornellBox-Original.gltf";
}

}  // namespace svit::test

#pragma once
// Bakes for the runtime's GL tests: each level baked once per test binary
// into a temporary directory, at a quality that keeps the tests quick.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <unistd.h>
#include <string>

#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/level.h"
#include "svit/scene.h"

/// Setup that cannot go on (a bake failed): says why and aborts (usable
/// from tests and benchmarks alike).
#define SVIT_SETUP_CHECK(cond, message)                                         \
  do {                                                                          \
    if (!(cond)) {                                                              \
      std::fprintf(stderr, "%s:%d: %s failed: %s\n", __FILE__, __LINE__, #cond, \
                   std::string(message).c_str());                               \
      std::abort();                                                             \
    }                                                                           \
  } while (0)

namespace svit::test {

struct BakedLevel {
  Scene scene;
  BakeData bake;
  std::string dir;
};

/// Bakes `level_path` (once per process, keyed by `key`) and loads it back.
/// No time budget: a quality-bound bake is deterministic for its seed.
inline const BakedLevel& bakedLevel(const std::string& key, const std::string& level_path,
                                    double quality = 0.3) {
  static std::map<std::string, BakedLevel> cache;
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("svit_runtime_test_" + key + "_" + std::to_string(::getpid())))
                              .string();
  baker::BakeOptions options;
  options.level_path = level_path;
  options.out_dir = dir;
  options.quality = quality;
  options.seed = 7;
  Expected<baker::BakeResult> result = baker::bakeLevel(options, nullptr, nullptr);
  SVIT_SETUP_CHECK(result.ok(), result.status().message());
  BakedLevel level;
  level.dir = dir;
  Expected<Scene> scene = loadLevel(level_path);
  SVIT_SETUP_CHECK(scene.ok(), scene.status().message());
  if (scene.ok()) level.scene = std::move(scene).value();
  Expected<BakeData> bake = readBakeFile(dir + "/bake.svit");
  SVIT_SETUP_CHECK(bake.ok(), bake.status().message());
  if (bake.ok()) level.bake = std::move(bake).value();
  return cache.emplace(key, std::move(level)).first->second;
}

inline std::string cornellLevel() {
  return std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/level.json";
}
inline std::string cornellGltf() { return SVIT_CORNELL_GLTF; }

}  // namespace svit::test

#pragma once
// The generated 2 x 2 house (samples/levels/house) and a runtime over it with
// small importance-caching settings, for the runtime importance and culling
// tests: its bake, node lookup, settling until nothing is out of date, and
// moving a placed object.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "runtime_test_util.h"
#include "svit/runtime.h"

namespace svit::test {

inline const test::BakedLevel& house() {
  return bakedLevel("house", std::string(SVIT_SOURCE_DIR) + "/samples/levels/house/level.json",
                    0.2);
}

inline int nodeIndex(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].name == name) return int(i);
  }
  ADD_FAILURE() << "no node " << name;
  return -1;
}

inline RuntimeSettings cachingSettings() {
  RuntimeSettings settings;
  settings.target_patches = 512;
  settings.target_shooters = 64;
  settings.map_resolution = 64;
  settings.max_samples_per_emitter = 4;
  settings.max_samples_per_frame = 16;
  settings.max_refresh_interval = 8;
  settings.view_pass_width = 96;
  return settings;
}

inline std::unique_ptr<Runtime> makeRuntime(const test::BakedLevel& level,
                                            const RuntimeSettings& settings) {
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  EXPECT_TRUE(runtime.ok()) << runtime.status().message();
  return runtime.ok() ? std::move(runtime).value() : nullptr;
}

/// Updates without a sample budget until nothing is out of date (bounded),
/// then sets `budget` (samples per frame).
inline void settle(Runtime& runtime, int budget = cachingSettings().max_samples_per_frame) {
  ASSERT_TRUE(runtime.setSampleBudget(0).ok());
  bool settled = false;
  for (int frame = 0; frame < 16 && !settled; ++frame) {
    const FrameStats stats = runtime.update(0);
    ASSERT_TRUE(stats.error.empty()) << stats.error;
    settled = stats.idle || stats.emitters_pending == 0;
  }
  ASSERT_TRUE(runtime.setSampleBudget(budget).ok());
  ASSERT_TRUE(settled) << "the runtime did not settle in 16 updates";
}

inline Mat4 translated(const Mat4& placed, float dx, float dz) {
  Mat4 out = placed;
  out.m[12] += dx;
  out.m[14] += dz;
  return out;
}

}  // namespace svit::test

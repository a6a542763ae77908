#pragma once
// Helpers of the picture tests: a level written for a test, the baked view
// of a bake (a reference picture) and a runtime with a renderer over it,
// all at one fixed exposure and size.

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <string>

#include "picture_metric.h"
#include "runtime/render/scene_renderer_test_util.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit::render_test {

// Writes `body` as the level `name`.json in the tests' temporary directory.
inline std::string writeLevel(const std::string& name, const std::string& body) {
  const fs::path path = fs::temp_directory_path() / "svit_scene_renderer_test" / (name + ".json");
  fs::create_directories(path.parent_path());
  std::ofstream(path) << body;
  return path.string();
}

inline SceneRendererSettings fixedExposure() {
  SceneRendererSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.auto_exposure = false;
  settings.exposure = 1;
  return settings;
}

// The baked view of `level` (no runtime): a reference picture.
inline test::LinearFrame bakedPicture(const BakedLevel& level, const Camera& camera) {
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, nullptr, fixedExposure());
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return {};
  EXPECT_TRUE((*renderer)->render(camera, ShadingView::kBakedOnly).ok());
  return test::readLinearFrame(**renderer);
}

// A runtime of `level` (the per-pixel delta lookup, as svit-walk shades)
// with `samples_per_frame` (0: none) and a renderer over it.
struct Viewer {
  std::unique_ptr<Runtime> runtime;
  std::unique_ptr<SceneRenderer> renderer;
};

inline Viewer makeViewer(const BakedLevel& level, int samples_per_frame) {
  RuntimeSettings settings;
  settings.max_samples_per_frame = samples_per_frame;
  settings.delta_textures = false;
  Viewer v;
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(level.scene, level.bake, level.dir, settings);
  EXPECT_TRUE(runtime.ok()) << runtime.status().message();
  if (!runtime.ok()) return v;
  v.runtime = std::move(runtime).value();
  auto renderer =
      SceneRenderer::create(level.scene, level.bake, level.dir, v.runtime.get(), fixedExposure());
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (renderer.ok()) v.renderer = std::move(renderer).value();
  return v;
}

}  // namespace svit::render_test

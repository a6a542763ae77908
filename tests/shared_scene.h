// Where the tests find their scenes. The Cornell box most of them use is in
// the repository (samples/levels/cornell, compiled in as SVIT_CORNELL_GLTF).
// The large scenes (Sponza, the virtual city, the vinc3r Cornell box) are
// optional: they are read from ../shared/scenes beside the checkout
// (SVIT_SHARED_SCENES_DIR), and a test that needs one skips, naming the
// missing file, when a clone has no ../shared.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace svit::test {

/// `relative_path` (e.g. "sponza/Sponza.gltf") under SVIT_SHARED_SCENES_DIR.
inline std::string sharedScenePath(const std::string& relative_path) {
  return std::string(SVIT_SHARED_SCENES_DIR) + "/" + relative_path;
}

}  // namespace svit::test

/// Skips the calling TEST (GTEST_SKIP returns from it) when the shared scene
/// file `relative_path` is not there, saying which file and why it may be missing.
#define SVIT_SKIP_WITHOUT_SHARED_SCENE(relative_path)                                         \
  do {                                                                                        \
    const std::string svit_shared_scene_file_ = ::svit::test::sharedScenePath(relative_path); \
    if (!std::filesystem::exists(svit_shared_scene_file_))                                    \
      GTEST_SKIP() << "needs " << svit_shared_scene_file_                                     \
                   << ", which is missing: the large scenes are optional and live in "        \
                      "../shared/scenes beside "                                              \
                      "the checkout (CMake cache SVIT_SHARED_SCENES_DIR)";                    \
  } while (false)

// libFuzzer target: level import through loadLevel(), the entry point every
// tool and the runtime use. Built three times (tests/fuzz/CMakeLists.txt)
// with SVIT_FUZZ_EXTENSION naming the format the bytes are fed as:
//   ".gltf"  glTF 2.0 JSON            (fuzz_gltf)
//   ".glb"   binary glTF              (fuzz_glb)
//   ".json"  level.json               (fuzz_level_json; the glTF files of
//            tests/data sit beside it, so "gltf": "good_quad.gltf" resolves)
// loadLevel() only takes a path (external buffers and images resolve next
// to it), so each input is written to a scratch file first.
//
// The contract: any bytes give either a Scene that keeps the promises of
// svit/scene.h (checked by sceneContractViolation()) or a failed Status
// whose message names the file. A crash, a sanitizer report, a broken
// promise, a hang (-timeout) or a huge allocation (-malloc_limit_mb) is a
// finding.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scene_contract.h"
#include "svit/bake_file.h"
#include "svit/level.h"
#include "svit/scene_summary.h"

#ifndef SVIT_FUZZ_EXTENSION
#error "SVIT_FUZZ_EXTENSION must be \".gltf\", \".glb\" or \".json\""
#endif

namespace {

const svit::fuzz::ScratchDir& scratch() {
  static const svit::fuzz::ScratchDir dir;
  // A level.json names its glTF relative to itself: offer the real ones.
  static const bool copied =
      std::string(SVIT_FUZZ_EXTENSION) == ".json" && (dir.copyTestData(".gltf"), true);
  (void)copied;
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = scratch().write(std::string("input") + SVIT_FUZZ_EXTENSION, data, size);
  const svit::Expected<svit::Scene> scene = svit::loadLevel(path);
  if (!scene.ok()) {
    if (scene.status().message().find(path) == std::string::npos) {
      svit::fuzz::fail("error message does not name the file: " + scene.status().message());
    }
    return 0;
  }
  if (const std::string broken = svit::fuzz::sceneContractViolation(*scene); !broken.empty()) {
    svit::fuzz::fail("loaded scene breaks its contract: " + broken);
  }
  // What every consumer does next: summarise (svit-info) and hash (the bake
  // key). Both must take any scene the loader accepts.
  const svit::SceneSummary summary = svit::summarize(*scene);
  (void)svit::summaryToJson(path, summary);
  (void)svit::hashLevel(*scene);
  return 0;
}

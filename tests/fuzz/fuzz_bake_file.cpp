// libFuzzer target: bake.svit parsing (bakeio::decodeBakeFile, the parser of
// readBakeFile) and what a runtime does with an accepted bake before it
// touches GL: BakedSurfaces::build() against a level, and a write/read round
// trip.
//
// Bake files end in an FNV-1a 64 checksum of everything before it. A mutated
// input would almost never get past it, so the target rewrites the last 8
// bytes with the right checksum (inputs of at least 24 bytes, the smallest
// bake), which lets mutations reach every section parser and the validator.
// Corruption that the checksum catches is covered by tests/scene/bake_file_test.cpp.
//
// The contract: any bytes give BakeData that passes validateBakeData (and
// survives writeBakeFile/readBakeFile unchanged in its counts), or a failed
// Status naming the file; nothing allocates more than the input size allows.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "scene/bake_file_decode.h"
#include "scene/bake_file_validate.h"
#include "svit/bake_file.h"
#include "svit/baked_surfaces.h"
#include "svit/level.h"

namespace {

constexpr size_t kChecksumBytes = 8;
// "SVITBAKE", version, section count, checksum
constexpr size_t kSmallestBake = 16 + kChecksumBytes;
const std::string kName = "fuzz.svit";

// good_level.json: the quad the corpus bakes were made from, with the
// dynamic lamp that makes the baker write runtime sections.
const svit::Scene& level() {
  static const svit::Scene scene = [] {
    svit::Expected<svit::Scene> loaded =
        svit::loadLevel(std::string(SVIT_TEST_DATA_DIR) + "/good_level.json");
    if (!loaded.ok()) svit::fuzz::fail("cannot load good_level.json: " + loaded.status().message());
    return std::move(loaded).value();
  }();
  return scene;
}

const svit::fuzz::ScratchDir& scratch() {
  static const svit::fuzz::ScratchDir dir;
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  if (bytes.size() >= kSmallestBake) {
    const uint64_t sum = svit::fnv1a64(bytes.data(), bytes.size() - kChecksumBytes);
    for (size_t i = 0; i < kChecksumBytes; ++i)
      bytes[bytes.size() - kChecksumBytes + i] = uint8_t(sum >> (8 * i));
  }
  const svit::Expected<svit::BakeData> bake =
      svit::bakeio::decodeBakeFile(bytes.data(), bytes.size(), kName);
  if (!bake.ok()) {
    if (bake.status().code() != svit::StatusCode::kInvalidInput) {
      svit::fuzz::fail("bad bytes gave a status other than invalid input: " +
                       bake.status().message());
    }
    if (bake.status().message().rfind(kName + ": ", 0) != 0) {
      svit::fuzz::fail("error message does not start with the file name: " +
                       bake.status().message());
    }
    return 0;
  }
  if (svit::Status s = svit::bakeio::validateBakeData(*bake, kName); !s.ok()) {
    svit::fuzz::fail("accepted bake fails validation: " + s.message());
  }
  // The runtime rebuilds the baked triangles from the level; a bake of some
  // other level must fail there with a message, not index out of bounds.
  (void)svit::BakedSurfaces::build(level(), *bake);

  // What was accepted is what the writer accepts, and reads back the same.
  const std::string path = scratch().path("round_trip.svit");
  if (svit::Status s = svit::writeBakeFile(*bake, path); !s.ok()) {
    svit::fuzz::fail("accepted bake cannot be written: " + s.message());
  }
  const svit::Expected<svit::BakeData> again = svit::readBakeFile(path);
  if (!again.ok()) svit::fuzz::fail("written bake cannot be read: " + again.status().message());
  if (again->pages.size() != bake->pages.size() ||
      again->triangle_uvs.size() != bake->triangle_uvs.size() ||
      again->has_runtime_sections != bake->has_runtime_sections ||
      again->patches.size() != bake->patches.size() ||
      again->emitters.size() != bake->emitters.size() || again->level_hash != bake->level_hash) {
    svit::fuzz::fail("bake changed in a write/read round trip");
  }
  return 0;
}

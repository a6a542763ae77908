// libFuzzer target: lightmap pages (readLightmapExr), the other half of
// loading a bake: bake.svit names lightmap-<page>.exr files beside it, and
// svit-probe and the runtime read them with this function. It only takes a
// path, so each input is written to a scratch file first.
//
// The contract: any bytes give an image of positive size with 3 finite
// floats per texel, or a failed Status naming the file.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "svit/lightmap_image.h"

namespace {

const svit::fuzz::ScratchDir& scratch() {
  static const svit::fuzz::ScratchDir dir;
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = scratch().write("lightmap-0.exr", data, size);
  const svit::Expected<svit::LightmapImage> image = svit::readLightmapExr(path);
  if (!image.ok()) {
    if (image.status().message().find(path) == std::string::npos) {
      svit::fuzz::fail("error message does not name the file: " + image.status().message());
    }
    return 0;
  }
  if (image->width <= 0 || image->height <= 0 ||
      image->rgb.size() != size_t(image->width) * size_t(image->height) * 3) {
    svit::fuzz::fail("accepted image has an inconsistent size");
  }
  for (float v : image->rgb) {
    if (!std::isfinite(v)) svit::fuzz::fail("accepted image has a texel that is not finite");
  }
  // What svit-probe does with a page: bilinear lookups anywhere in [0, 1].
  (void)image->sampleBilinear({0.5f, 0.5f});
  (void)image->sampleBilinear({1.0f, 0.0f});
  return 0;
}

// PNG output of rendered frames through stb_image_write (Debian's stb,
// which carries the implementation in libstb).

#include <stb_image_write.h>

#include <cstdint>
#include <vector>

#include "scene/file_output.h"
#include "scene_renderer_target.h"

namespace svit::gl {

Status writeRgbPng(const std::string& path, int width, int height,
                   const std::vector<uint8_t>& rgb) {
  if (width < 1 || height < 1 || rgb.size() != size_t(width) * size_t(height) * 3) {
    return Status(StatusCode::kInvalidInput, path + ": no frame to write (render one first)");
  }
  // Encoded in memory and written by writeFileReplacing (beside the target,
  // then renamed): stbi_write_png checks neither fwrite nor fclose, so a full
  // disk or `ulimit -f` would leave a cut PNG and report success.
  std::vector<uint8_t> png;
  auto append = [](void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<uint8_t>*>(context);
    bytes->insert(bytes->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  };
  if (stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3) == 0)
    return Status(StatusCode::kIoError, path + ": cannot encode the PNG");
  return writeFileReplacing(path, png.data(), png.size());
}

}  // namespace svit::gl

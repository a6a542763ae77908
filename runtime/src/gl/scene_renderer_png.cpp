// PNG output of rendered frames through stb_image_write (Debian's stb,
// which carries the implementation in libstb).

#include <stb_image_write.h>

#include <filesystem>
#include <system_error>

#include "scene_renderer_target.h"

namespace svit::gl {

Status writeRgbPng(const std::string& path, int width, int height,
                   const std::vector<uint8_t>& rgb) {
  if (width < 1 || height < 1 || rgb.size() != size_t(width) * size_t(height) * 3) {
    return Status(StatusCode::kInvalidInput, path + ": no frame to write (render one first)");
  }
  // Write beside the target and rename, so a failure never leaves half a file.
  const std::string tmp = path + ".tmp";
  if (stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), width * 3) == 0) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return Status(StatusCode::kIoError, path + ": cannot write the PNG");
  }
  std::error_code error;
  std::filesystem::rename(tmp, path, error);
  if (error) {
    std::filesystem::remove(tmp, error);
    return Status(StatusCode::kIoError, path + ": cannot write the PNG (" + error.message() + ")");
  }
  return Status();
}

}  // namespace svit::gl

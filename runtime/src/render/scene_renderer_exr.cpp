// OpenEXR output of rendered frames' linear radiance: the baker's fp32 RGB
// writer (writeLightmapExr, tinyexr, ZIP), so frames and lightmap pages
// share one EXR path and its tmp-and-rename.

#include "svit/lightmap_image.h"

#include "scene_renderer_target.h"

namespace svit::gl {

Status writeRgbExr(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  if (width < 1 || height < 1 || rgb.size() != size_t(width) * size_t(height) * 3) {
    return Status(StatusCode::kInvalidInput, path + ": no frame to write (render one first)");
  }
  // EXR rows run top to bottom (y grows down the data window), as ours do.
  LightmapImage image;
  image.width = width;
  image.height = height;
  image.rgb = rgb;
  return writeLightmapExr(image, path);
}

}  // namespace svit::gl

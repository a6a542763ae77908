#pragma once
// The SceneRenderer's offscreen target: RGBA8 colour (already tone mapped
// and sRGB encoded by the shaders) and a 32-bit float depth buffer.

#include <cstdint>
#include <string>
#include <vector>

#include "gl_memory.h"
#include "svit/status.h"

namespace svit::gl {

class OffscreenTarget {
 public:
  /// Allocates a `width` x `height` target. Errors: size outside 1..16384, an
  /// incomplete framebuffer.
  static Expected<OffscreenTarget> create(int width, int height);
  OffscreenTarget() = default;
  OffscreenTarget(OffscreenTarget&& other) noexcept;
  OffscreenTarget& operator=(OffscreenTarget&& other) noexcept;
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;
  ~OffscreenTarget();

  uint32_t framebuffer() const { return framebuffer_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// The colour as 8-bit RGB, rows top first (GL's first row is the bottom).
  std::vector<uint8_t> readRgb() const;

  std::vector<GlObject> glObjects() const { return {glTextureObject(colour_), glRenderbufferObject(depth_)}; }

 private:
  void release();
  uint32_t framebuffer_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

/// Writes 8-bit RGB rows (top first) as a PNG. Errors name the path.
Status writeRgbPng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace svit::gl

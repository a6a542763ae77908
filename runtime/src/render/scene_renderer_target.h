#pragma once
// The SceneRenderer's offscreen target: RGBA8 colour (already tone mapped
// and sRGB encoded by the shaders) at attachment 0, RGBA32F linear radiance
// (cd/m2, before exposure and the tone curve) at attachment 1, and a 32-bit
// float depth buffer.

#include <cstdint>
#include <string>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/status.h"

namespace svit::gl {

class OffscreenTarget {
 public:
  /// Allocates a `width` x `height` target drawing to the colour attachment
  /// only. Errors: size outside 1..16384, an incomplete framebuffer.
  static Expected<OffscreenTarget> create(int width, int height);
  OffscreenTarget() = default;
  OffscreenTarget(OffscreenTarget&& other) noexcept;
  OffscreenTarget& operator=(OffscreenTarget&& other) noexcept;
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;
  ~OffscreenTarget();

  uint32_t framebuffer() const { return framebuffer_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  /// Fragment outputs 0 and 1 go to colour and radiance (the lit passes);
  /// with `false` only output 0 goes to colour, so a host's HUD drawn after
  /// the frame leaves the radiance as the lit passes wrote it.
  void drawRadiance(bool on) const;
  /// The colour as 8-bit RGB, rows top first (GL's first row is the bottom).
  std::vector<uint8_t> readRgb() const;
  /// The radiance as linear float RGB, cd/m2, rows top first.
  std::vector<float> readRadiance() const;
  /// Sets the radiance attachment to 0, its alpha (the surface kind) too.
  void clearRadiance() const;
  /// The radiance attachment's alpha: svit::SurfaceKind per pixel, rows top first.
  std::vector<uint8_t> readSurfaceKinds() const;

  std::vector<GlObject> glObjects() const {
    return {glTextureObject(colour_.id()), glTextureObject(radiance_.id()),
            glRenderbufferObject(depth_.id())};
  }

 private:
  void release();
  GlFramebuffer framebuffer_;
  GlTexture colour_, radiance_;
  GlRenderbuffer depth_;
  int width_ = 0, height_ = 0;
};

/// Writes 8-bit RGB rows (top first) as a PNG. Errors name the path.
Status writeRgbPng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

/// Writes linear float RGB rows (top first) as an fp32 OpenEXR, via
/// `path`.tmp and a rename. Errors name the path: no frame, a value that
/// is not finite, I/O failure.
Status writeRgbExr(const std::string& path, int width, int height, const std::vector<float>& rgb);

}  // namespace svit::gl

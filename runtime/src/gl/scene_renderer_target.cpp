#include "scene_renderer_target.h"

#include <epoxy/gl.h>

#include <cstring>
#include <string>
#include <utility>

#include "gl_program.h"

namespace svit::gl {

Expected<OffscreenTarget> OffscreenTarget::create(int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    return Status(StatusCode::kInvalidInput, "render target " + std::to_string(width) + "x" + std::to_string(height) +
                                                 " is outside 1..16384");
  }
  OffscreenTarget out;
  out.width_ = width;
  out.height_ = height;
  glCreateTextures(GL_TEXTURE_2D, 1, &out.colour_);
  glTextureStorage2D(out.colour_, 1, GL_RGBA8, width, height);
  glCreateRenderbuffers(1, &out.depth_);
  glNamedRenderbufferStorage(out.depth_, GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &out.framebuffer_);
  glNamedFramebufferTexture(out.framebuffer_, GL_COLOR_ATTACHMENT0, out.colour_, 0);
  glNamedFramebufferRenderbuffer(out.framebuffer_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, out.depth_);
  const GLenum status = glCheckNamedFramebufferStatus(out.framebuffer_, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    return Status(StatusCode::kInternal, "render target " + std::to_string(width) + "x" + std::to_string(height) +
                                             ": framebuffer incomplete (status " + std::to_string(status) + ")");
  }
  Status error = checkGlError("creating the render target");
  if (!error.ok()) return error;
  return out;
}

OffscreenTarget::OffscreenTarget(OffscreenTarget&& other) noexcept { *this = std::move(other); }

OffscreenTarget& OffscreenTarget::operator=(OffscreenTarget&& other) noexcept {
  if (this != &other) {
    release();
    framebuffer_ = std::exchange(other.framebuffer_, 0);
    colour_ = std::exchange(other.colour_, 0);
    depth_ = std::exchange(other.depth_, 0);
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
  }
  return *this;
}

OffscreenTarget::~OffscreenTarget() { release(); }

void OffscreenTarget::release() {
  if (framebuffer_ != 0) glDeleteFramebuffers(1, &framebuffer_);
  if (colour_ != 0) glDeleteTextures(1, &colour_);
  if (depth_ != 0) glDeleteRenderbuffers(1, &depth_);
  framebuffer_ = colour_ = depth_ = 0;
}

std::vector<uint8_t> OffscreenTarget::readRgb() const {
  if (framebuffer_ == 0) return {};
  const size_t row = size_t(width_) * 3;
  std::vector<uint8_t> bottom_up(row * size_t(height_));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glNamedFramebufferReadBuffer(framebuffer_, GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  std::vector<uint8_t> top_down(bottom_up.size());
  for (int y = 0; y < height_; ++y) {
    std::memcpy(&top_down[size_t(y) * row], &bottom_up[size_t(height_ - 1 - y) * row], row);
  }
  return top_down;
}

}  // namespace svit::gl

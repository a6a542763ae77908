#include "scene_renderer_target.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>

#include "gl/gl_program.h"

namespace svit::gl {

Expected<OffscreenTarget> OffscreenTarget::create(int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    return Status(StatusCode::kInvalidInput, "render target " + std::to_string(width) + "x" +
                                                 std::to_string(height) + " is outside 1..16384");
  }
  OffscreenTarget out;
  out.width_ = width;
  out.height_ = height;
  out.colour_ = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(out.colour_.id(), 1, GL_RGBA8, width, height);
  // RGBA, not RGB: GL 4.5 does not require RGB32F to be colour-renderable.
  out.radiance_ = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(out.radiance_.id(), 1, GL_RGBA32F, width, height);
  out.depth_ = createGlRenderbuffer();
  glNamedRenderbufferStorage(out.depth_.id(), GL_DEPTH_COMPONENT32F, width, height);
  out.framebuffer_ = createGlFramebuffer();
  const GLuint framebuffer = out.framebuffer_.id();
  glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, out.colour_.id(), 0);
  glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT1, out.radiance_.id(), 0);
  glNamedFramebufferRenderbuffer(framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                 out.depth_.id());
  out.drawRadiance(false);
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    return Status(StatusCode::kInternal,
                  "render target " + std::to_string(width) + "x" + std::to_string(height) +
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
    framebuffer_ = std::move(other.framebuffer_);
    colour_ = std::move(other.colour_);
    radiance_ = std::move(other.radiance_);
    depth_ = std::move(other.depth_);
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
  }
  return *this;
}

OffscreenTarget::~OffscreenTarget() { release(); }

void OffscreenTarget::release() {
  framebuffer_.reset();
  colour_.reset();
  radiance_.reset();
  depth_.reset();
}

void OffscreenTarget::drawRadiance(bool on) const {
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_.id(), on ? 2 : 1, both);
}

namespace {

// Reads `attachment` as RGB (or RGBA), 3 (4) `T` per pixel, and flips the
// rows to top first (GL's first row is the bottom).
template <typename T>
std::vector<T> readTopDown(uint32_t framebuffer, GLenum attachment, int width, int height,
                           GLenum format = GL_RGB) {
  constexpr GLenum kType = std::is_same_v<T, float> ? GL_FLOAT : GL_UNSIGNED_BYTE;
  const size_t row = size_t(width) * (format == GL_RGBA ? 4 : 3);
  std::vector<T> bottom_up(row * size_t(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glNamedFramebufferReadBuffer(framebuffer, attachment);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glReadPixels(0, 0, width, height, format, kType, bottom_up.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glNamedFramebufferReadBuffer(framebuffer, GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  std::vector<T> top_down(bottom_up.size());
  for (int y = 0; y < height; ++y) {
    std::memcpy(&top_down[size_t(y) * row], &bottom_up[size_t(height - 1 - y) * row],
                row * sizeof(T));
  }
  return top_down;
}

}  // namespace

std::vector<uint8_t> OffscreenTarget::readRgb() const {
  if (!framebuffer_) return {};
  return readTopDown<uint8_t>(framebuffer_.id(), GL_COLOR_ATTACHMENT0, width_, height_);
}

// A float attachment reads back unclamped (GL_CLAMP_READ_COLOR defaults to
// GL_FIXED_ONLY): radiance above 1 cd/m2 survives.
std::vector<float> OffscreenTarget::readRadiance() const {
  if (!framebuffer_) return {};
  return readTopDown<float>(framebuffer_.id(), GL_COLOR_ATTACHMENT1, width_, height_);
}

void OffscreenTarget::clearRadiance() const {
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 1, zero);
}

std::vector<uint8_t> OffscreenTarget::readSurfaceKinds() const {
  if (!framebuffer_) return {};
  const std::vector<float> rgba =
      readTopDown<float>(framebuffer_.id(), GL_COLOR_ATTACHMENT1, width_, height_, GL_RGBA);
  std::vector<uint8_t> kinds(rgba.size() / 4);
  for (size_t i = 0; i < kinds.size(); ++i)
    kinds[i] = uint8_t(std::lround(std::clamp(rgba[i * 4 + 3], 0.0f, 255.0f)));
  return kinds;
}

}  // namespace svit::gl

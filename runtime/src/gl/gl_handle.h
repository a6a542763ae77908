#pragma once
// One owning handle for GL object names: buffers, textures, framebuffers,
// renderbuffers, vertex arrays, queries, shaders and programs. Move-only;
// deletes its name on destruction or reset, so no other file calls
// glDelete*. The context that made the name must be current then.

#include <cstdint>
#include <utility>

namespace svit::gl {

enum class GlKind {
  kBuffer,
  kTexture,
  kFramebuffer,
  kRenderbuffer,
  kVertexArray,
  kQuery,
  kShader,
  kProgram
};

/// Deletes `name` (non-zero) of `kind`: gl_handle.cpp, the one place that does.
void deleteGlName(GlKind kind, uint32_t name);

template <GlKind kKind>
class GlHandle {
 public:
  GlHandle() = default;
  /// Takes ownership of `name` (0 = none).
  explicit GlHandle(uint32_t name) : name_(name) {}
  GlHandle(GlHandle&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  GlHandle& operator=(GlHandle&& other) noexcept {
    if (this != &other) reset(std::exchange(other.name_, 0));
    return *this;
  }
  GlHandle(const GlHandle&) = delete;
  GlHandle& operator=(const GlHandle&) = delete;
  ~GlHandle() { reset(); }

  uint32_t id() const { return name_; }
  explicit operator bool() const { return name_ != 0; }
  /// Deletes the name held, then owns `name`.
  void reset(uint32_t name = 0) {
    if (name_ != 0) deleteGlName(kKind, name_);
    name_ = name;
  }
  /// Gives the name up without deleting it.
  uint32_t release() { return std::exchange(name_, 0); }

 private:
  uint32_t name_ = 0;
};

using GlBuffer = GlHandle<GlKind::kBuffer>;
using GlTexture = GlHandle<GlKind::kTexture>;
using GlFramebuffer = GlHandle<GlKind::kFramebuffer>;
using GlRenderbuffer = GlHandle<GlKind::kRenderbuffer>;
using GlVertexArray = GlHandle<GlKind::kVertexArray>;
using GlQuery = GlHandle<GlKind::kQuery>;
using GlShader = GlHandle<GlKind::kShader>;
using GlProgram = GlHandle<GlKind::kProgram>;  ///< linkProgram() (gl_program.h) makes them

/// New names made with glCreate* (DSA, GL 4.5): initialised objects of their
/// kind, ready for glNamed*/glTexture* calls.
GlBuffer createGlBuffer();
GlTexture createGlTexture(uint32_t target);
GlFramebuffer createGlFramebuffer();
GlRenderbuffer createGlRenderbuffer();
GlVertexArray createGlVertexArray();
GlQuery createGlQuery(uint32_t target);

}  // namespace svit::gl

#pragma once
// Compiling and linking GLSL programs from the embedded shaders/ files, with
// errors that name the file and carry the driver's log.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

#include "svit/status.h"

namespace svit::gl {

/// An owned GL program object (0 = none). Move-only; deletes on destruction
/// (needs the context it was made in to be current then).
class GlProgram {
 public:
  GlProgram() = default;
  explicit GlProgram(uint32_t id) : id_(id) {}
  GlProgram(GlProgram&& other) noexcept : id_(other.id_) { other.id_ = 0; }
  GlProgram& operator=(GlProgram&& other) noexcept;
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;
  ~GlProgram();
  uint32_t id() const { return id_; }

 private:
  uint32_t id_ = 0;
};

/// Links a program from shader files of shaders/ (stage from the extension:
/// .vert .geom .frag .comp). `defines` lines ("NAME VALUE") are inserted
/// after the #version line. Errors: unknown file, compile or link failure,
/// with the file name and the driver's log.
Expected<GlProgram> linkProgram(std::initializer_list<std::string_view> files,
                                std::initializer_list<std::string_view> defines = {});

/// A GL error left by the calls since the last check, as a Status naming
/// `where`, or OK.
Status checkGlError(const char* where);

}  // namespace svit::gl

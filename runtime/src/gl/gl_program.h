#pragma once
// Compiling and linking GLSL programs from the embedded shaders/ files, with
// errors that name the file and carry the driver's log.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

#include "gl_handle.h"
#include "svit/status.h"

namespace svit::gl {

/// Links a program (an owning GlProgram of gl_handle.h) from shader files of
/// shaders/ (stage from the extension: .vert .geom .frag .comp). `defines`
/// lines ("NAME VALUE") are inserted after the #version line. Errors: unknown file, compile or link
/// failure, with the file name and the driver's log.
Expected<GlProgram> linkProgram(std::initializer_list<std::string_view> files,
                                std::initializer_list<std::string_view> defines = {});

/// A GL error left by the calls since the last check, as a Status naming
/// `where`, or OK.
Status checkGlError(const char* where);

}  // namespace svit::gl

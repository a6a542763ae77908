#pragma once
// GLSL sources from shaders/, compiled into the library by
// cmake/EmbedShaders.cmake so a game never ships or finds shader files.

#include <string_view>

namespace svit::gl {

/// The text of shaders/<file_name> (e.g. "index_map.frag"), or an empty view
/// when there is no such shader. Thread-safe.
std::string_view shaderSource(std::string_view file_name);

}  // namespace svit::gl

#include "gl_program.h"

#include <epoxy/gl.h>

#include <string>
#include <vector>

#include "shader_sources.h"

namespace svit::gl {
namespace {

Expected<GLenum> stageOf(std::string_view file) {
  auto ends = [&](std::string_view suffix) {
    return file.size() >= suffix.size() && file.substr(file.size() - suffix.size()) == suffix;
  };
  if (ends(".vert")) return GLenum(GL_VERTEX_SHADER);
  if (ends(".geom")) return GLenum(GL_GEOMETRY_SHADER);
  if (ends(".frag")) return GLenum(GL_FRAGMENT_SHADER);
  if (ends(".comp")) return GLenum(GL_COMPUTE_SHADER);
  return Status(StatusCode::kInternal,
                "shader '" + std::string(file) + "': unknown stage (extension)");
}

// Inserts the defines after the first line (#version).
std::string withDefines(std::string_view text, std::initializer_list<std::string_view> defines) {
  const size_t eol = text.find('\n');
  std::string out(text.substr(0, eol == std::string_view::npos ? text.size() : eol + 1));
  for (std::string_view d : defines) out += "#define " + std::string(d) + "\n";
  if (eol != std::string_view::npos) out += text.substr(eol + 1);
  return out;
}

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log;
}

}  // namespace

Expected<GlProgram> linkProgram(std::initializer_list<std::string_view> files,
                                std::initializer_list<std::string_view> defines) {
  GlProgram program(glCreateProgram());
  // Deleted once linked (or on an error): the program keeps what it needs.
  std::vector<GlShader> shaders;
  for (std::string_view file : files) {
    const std::string_view text = shaderSource(file);
    if (text.empty()) {
      return Status(StatusCode::kInternal, "shader '" + std::string(file) + "' is not in shaders/");
    }
    Expected<GLenum> stage = stageOf(file);
    if (!stage.ok()) return stage.status();
    shaders.emplace_back(glCreateShader(*stage));
    const GLuint shader = shaders.back().id();
    const std::string source = withDefines(text, defines);
    const char* source_ptr = source.c_str();
    glShaderSource(shader, 1, &source_ptr, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      return Status(StatusCode::kInternal,
                    "shader '" + std::string(file) + "' does not compile: " + shaderLog(shader));
    }
    glAttachShader(program.id(), shader);
  }
  glLinkProgram(program.id());
  shaders.clear();
  GLint linked = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
  if (!linked) {
    GLint length = 0;
    glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program.id(), length, nullptr, log.data());
    std::string names;
    for (std::string_view f : files) names += (names.empty() ? "" : " + ") + std::string(f);
    return Status(StatusCode::kInternal, "program " + names + " does not link: " + log);
  }
  return program;
}

Status checkGlError(const char* where) {
  GLenum first = glGetError();
  if (first == GL_NO_ERROR) return Status();
  while (glGetError() != GL_NO_ERROR) {}
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", unsigned(first));
  return Status(StatusCode::kInternal, std::string("OpenGL error ") + code + " in " + where);
}

}  // namespace svit::gl

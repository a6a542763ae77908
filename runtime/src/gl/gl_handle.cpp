#include "gl_handle.h"

#include <epoxy/gl.h>

namespace svit::gl {

void deleteGlName(GlKind kind, uint32_t name) {
  GLuint n = name;
  switch (kind) {
    case GlKind::kBuffer: glDeleteBuffers(1, &n); break;
    case GlKind::kTexture: glDeleteTextures(1, &n); break;
    case GlKind::kFramebuffer: glDeleteFramebuffers(1, &n); break;
    case GlKind::kRenderbuffer: glDeleteRenderbuffers(1, &n); break;
    case GlKind::kVertexArray: glDeleteVertexArrays(1, &n); break;
    case GlKind::kQuery: glDeleteQueries(1, &n); break;
    case GlKind::kShader: glDeleteShader(n); break;
    case GlKind::kProgram: glDeleteProgram(n); break;
  }
}

GlBuffer createGlBuffer() {
  GLuint n = 0;
  glCreateBuffers(1, &n);
  return GlBuffer(n);
}

GlTexture createGlTexture(uint32_t target) {
  GLuint n = 0;
  glCreateTextures(GLenum(target), 1, &n);
  return GlTexture(n);
}

GlFramebuffer createGlFramebuffer() {
  GLuint n = 0;
  glCreateFramebuffers(1, &n);
  return GlFramebuffer(n);
}

GlRenderbuffer createGlRenderbuffer() {
  GLuint n = 0;
  glCreateRenderbuffers(1, &n);
  return GlRenderbuffer(n);
}

GlVertexArray createGlVertexArray() {
  GLuint n = 0;
  glCreateVertexArrays(1, &n);
  return GlVertexArray(n);
}

GlQuery createGlQuery(uint32_t target) {
  GLuint n = 0;
  glCreateQueries(GLenum(target), 1, &n);
  return GlQuery(n);
}

}  // namespace svit::gl

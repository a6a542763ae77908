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

namespace {

// A handle owning the one name `create` (a glCreate* call) writes.
template <typename Handle, typename Create>
Handle created(Create&& create) {
  GLuint n = 0;
  create(&n);
  return Handle(n);
}

}  // namespace

GlBuffer createGlBuffer() {
  return created<GlBuffer>([](GLuint* n) { glCreateBuffers(1, n); });
}
GlTexture createGlTexture(uint32_t target) {
  return created<GlTexture>([&](GLuint* n) { glCreateTextures(GLenum(target), 1, n); });
}
GlFramebuffer createGlFramebuffer() {
  return created<GlFramebuffer>([](GLuint* n) { glCreateFramebuffers(1, n); });
}
GlRenderbuffer createGlRenderbuffer() {
  return created<GlRenderbuffer>([](GLuint* n) { glCreateRenderbuffers(1, n); });
}
GlVertexArray createGlVertexArray() {
  return created<GlVertexArray>([](GLuint* n) { glCreateVertexArrays(1, n); });
}
GlQuery createGlQuery(uint32_t target) {
  return created<GlQuery>([&](GLuint* n) { glCreateQueries(GLenum(target), 1, n); });
}

}  // namespace svit::gl

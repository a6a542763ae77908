// Detects a current GL context before any GL call: with libepoxy a GL call
// without a context aborts the process, which a game must never see.

#include "svit/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <epoxy/glx.h>
// Xlib defines Status as a macro; svit::Status is meant below.
#undef Status

namespace svit {
namespace {

bool hasCurrentContext() {
  // GLFW and most engines on Linux use GLX; headless and Wayland hosts use
  // EGL. Asking either for the current context is safe without one.
  if (glXGetCurrentContext() != nullptr) return true;
  return epoxy_has_egl() && eglGetCurrentContext() != EGL_NO_CONTEXT;
}

}  // namespace

Expected<GlContextInfo> checkGlContext() {
  if (!hasCurrentContext()) {
    return Status(StatusCode::kUnsupported,
                  "svit runtime: no current OpenGL context on this thread (make an OpenGL 4.5 "
                  "core context current before creating the runtime)");
  }
  GlContextInfo info;
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);
  GLint mask = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
  info.core_profile = (mask & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  info.renderer = renderer ? renderer : "";
  info.version = version ? version : "";
  if (info.major < 4 || (info.major == 4 && info.minor < 5)) {
    return Status(StatusCode::kUnsupported, "svit runtime: OpenGL " + std::to_string(info.major) +
                                                "." + std::to_string(info.minor) + " (" +
                                                info.renderer +
                                                ") is current; svit needs OpenGL 4.5");
  }
  return info;
}

}  // namespace svit

#pragma once
// Checks that the calling thread has a current OpenGL context the runtime
// can use. The host (game) owns the context; svit never creates one.

#include <string>

#include "svit/status.h"

namespace svit {

/// What the current context is.
struct GlContextInfo {
  int major = 0;
  int minor = 0;
  bool core_profile = false;
  std::string renderer;  ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   ///< GL_VERSION string
};

/// Returns the current context's version and renderer, or kUnsupported when
/// no context is current on this thread (GLX or EGL) or it is older than
/// OpenGL 4.5. Never calls GL without a current context, so it never crashes.
/// Thread-safe: checks the calling thread's context.
Expected<GlContextInfo> checkGlContext();

}  // namespace svit

#pragma once
// svit::ResourceUse — one line of the "pay for what is used" audit: a
// buffer, texture set or CPU table the runtime or the renderer keeps, and
// why it is there, or why it was left out (Runtime::resources(),
// SceneRenderer::resources()).

#include <cstdint>
#include <string>

namespace svit {

struct ResourceUse {
  std::string name;         ///< what it is, e.g. "index maps (id + depth layers)"
  bool allocated = false;   ///< false: left out, `reason` says why
  uint32_t gl_objects = 0;  ///< GL buffers, textures and renderbuffers it holds
  uint64_t gpu_bytes = 0;   ///< their storage, measured through GL queries
  uint64_t cpu_bytes = 0;   ///< host memory, from the containers' sizes
  std::string reason;       ///< why it exists, or why it is not needed
};

}  // namespace svit

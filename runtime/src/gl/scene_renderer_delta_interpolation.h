#pragma once
// The runtime's per-patch irradiance deltas interpolated at the static
// mesh's welded vertices on the GPU (shaders/delta_to_vertices.comp): a
// small compute pass from Runtime::shadingResources().patch_delta_buffer
// into a vec4-per-vertex buffer that lit_static.vert reads. Rerun only when
// the deltas changed.

#include <cstdint>

#include "gl_memory.h"
#include "scene_renderer_static_mesh.h"
#include "gl_program.h"
#include "svit/status.h"

namespace svit::gl {

class VertexDeltaInterpolator {
 public:
  /// Uploads the vertex -> patch lists and allocates the output (zeros).
  /// Nothing is allocated when `deltas` has no vertices. Needs a current GL
  /// 4.5 context. Errors: the compute shader does not compile.
  static Expected<VertexDeltaInterpolator> create(const DeltaInterpolation& deltas);
  VertexDeltaInterpolator() = default;
  VertexDeltaInterpolator(VertexDeltaInterpolator&& other) noexcept;
  VertexDeltaInterpolator& operator=(VertexDeltaInterpolator&& other) noexcept;
  VertexDeltaInterpolator(const VertexDeltaInterpolator&) = delete;
  VertexDeltaInterpolator& operator=(const VertexDeltaInterpolator&) = delete;
  ~VertexDeltaInterpolator();

  /// Recomputes every vertex delta from `patch_delta_buffer` (std430 vec4
  /// per patch, at least as many as the lists name). Ends with the barrier
  /// that makes the result visible to shader storage reads.
  void update(uint32_t patch_delta_buffer);
  /// Sets every vertex delta to zero (no runtime content).
  void clear();

  /// vec4 per welded vertex (lux); 0 when there are none.
  uint32_t vertexDeltaBuffer() const { return vertex_deltas_; }
  uint32_t vertexCount() const { return vertex_count_; }

  std::vector<GlObject> glObjects() const {
    return {glBufferObject(offsets_), glBufferObject(entries_), glBufferObject(vertex_deltas_)};
  }

 private:
  void release();
  GlProgram program_;
  uint32_t vertex_count_ = 0;
  uint32_t offsets_ = 0, entries_ = 0, vertex_deltas_ = 0;
};

}  // namespace svit::gl

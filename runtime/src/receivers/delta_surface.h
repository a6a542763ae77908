#pragma once
// The runtime's displayed deltas as a shader looks them up per pixel, at
// the resolution of the runtime patches rather than of the static mesh's
// vertices (a two-triangle wall has four vertices, and runtime patches cut
// bake triangles into n x n sub-triangles): for a static triangle side
// (bake element) and barycentrics inside it, the sub-triangle under the
// point and the delta interpolated between its welded vertices, exactly as
// Runtime::irradianceAt does on the CPU (RuntimePatches::subTriangle); the
// w of each vertex is the factor on the lightmap minus 1 (dimmed baked
// emitters, runtime_light_scale.cpp).
// shaders/svit_runtime_delta.frag is the GLSL side; the three buffers are
// ShadingResources::delta_elements, delta_slots and vertex_deltas.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "runtime_patches.h"

namespace svit::gl {

class DeltaSurfaceBuffers {
 public:
  /// Uploads the tessellation tables of `patches` and allocates the vertex
  /// deltas (zeros). Needs a current GL 4.5 context.
  static DeltaSurfaceBuffers create(const RuntimePatches& patches);
  DeltaSurfaceBuffers() = default;
  DeltaSurfaceBuffers(DeltaSurfaceBuffers&& other) noexcept;
  DeltaSurfaceBuffers& operator=(DeltaSurfaceBuffers&& other) noexcept;
  DeltaSurfaceBuffers(const DeltaSurfaceBuffers&) = delete;
  DeltaSurfaceBuffers& operator=(const DeltaSurfaceBuffers&) = delete;
  ~DeltaSurfaceBuffers();

  /// Replaces the per-welded-vertex deltas (lux) and light scales minus 1
  /// (the x of `scale_minus_one`; empty: 0), `patches.vertex_count` of each.
  void upload(const std::vector<glm::dvec3>& vertex_values,
              const std::vector<glm::dvec3>& scale_minus_one);

  bool allocated() const { return bool(vertex_deltas_); }
  uint32_t elementBuffer() const { return elements_.id(); }
  uint32_t slotBuffer() const { return slots_.id(); }
  uint32_t vertexDeltaBuffer() const { return vertex_deltas_.id(); }
  std::vector<GlObject> glObjects() const {
    return {glBufferObject(elements_.id()), glBufferObject(slots_.id()),
            glBufferObject(vertex_deltas_.id())};
  }

 private:
  GlBuffer elements_, slots_, vertex_deltas_;
  uint32_t vertex_count_ = 0;
};

}  // namespace svit::gl

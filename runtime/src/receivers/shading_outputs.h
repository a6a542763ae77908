#pragma once
// What the runtime hands to shading (ShadingResources) and to its queries:
// the per-receiver deltas of the last solve, the displayed (temporally
// blended) deltas, and the GL objects they are uploaded to, owned here.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "delta_surface.h"
#include "gl/gl_handle.h"
#include "receivers.h"
#include "runtime_patches.h"
#include "svit/lightmap_image.h"
#include "svit/runtime.h"

namespace svit::gl {

/// What one upload shows, besides the deltas of the outputs themselves.
struct DisplayInput {
  const RuntimePatches* patches = nullptr;
  uint32_t static_receivers = 0;
  /// Per static receiver: the factor on its baked light (1 = as baked);
  /// empty while every baked emitter is as baked.
  const std::vector<double>* light_scale = nullptr;
  const std::vector<DynamicObject>* objects = nullptr;
  const std::vector<LightmapImage>* pages = nullptr;
  float temporal_blend = 1;
  bool delta_textures = false;  ///< RuntimeSettings::delta_textures
};

class ShadingOutputs {
 public:
  // Per receiver, from the last solve.
  /// irradiance delta incl. runtime lights' direct light, lux
  std::vector<glm::dvec3> delta_total;
  /// direct irradiance shaded per pixel, lux: runtime lights' everywhere,
  /// masked baked lights' on static surfaces
  /// (the name is older than the masks)
  std::vector<glm::dvec3> runtime_direct;
  std::vector<Rgb> display;  ///< what shading adds (temporally blended), lux
  /// the masked baked lights' first-round delta on static receivers, lux
  /// (part of delta_total and of runtime_direct; shaded per pixel)
  std::vector<glm::dvec3> masked_direct;

  /// Grows the per-receiver vectors to `receivers` (objects are appended).
  void resize(size_t receivers);
  /// A solve changed delta_total: the vertex values are recomputed when asked.
  void deltasChanged() { vertex_deltas_stale_ = true; }
  /// delta_total less masked_direct (what shading interpolates over the
  /// patches) at the welded vertices of `patches` (computed lazily).
  const std::vector<glm::dvec3>& vertexDeltas(const RuntimePatches& patches) const;
  /// The light scale minus 1 (x) at the welded vertices, as the last upload
  /// showed it; empty while every baked emitter is as baked.
  const std::vector<glm::dvec3>& vertexScales() const { return vertex_scales_; }

  /// Blends `display` towards the solve's deltas and uploads it to the
  /// patch delta buffer, the delta surface and (when asked) the delta
  /// textures. Returns the GL objects it had to create.
  uint32_t upload(const DisplayInput& in);

  /// The lightmap pages as textures, made on the first call.
  std::vector<uint32_t> lightmapTextures(const std::vector<LightmapImage>& pages) const;

  uint32_t deltaBuffer() const { return delta_buffer_.id(); }
  uint32_t deltaBufferReceivers() const { return delta_buffer_receivers_; }
  std::vector<uint32_t> deltaTextures() const { return ids(delta_textures_); }
  const DeltaSurfaceBuffers& deltaSurface() const { return delta_surface_; }
  std::vector<GlObject> lightmapObjects() const { return textureObjects(lightmap_textures_); }
  std::vector<GlObject> deltaTextureObjects() const { return textureObjects(delta_textures_); }
  /// Host bytes of the per-receiver vectors.
  uint64_t hostBytes() const;

 private:
  static std::vector<uint32_t> ids(const std::vector<GlTexture>& textures);
  static std::vector<GlObject> textureObjects(const std::vector<GlTexture>& textures);
  std::vector<float> packReceivers(const DisplayInput& in);
  uint32_t uploadPatchBuffer(const std::vector<float>& packed, size_t receivers);
  uint32_t uploadDeltaTextures(const DisplayInput& in, const std::vector<glm::dvec3>& shown,
                               const std::vector<glm::dvec3>& scales);

  mutable std::vector<glm::dvec3> vertex_deltas_;
  mutable bool vertex_deltas_stale_ = true;
  std::vector<glm::dvec3> vertex_scales_;
  GlBuffer delta_buffer_;
  uint32_t delta_buffer_receivers_ = 0;
  mutable std::vector<GlTexture> lightmap_textures_;
  std::vector<GlTexture> delta_textures_;  ///< per page, GL_RGBA32F at half size (delta_atlas.h)
  /// per-pixel lookup of the static deltas (delta_surface.h)
  DeltaSurfaceBuffers delta_surface_;
};

}  // namespace svit::gl

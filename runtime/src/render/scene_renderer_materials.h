#pragma once
// Materials for the SceneRenderer: the scene's colour textures on the GPU
// (sRGB-decoded by the sampler, mipmapped) and the per-draw uniforms of a
// material (base colour factor and texture with KHR_texture_transform,
// emissive luminance and texture, sidedness, alpha mask).

#include <cstdint>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::gl {

class MaterialTextures {
 public:
  /// Uploads every texture a material uses as base colour or emission
  /// (GL_SRGB8_ALPHA8 + mipmaps, the glTF sampler's wrap modes). Textures
  /// no material uses are not uploaded. Errors: a texture whose texel count
  /// does not match its size (named), a GL error.
  static Expected<MaterialTextures> create(const Scene& scene);
  MaterialTextures() = default;
  MaterialTextures(MaterialTextures&& other) noexcept;
  MaterialTextures& operator=(MaterialTextures&& other) noexcept;
  MaterialTextures(const MaterialTextures&) = delete;
  MaterialTextures& operator=(const MaterialTextures&) = delete;
  ~MaterialTextures();

  /// Sets the material uniforms (scene_renderer_bindings.h) of the current
  /// program and binds its textures (a white texel where it has none).
  void bind(const Material& material) const;

  /// The uploaded textures and the 1x1 white one.
  std::vector<GlObject> glObjects() const;
  /// Scene textures not uploaded because no material uses them.
  size_t skippedCount() const;

 private:
  std::vector<GlTexture> textures_;  ///< per Scene::textures entry; none = not uploaded
  GlTexture white_;
};

}  // namespace svit::gl

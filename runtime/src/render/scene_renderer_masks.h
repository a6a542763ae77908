#pragma once
// The bake's shadow masks (BakeShadowMasks) as GL textures: per lightmap
// page one GL_RGBA16UI array of the masks' layers, read with texelFetch
// (an owner and a visibility per channel: not filterable, so
// lit_static.frag filters them itself). Nothing is made for a bake
// without masks.

#include <cstdint>
#include <string>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/bake_file.h"
#include "svit/masked_lights.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::gl {

class ShadowMaskTextures {
 public:
  static Expected<ShadowMaskTextures> create(const BakeData& bake);
  bool empty() const { return textures_.empty(); }
  uint32_t texture(uint32_t page) const { return textures_[page].id(); }
  std::vector<GlObject> glObjects() const;

 private:
  std::vector<GlTexture> textures_;
};

/// The masked lights as the renderer shades them, and how much brighter a
/// masked bake's surfaces are than its lightmap says (the masked lights'
/// direct light is not in the pages), for auto exposure: the
/// area-weighted log-mean irradiance over the static triangles' centroids
/// with the masked lights, over that without (1 without masks).
struct MaskedShading {
  MaskedLightField field;
  double exposure_ratio = 1;
};

/// Errors: unreadable pages, a bake of another level.
Expected<MaskedShading> prepareMaskedShading(const Scene& scene, const BakeData& bake,
                                             const std::string& bake_dir);

/// The masked area lights' triangles for lit_static.frag
/// (render_binding::kAreaLights): per area light a header vec4 (x: its
/// element count), then per element four vec4s: its corners, wound to
/// face the emitting side, and its luminance (rgb, cd/m2). Nothing is made
/// for a bake without area lights.
class AreaLightBuffer {
 public:
  static AreaLightBuffer create(const MaskedLightField& field);
  /// Masked light k's first vec4 (0 for a light that is not an area).
  uint32_t offset(size_t k) const { return offsets_[k]; }
  void bind() const;
  std::vector<GlObject> glObjects() const;

 private:
  GlBuffer buffer_;
  std::vector<uint32_t> offsets_;
};

}  // namespace svit::gl

#pragma once
// The bake's shadow masks (BakeShadowMasks) as GL textures: per lightmap
// page one GL_RGBA16UI array of the masks' layers, read with texelFetch
// (an owner and a visibility per channel: not filterable, so
// lit_static.frag filters them itself). Nothing is made for a bake
// without masks.

#include <cstdint>
#include <string>
#include <vector>

#include "gl_handle.h"
#include "gl_memory.h"
#include "svit/bake_file.h"
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

/// How much brighter a masked bake's surfaces are than its lightmap says
/// (the masked lights' direct light is not in the pages), for auto
/// exposure: the area-weighted log-mean irradiance over the static
/// triangles' centroids with the masked lights, over that without. 1 for a
/// bake without masks. Errors: unreadable pages, a bake of another level.
Expected<double> maskedExposureRatio(const Scene& scene, const BakeData& bake,
                                     const std::string& bake_dir);

}  // namespace svit::gl

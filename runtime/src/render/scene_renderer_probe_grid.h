#pragma once
// The bake's L1 SH irradiance probe grid as three RGBA32F 3D textures (one
// per colour channel; rgba = Y00, Y1-1, Y10, Y11), sampled trilinearly by
// lit_dynamic.frag for the indirect light of dynamic objects.

#include <cstdint>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/bake_file.h"
#include "svit/status.h"

namespace svit::gl {

class ProbeGridTextures {
 public:
  /// Uploads `grid`; allocates nothing for an empty grid. Error: sh holds
  /// fewer than 12 floats per probe.
  static Expected<ProbeGridTextures> create(const BakeProbeGrid& grid);
  ProbeGridTextures() = default;
  ProbeGridTextures(ProbeGridTextures&& other) noexcept;
  ProbeGridTextures& operator=(ProbeGridTextures&& other) noexcept;
  ProbeGridTextures(const ProbeGridTextures&) = delete;
  ProbeGridTextures& operator=(const ProbeGridTextures&) = delete;
  ~ProbeGridTextures();

  bool empty() const { return !textures_[0]; }
  /// Binds the textures and sets the grid uniforms of the current program
  /// (kProbeOrigin..kUseProbes of scene_renderer_bindings.h).
  void bind() const;

  std::vector<GlObject> glObjects() const {
    return {glTextureObject(textures_[0].id()), glTextureObject(textures_[1].id()),
            glTextureObject(textures_[2].id())};
  }

 private:
  GlTexture textures_[3];  ///< the SH coefficients of R, G, B
  BakeProbeGrid layout_;   ///< origin, spacing, dims (sh left empty)
};

}  // namespace svit::gl

#pragma once
// The bake's lightmap pages as GL textures for the SceneRenderer, and the
// irradiance level that auto exposure keys on.

#include <cstdint>
#include <string>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/bake_file.h"
#include "svit/status.h"

namespace svit::gl {

class LightmapTextures {
 public:
  /// Reads every page of `bake` from `bake_dir` and uploads it as a
  /// GL_RGB32F texture (bilinear, clamp to edge: the baker dilates charts
  /// for exactly that filter; no mipmaps, which would bleed across charts).
  /// Errors name the file: unreadable or missing page, a page whose size
  /// differs from the bake's record of it.
  static Expected<LightmapTextures> create(const BakeData& bake, const std::string& bake_dir);
  /// Borrows textures that already hold the bake's pages (the runtime's
  /// ShadingResources::lightmap_textures, one per page, bake order) instead
  /// of a second copy; reads them back once for the auto-exposure level.
  /// They must outlive this object. Error: not one texture per page.
  static Expected<LightmapTextures> borrow(const BakeData& bake,
                                           const std::vector<uint32_t>& textures);
  LightmapTextures() = default;
  LightmapTextures(LightmapTextures&& other) noexcept;
  LightmapTextures& operator=(LightmapTextures&& other) noexcept;
  LightmapTextures(const LightmapTextures&) = delete;
  LightmapTextures& operator=(const LightmapTextures&) = delete;
  ~LightmapTextures();

  uint32_t texture(uint32_t page) const { return textures_[page]; }
  size_t pageCount() const { return textures_.size(); }
  /// Log-average luminance (lux) of the covered texels (Y > 0): the
  /// irradiance a "typical" surface receives, robust to the few texels
  /// beside a lamp. 0 when no texel is lit.
  double logMeanIrradiance() const { return log_mean_lux_; }

  /// Its textures when it owns them (borrowed ones belong to the runtime).
  std::vector<GlObject> glObjects() const;
  bool borrowed() const { return !owned_; }

 private:
  std::vector<uint32_t> textures_;         ///< per page, owned or borrowed
  std::vector<GlTexture> owned_textures_;  ///< the same names when owned; empty when borrowed
  bool owned_ = true;
  double log_mean_lux_ = 0;
};

}  // namespace svit::gl

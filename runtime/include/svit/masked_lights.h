#pragma once
// The direct light of a bake's masked lights (BakeData::masks) at a static
// surface point, computed as shaders/lit_static.frag shades it: the light's
// unshadowed irradiance there x its shadow mask, read bilinearly from the
// lightmap texels around the point (a texel another light of the channel
// owns reads as 0). The lightmap of such a bake leaves that light out, so
// whatever reads lightmap irradiance (svit-probe, the runtime's patch
// baselines, Runtime::irradianceAt) adds this to it.

#include <cstdint>
#include <memory>
#include <vector>

#include "svit/bake_file.h"
#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

class MaskedLightField {
 public:
  /// The masked lights of `bake` with their parameters from `scene` (the
  /// sun as a directional light). Errors name the bake emitter that is not
  /// a light of the level. An empty field when the bake masks nothing.
  /// The field shares a copy of the masks, so it may outlive `bake`.
  static Expected<MaskedLightField> create(const Scene& scene, const BakeData& bake);
  MaskedLightField() = default;

  size_t lightCount() const { return lights_.size(); }
  bool empty() const { return lights_.empty(); }
  /// Light k as the shader lights it (the sun: a directional light named "sun").
  const Light& light(size_t k) const { return lights_[k]; }
  /// Its BakeData::emitters index.
  uint32_t emitter(size_t k) const { return emitters_[k]; }
  const BakeShadowMasks& masks() const { return *masks_; }

  /// Light k's irradiance (lux) at `p` on a surface of unit normal `n`
  /// with nothing in the way: inverse square, Lambert cosine, the glTF
  /// spot cone as t^2 between its cosines, no range cut-off.
  Rgb unshadowed(size_t k, const Vec3& p, const Vec3& n) const;
  /// Light k's static visibility at lightmap page `page`, coordinates `uv`
  /// (texel centres at (i + 0.5) / size, clamped at the page's edges): 0..1.
  float visibility(size_t k, uint32_t page, const Vec2& uv) const;
  /// Every masked light's direct light at `p` (unit normal `n`, lightmap
  /// `page` and `uv`) as baked: the sum of unshadowed x visibility, lux.
  Rgb bakedIrradiance(const Vec3& p, const Vec3& n, uint32_t page, const Vec2& uv) const;
  /// Direction from `p` towards light k (unit).
  Vec3 towardLight(size_t k, const Vec3& p) const;
  /// Distance from `p` to light k (metres; infinity for directional lights).
  float distanceToLight(size_t k, const Vec3& p) const;

 private:
  std::vector<Light> lights_;
  std::vector<uint32_t> emitters_;
  std::shared_ptr<const BakeShadowMasks> masks_;
  std::vector<uint32_t> page_width_, page_height_;
};

}  // namespace svit

#pragma once
// The direct light of a bake's masked lights (BakeData::masks) at a static
// surface point, computed as shaders/lit_static.frag shades it: the light's
// unshadowed irradiance there x its shadow mask, read bilinearly from the
// lightmap texels around the point (a texel another light of the channel
// owns reads as 0). The lightmap of such a bake leaves that light out, so
// whatever reads lightmap irradiance (svit-probe, the runtime's patch
// baselines, Runtime::irradianceAt) adds this to it. A lamp's emissive
// patch is an area light: its unshadowed irradiance is exact (Lambert's
// polygon formula over its triangles), and the dynamic objects' shadow is
// the weighted share of a few point samples of it they do not hide.

#include <cstdint>
#include <memory>
#include <vector>

#include "svit/bake_file.h"
#include "svit/baked_surfaces.h"
#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit {

/// One emitting triangle side of a masked area light.
struct MaskedAreaElement {
  Vec3 corner[3];  ///< world metres, wound so that the emitting side is the front
  Vec3 normal;     ///< unit, of the emitting side
  float area_m2 = 0;
  Rgb luminance;  ///< cd/m2
};

/// A point of an area light the dynamic objects' shadow is tested from.
struct MaskedAreaSample {
  Vec3 point;
  Vec3 normal;  ///< its element's
};

/// Point samples of an area light for the dynamic objects' shadow: the
/// solid angle the light subtends at the casters over this, rounded up,
/// 1..kMaxAreaSamples (a far lamp casts as a point; a near one needs its
/// penumbra resolved). Tuned on the Cornell lamp, whose two patches each
/// subtend about 0.05 sr at the moved tall box: 12 samples a patch, where
/// the picture error against the reference stops falling
/// (RuntimePicture.AreaLampShadowOfTheMovedBoxIsPerPixel;
/// docs/bench/runtime_picture.md).
inline constexpr double kAreaSampleSolidAngleSr = 0.004;
inline constexpr uint32_t kMaxAreaSamples = 16;

class MaskedLightField {
 public:
  /// The masked lights of `bake` with their parameters from `scene` (the
  /// sun as a directional light). Errors name the bake emitter that is not
  /// a light of the level. An empty field when the bake masks nothing.
  /// A lamp's patch (kPatch emitter) takes its emissive triangle sides
  /// from `surfaces` (BakedSurfaces::build of the same scene and bake);
  /// an error names a patch with none. The field shares a copy of the
  /// masks, so it may outlive `bake`.
  static Expected<MaskedLightField> create(const Scene& scene, const BakeData& bake,
                                           const BakedSurfaces& surfaces);
  MaskedLightField() = default;

  size_t lightCount() const { return lights_.size(); }
  bool empty() const { return lights_.empty(); }
  /// Light k as the shader lights it (the sun: a directional light named
  /// "sun"; an area light: a point light at its centre, named after its patch).
  const Light& light(size_t k) const { return lights_[k]; }
  bool isArea(size_t k) const { return !areas_[k].empty(); }
  /// An area light's emitting triangle sides (empty for the others).
  const std::vector<MaskedAreaElement>& areaElements(size_t k) const { return areas_[k]; }
  /// How many point samples area light k needs for casters around `at`.
  uint32_t areaSampleCount(size_t k, const Vec3& at) const;
  /// `count` points stratified over area light k by area; deterministic.
  std::vector<MaskedAreaSample> areaSamples(size_t k, uint32_t count) const;
  /// Its BakeData::emitters index.
  uint32_t emitter(size_t k) const { return emitters_[k]; }
  const BakeShadowMasks& masks() const { return *masks_; }

  /// Light k's irradiance (lux) at `p` on a surface of unit normal `n`
  /// with nothing in the way: inverse square, Lambert cosine, the glTF
  /// spot cone as t^2 between its cosines, no range cut-off; an area
  /// light's luminance x the cosine-weighted solid angle of the elements
  /// whose emitting side `p` is in front of.
  Rgb unshadowed(size_t k, const Vec3& p, const Vec3& n) const;
  /// Light k's static visibility at lightmap page `page`, coordinates `uv`
  /// (texel centres at (i + 0.5) / size, clamped at the page's edges): 0..1.
  float visibility(size_t k, uint32_t page, const Vec2& uv) const;
  /// Every masked light's direct light at `p` (unit normal `n`, lightmap
  /// `page` and `uv`) as baked: the sum of unshadowed x visibility, lux.
  Rgb bakedIrradiance(const Vec3& p, const Vec3& n, uint32_t page, const Vec2& uv) const;
  /// Direction from `p` towards light k (unit; an area light's centre).
  Vec3 towardLight(size_t k, const Vec3& p) const;
  /// Distance from `p` to light k (metres; infinity for directional lights).
  float distanceToLight(size_t k, const Vec3& p) const;

 private:
  std::vector<Light> lights_;
  std::vector<std::vector<MaskedAreaElement>> areas_;  ///< per light; empty unless an area
  std::vector<uint32_t> emitters_;
  std::shared_ptr<const BakeShadowMasks> masks_;
  std::vector<uint32_t> page_width_, page_height_;
};

}  // namespace svit

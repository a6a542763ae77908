#pragma once
// The baked light sources that are not surfaces: point and spot lights
// (candela), directional lights and the sun (lux, the sun with an angular
// radius), and the sky (cd/m2 at infinity). Each knows its flux entering the
// scene and samples rays whose luminous flux is equal; sun and sky shoot
// from a disk that encloses the scene (docs/architecture/baker-radiosity.md
// "Light sources").

#include <vector>

#include <glm/glm.hpp>

#include "svit/baker/bake_geometry.h"
#include "svit/scene.h"
#include "svit/status.h"
#include "util/random.h"

namespace svit::baker {

enum class LightKind { kPoint, kSpot, kDirectional, kSky };

struct LightRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, -1.0, 0.0};  ///< unit
  glm::dvec3 colour{1.0};                ///< rgb per unit luminous flux: luminance(colour) = 1
};

class LightSource {
 public:
  LightKind kind = LightKind::kPoint;
  std::string name;
  glm::dvec3 flux_rgb{0.0};  ///< lm per channel entering the scene's enclosing disk or emitted
  double flux_y = 0;         ///< luminous flux, lm

  /// One ray of this source's emission distribution. Deterministic in `rng`.
  LightRay sample(Rng& rng) const;

  // Parameters (set by makeLightSources).
  glm::dvec3 position{0.0};
  glm::dvec3 direction{0.0, -1.0, 0.0};  ///< spot axis / directional travel
  double cos_inner = 1, cos_outer = 0;   ///< spot
  double cos_radius = 1;                 ///< sun disk: cos(angular radius)
  glm::dvec3 colour{1.0};                ///< normalised colour of point/spot/directional
  glm::dvec3 centre{0.0};                ///< scene's enclosing sphere
  double radius = 1;                     ///< of the sphere
  double disk_radius = 1;                ///< of the shooting disk (sun: widened for the cone)
  glm::dvec3 zenith{0.0}, horizon{0.0}, ground{0.0};  ///< sky luminance, cd/m2
  double upper_share = 1;  ///< sky: luminous share of the upper hemisphere
};

/// Builds the static (baked) light sources of `scene` around `geometry`'s
/// bounds: lights not marked dynamic, the sun and the sky. Errors name the
/// light and value (non-finite parameters reaching the baker).
Expected<std::vector<LightSource>> makeLightSources(const Scene& scene,
                                                    const BakeGeometry& geometry);

/// Whether anything the bake lights with emits: a static light, the sun or
/// the sky with flux (makeLightSources' sources), or a static emissive
/// triangle. False: every lightmap texel is 0. A scene makeLightSources
/// refuses counts as emitting (the bake reports that error itself).
bool emitsAnyLight(const Scene& scene, const BakeGeometry& geometry);

/// glTF KHR_lights_punctual spot falloff: t^2 with
/// t = clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1).
double spotFalloff(double cos_angle, double cos_inner, double cos_outer);

}  // namespace svit::baker

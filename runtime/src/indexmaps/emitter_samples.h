#pragma once
// Point samples of emitters (thesis 5.3 steps 1-2, 5.4): a light is its own
// point; the sun and the sky become parallel samples through a window over
// the scene; a patch becomes points stratified over its surface, each with
// the patch's normal and a cosine lobe. Counts follow flux (the caller).

#include <cstdint>
#include <vector>

#include "index_map_renderer.h"
#include "svit/scene.h"

namespace svit::gl {

/// Where parallel light enters: a square window perpendicular to the
/// direction, covering the bounding sphere of the static scene.
struct ParallelWindow {
  Vec3 centre;     ///< of the scene's bounding sphere
  float radius_m;  ///< of that sphere (> 0)
};

/// Samples of a point or spot light; `roll_seed` varies the map frames.
/// Weights sum to 1.
std::vector<PointSample> lightSamples(const Light& light, int count, uint64_t seed, uint64_t stream,
                                      bool jitter_roll);

/// Spot profile the maps use (glTF's smooth falloff as the baker has it):
/// t^2, t = clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1).
/// Its integral over the sphere (sr), for a light's flux = I x that.
double lightLobeSolidAngle(const Light& light);

/// Sun samples: `count` directions spread over the sun's disk, parallel
/// through `window`; weights sum to 1. Flux of the sun = E x (2 r)^2.
std::vector<PointSample> sunSamples(const Sun& sun, const ParallelWindow& window, int count,
                                    uint64_t seed, bool jitter_roll);

/// Sky samples: `count` (>= 4) directions stratified over the upper
/// hemisphere (and the lower one when the gradient sky has a ground), each
/// weighted by its luminance x solid angle; weights sum to 1. `flux_out`
/// gets the sky's flux through the window (lm per channel).
std::vector<PointSample> skySamples(const Sky& sky, const ParallelWindow& window, int count,
                                    uint64_t seed, bool jitter_roll, Rgb& flux_out);

/// Samples stratified over the map triangles `triangles` (indices into
/// `map`) in proportion to area x `density` (per listed triangle; empty =
/// uniform), so samples sit where the light is (thesis 5.4). Each faces the
/// triangle's front side and is pushed `offset_m` off it; `own_triangle`
/// keeps it from lighting its own triangle. Weights sum to 1. Empty when
/// nothing has weight.
std::vector<PointSample> surfaceSamples(const MapTriangles& map, uint32_t triangle_base,
                                        const std::vector<uint32_t>& triangles,
                                        const std::vector<double>& density, int count,
                                        float offset_m, uint64_t seed, uint64_t stream,
                                        bool jitter_roll);

}  // namespace svit::gl

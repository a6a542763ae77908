#pragma once
// The runtime's patches: the bake's patches (cluster-tree nodes) cut down to
// a size that can carry a dynamic object's shadow. Each bake triangle side
// is tessellated into n x n sub-triangles no larger than the target area,
// and the sub-triangles of each bake patch are grouped by median splits
// into runtime patches of at most that area. A runtime patch's baseline is
// read from the lightmap under it (emission + albedo x baked irradiance), so
// deltas are taken against exactly what the game shows. The bake patch each
// runtime patch came from is its group: groups shoot as one emitter
// (hierarchical shooting, thesis 4.2), runtime patches receive.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "indexmaps/index_map_renderer.h"
#include "receivers.h"
#include "svit/bake_file.h"
#include "svit/baked_surfaces.h"
#include "svit/lightmap_image.h"
#include "svit/masked_lights.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::gl {

struct RuntimePatches {
  std::vector<Receiver> receivers;   ///< per runtime patch
  std::vector<glm::dvec3> baseline;  ///< per runtime patch: baked exitance B0, lm/m2
  std::vector<glm::dvec3> emission;  ///< per runtime patch: own exitance pi L, lm/m2
  /// per runtime patch: the masked lights' baked direct irradiance (lux),
  /// part of `baseline` but not of the lightmap
  std::vector<glm::dvec3> masked_direct;
  std::vector<glm::dvec3> lightmap_irradiance;  ///< per runtime patch: what its lightmap holds, lux
  std::vector<uint32_t> bake_patch;             ///< per runtime patch: the bake patch it came from
  std::vector<uint32_t> shooter;  ///< per runtime patch: the shooter group it belongs to
  std::vector<Aabb> bounds;       ///< per runtime patch
  std::vector<std::vector<uint32_t>> bake_members;     ///< per bake patch: its runtime patches
  std::vector<std::vector<uint32_t>> shooter_members;  ///< per shooter: its runtime patches
  std::vector<uint32_t> shooter_bake_patch;            ///< per shooter: its bake patch

  /// The sub-triangles, one side each, receiver = runtime patch: what index
  /// maps draw in full-geometry mode and what shading interpolates over.
  MapTriangles triangles;
  std::vector<uint32_t> triangle_vertices;  ///< 3 per sub-triangle: welded vertex ids
  uint32_t vertex_count = 0;
  std::vector<uint32_t> triangle_page;  ///< per sub-triangle: lightmap page
  std::vector<Vec2> triangle_uvs;       ///< 3 per sub-triangle: lightmap coordinates

  /// Per bake element (triangle * 2 + side): tessellation n (0 = not a
  /// patch element) and where its n*n*2 sub-triangle slots start.
  std::vector<uint16_t> element_n;
  std::vector<uint32_t> element_first_slot;
  std::vector<uint32_t> slots;  ///< sub-triangle index or kNoReceiver (unused slot)

  /// The sub-triangle under barycentrics (w1, w2) of bake element `element`,
  /// with the barycentrics inside it; kNoReceiver when the element has none.
  uint32_t subTriangle(uint32_t element, float w1, float w2, float& s1, float& s2) const;
};

/// Builds the runtime patches (each at most `max_area_m2`) and the shooters
/// (groups of them within a bake patch, each at most `max_shooter_area_m2`).
/// Errors name the bake element that is out of range.
Expected<RuntimePatches> buildRuntimePatches(const Scene& scene, const BakeData& bake,
                                             const BakedSurfaces& surfaces,
                                             const std::vector<LightmapImage>& pages,
                                             const MaskedLightField& masked, double max_area_m2,
                                             double max_shooter_area_m2);

/// A bake patch's proxy is used when it takes fewer than this share of the
/// patch's own sub-triangles and its area is within these bounds of the
/// patch's (proxyMapTriangles).
inline constexpr double kProxyShare = 0.5;
inline constexpr double kProxyCoverage[2] = {0.8, 1.25};

/// What index maps draw for the static level with LOD proxies: per bake
/// patch, its proxy faces tessellated to a quarter of a patch (each piece
/// standing for the nearest runtime patch of that bake patch) where that is
/// under kProxyShare of the patch's own sub-triangles and covers its area
/// (kProxyCoverage), else those sub-triangles unchanged. Ordered by bake
/// patch.
MapTriangles proxyMapTriangles(const BakeData& bake, const RuntimePatches& patches,
                               double max_area_m2);

/// Per welded vertex: area-weighted mean of the values of the runtime
/// patches around it (what shading interpolates between).
std::vector<glm::dvec3> vertexValues(const RuntimePatches& patches,
                                     const std::vector<glm::dvec3>& per_patch);

}  // namespace svit::gl

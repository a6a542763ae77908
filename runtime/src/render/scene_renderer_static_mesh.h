#pragma once
// The static geometry as the SceneRenderer draws it: the bake's static
// triangles (BakeData::triangle_uvs order) in world space with their
// lightmap UVs, grouped into draw batches by (material, lightmap page, bake
// emitter of an emissive patch), each corner naming its bake elements so
// the fragment shader can look the runtime's delta up per runtime patch
// (shaders/svit_runtime_delta.frag). CPU only (no GL): built once at
// SceneRenderer::create.

#include <cstdint>
#include <vector>

#include "svit/bake_file.h"
#include "svit/math_types.h"
#include "svit/scene.h"
#include "svit/status.h"

namespace svit::gl {

/// One corner of a static triangle (3 per triangle, unshared: lightmap UVs
/// belong to the triangle's chart). Layout read by lit_static.vert.
struct StaticVertex {
  float position[3];     ///< world, metres
  float normal[3];       ///< world, unit, shading normal on the front (CCW) side
  float uv0[2];          ///< TEXCOORD_0 (0 when the mesh has none)
  float uv1[2];          ///< TEXCOORD_1 (0 when the mesh has none)
  float uv_lightmap[2];  ///< page coordinates, v down the rows
  /// Bake element (triangle * 2 + side) of the front and of the back side:
  /// where svit_runtime_delta.frag finds the runtime's delta.
  uint32_t delta_element[2];
};
static_assert(sizeof(StaticVertex) == 56, "lit_static.vert reads this layout");

/// StaticBatch::emitter of triangles that belong to no emitting patch.
inline constexpr uint32_t kNoBakeEmitter = 0xffffffffu;

/// Which sides of its triangles a batch draws. A double-sided triangle with
/// a back lightmap of its own (BakeData::back_uvs) is drawn twice, its front
/// with the front's texels, back faces culled, and its back with the back's,
/// front faces culled; every other triangle once, both sides.
enum class DrawnSides : uint8_t { kBoth, kFront, kBack };

/// Consecutive vertices sharing drawn sides, a material, a lightmap page and
/// a bake emitter.
struct StaticBatch {
  DrawnSides sides = DrawnSides::kBoth;
  uint32_t material = 0;  ///< Scene::materials index
  uint32_t page = 0;      ///< BakeData::pages index
  /// BakeData::emitters index of the kPatch emitter whose patch holds the
  /// drawn side of the triangles (for kBoth their front; the back where only
  /// it emits), when the material emits; else kNoBakeEmitter. The renderer
  /// scales their drawn emission by that emitter's scale.
  uint32_t emitter = kNoBakeEmitter;
  uint32_t first_vertex = 0;
  uint32_t vertex_count = 0;
};

struct StaticMesh {
  std::vector<StaticVertex> vertices;  ///< sorted by batch
  std::vector<StaticBatch> batches;
  Aabb bounds;  ///< world, of all static triangles
};

/// Builds the static mesh of `scene` as `bake` lit it. Errors name the
/// bake element: the bake's static triangle count
/// differs from the level's (another level or version), an instance, mesh
/// triangle or page out of range, a dynamic instance in the list, a patch
/// element out of range.
Expected<StaticMesh> buildStaticMesh(const Scene& scene, const BakeData& bake);

/// The level's static triangles of positive world area, counted the way the
/// baker counts them (baker/src/rays/bake_geometry.cpp): what
/// BakeData::triangle_uvs must list.
size_t countBakeableStaticTriangles(const Scene& scene);

}  // namespace svit::gl

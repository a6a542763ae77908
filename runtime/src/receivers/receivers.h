#pragma once
// The runtime's receivers: the runtime patches (ids 0..P-1, runtime_patches.h)
// and one receiver per triangle of each dynamic object (a range per object:
// appended, or one a removed object gave back, Runtime::Impl::takeReceivers),
// with the triangles index maps draw for them.

#include <cstdint>
#include <vector>

#include "indexmaps/index_map_renderer.h"
#include "svit/math_types.h"
#include "svit/runtime.h"
#include "svit/status.h"

namespace svit::gl {

struct Receiver {
  float area_m2 = 0;
  Rgb albedo;
  Vec3 centroid;
  Vec3 normal;
  /// Takes its share of the ambient (unshot flux, thesis 5.5): the level's
  /// patches and objects that overlap the level's box. An object far
  /// outside receives no light at all, so it takes none of the ambient
  /// either, and adding it changes nothing in the level.
  bool shares_ambient = true;
};

/// A dynamic object as the runtime tracks it.
struct DynamicObject {
  std::string name;
  int instance = -1;
  std::vector<Vec3> object_positions;  ///< 3 per triangle, object space (unshared)
  std::vector<Rgb> albedo;             ///< per triangle
  std::vector<Rgb> emission;           ///< per triangle, cd/m2
  /// per triangle: dominant axis of its object-space normal, 0..5
  std::vector<uint8_t> shooter_bin;
  /// Per triangle: the first triangle of its flat face (coplanar ones show
  /// one averaged delta); itself on meshes over kMaxFlatFaceTriangles.
  std::vector<uint32_t> flat_face;
  /// Per triangle: the first triangle with the same corners in the same
  /// winding (itself when none). A mesh that repeats a face (as the Cornell
  /// box's tall box does) would split an index map's texels between the
  /// copies; a copy's texels go to the first one instead, and the copy
  /// shows its value with no area of its own.
  std::vector<uint32_t> same_as;
  bool double_sided = false;
  Mat4 world_from_object;
  bool visible = true;
  bool removed = false;
  /// The emitters reaching it that carry all but 5 % of its light have had
  /// their shares rendered since it appeared (Runtime::Impl::updateObjectsLit):
  /// until then shading shows it by the probe grid, not by a partial sum.
  bool lit = false;
  uint64_t shown_revision = 0;        ///< Impl::shares_revisions when it was added or shown
  uint32_t first_receiver = 0;        ///< its triangles' receivers are first_receiver + t
  std::vector<Vec3> world_positions;  ///< 3 per triangle, kept current
  Aabb bounds;                        ///< of world_positions (empty when hidden)
};

/// Fills shooter_bin, flat_face and same_as from object_positions.
void binObjectTriangles(DynamicObject& object);

/// Meshes with more triangles keep a delta per triangle (grouping is
/// quadratic, once per object).
inline constexpr size_t kMaxFlatFaceTriangles = 512;

/// Recomputes world_positions and bounds of `object` from its transform.
void placeObject(DynamicObject& object);

/// Appends the map triangles of every visible, not removed object.
MapTriangles dynamicMapTriangles(const std::vector<DynamicObject>& objects);

/// The receiver entries (area, albedo, centroid, normal, shares_ambient
/// against `level_box`) of an object's triangles, written at
/// object.first_receiver.
void updateObjectReceivers(const DynamicObject& object, const Aabb& level_box,
                           std::vector<Receiver>& receivers);

}  // namespace svit::gl

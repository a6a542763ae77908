#pragma once
// Dynamic objects as the SceneRenderer draws them: every frame, the
// runtime's objects where it has them now (or, without a runtime, the
// level's dynamic instances where the level puts them), one vertex buffer
// for all, re-uploaded only when something moved.

#include <cstdint>
#include <vector>

#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "svit/math_types.h"
#include "svit/runtime.h"
#include "svit/scene.h"

namespace svit::gl {

/// A dynamic triangle corner as lit_dynamic.vert reads it.
struct DynamicVertex {
  float position[3];      ///< world, metres
  float normal[3];        ///< world, unit, front side
  float albedo[3];        ///< diffuse reflectance (the triangle's mean)
  float emission[3];      ///< luminance, cd/m2
  float centroid[3];      ///< the triangle's, world metres (where the runtime's value applies)
  float face_normal[3];   ///< the triangle's, world, unit
  uint32_t patch;         ///< its patch in the runtime's delta buffer, or 0xffffffff
  uint32_t double_sided;  ///< 1: lit and emitting on both sides
};
static_assert(sizeof(DynamicVertex) == 80, "lit_dynamic.vert reads this layout");

inline constexpr uint32_t kNoDynamicPatch = 0xffffffffu;

class DynamicObjectMeshes {
 public:
  DynamicObjectMeshes() = default;
  DynamicObjectMeshes(DynamicObjectMeshes&& other) noexcept;
  DynamicObjectMeshes& operator=(DynamicObjectMeshes&& other) noexcept;
  DynamicObjectMeshes(const DynamicObjectMeshes&) = delete;
  DynamicObjectMeshes& operator=(const DynamicObjectMeshes&) = delete;
  ~DynamicObjectMeshes();

  /// Gathers the visible dynamic triangles (from `runtime` when not null,
  /// else the scene's dynamic instances) and uploads them when they differ
  /// from the last call. Returns true when they differ. Allocates GL storage
  /// only when the triangle count exceeds every earlier one.
  bool update(const Scene& scene, const Runtime* runtime);

  uint32_t vertexCount() const { return uint32_t(vertices_.size()); }
  const Aabb& bounds() const { return bounds_; }
  /// After update(): the boxes of the objects whose triangles changed, where
  /// they were and where they are (all of them when objects came or went):
  /// what a shadow map must be tested against.
  const std::vector<Aabb>& movedBoxes() const { return moved_boxes_; }
  /// Draws the triangles (attributes 0..6 per DynamicVertex); no-op when empty.
  void draw() const;

  std::vector<GlObject> glObjects() const { return {glBufferObject(buffer_.id())}; }
  uint64_t hostBytes() const { return uint64_t(vertices_.capacity()) * sizeof(DynamicVertex); }

 private:
  void release();
  struct ObjectSpan {
    uint64_t hash = 0;  ///< of its vertices
    Aabb bounds;
  };
  /// update()'s stages: the triangles into vertices_ and bounds_, one span
  /// per object; the boxes of the objects that differ from objects_; the
  /// vertices into the buffer (grown when they do not fit).
  std::vector<ObjectSpan> gatherVertices(const Scene& scene, const Runtime* runtime);
  void findMovedBoxes(const std::vector<ObjectSpan>& objects);
  void upload();
  std::vector<DynamicVertex> vertices_;
  std::vector<ObjectSpan> objects_;  ///< per drawn object, in draw order
  std::vector<Aabb> moved_boxes_;
  uint64_t hash_ = 0;
  bool uploaded_ = false;
  Aabb bounds_;
  GlVertexArray vao_;
  GlBuffer buffer_;
  size_t capacity_ = 0;  ///< vertices the buffer holds
};

}  // namespace svit::gl

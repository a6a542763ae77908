#pragma once
// Nearest triangle side to a point, among one object's sides, by Embree's
// closest-point query (rtcPointQuery over a BVH of the sides): the proxy
// builder's face-to-patch mapping (proxy_builder.cpp), O(log F) per query
// where a scan is O(F).

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "embree_handles.h"
#include "svit/baker/bake_geometry.h"
#include "svit/status.h"

namespace svit::baker {

/// Squared distance from `p` to the nearest point of triangle (a, b, c).
double distance2ToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                           const glm::dvec3& c);

/// A triangle side a query may return: the triangle and the way it faces.
struct TriangleSide {
  uint32_t triangle;  // BakeGeometry triangle
  glm::dvec3 normal;  // of the side
};

class NearestSideIndex {
 public:
  /// A BVH over `sides` (triangles of `geometry`) on `device`. Both must
  /// outlive the index. Errors: kInternal (Embree's message).
  static Expected<NearestSideIndex> build(RTCDevice device, const BakeGeometry& geometry,
                                          const std::vector<TriangleSide>& sides);

  /// Index into `sides` of the side nearest to `p` whose normal has a
  /// positive dot product with `n` (any side when `any_side`); -1 when none
  /// qualifies. Ties go to the lowest index, whatever the traversal order,
  /// so the answer is deterministic. Thread-safe.
  int32_t nearest(const glm::dvec3& p, const glm::dvec3& n, bool any_side) const;

 private:
  const BakeGeometry* geometry_ = nullptr;
  const std::vector<TriangleSide>* sides_ = nullptr;
  EmbreeScene scene_;
};

}  // namespace svit::baker

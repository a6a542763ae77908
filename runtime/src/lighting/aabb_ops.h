#pragma once
// Box tests of the runtime's reach tracking: which emitters a moved object
// may change (an emitter's region is the box of its samples and of
// everything its shares light).

#include <algorithm>

#include "svit/math_types.h"

namespace svit::gl {

inline bool overlaps(const Aabb& a, const Aabb& b) {
  return !a.empty() && !b.empty() && a.min.x <= b.max.x && b.min.x <= a.max.x &&
         a.min.y <= b.max.y && b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
}

inline void grow(Aabb& box, const Vec3& p) {
  box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
  box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
}

inline void grow(Aabb& box, const Aabb& other) {
  if (other.empty()) return;
  grow(box, other.min);
  grow(box, other.max);
}

}  // namespace svit::gl

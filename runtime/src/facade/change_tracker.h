#pragma once
// What changed since the last update(): the boxes objects left and entered
// (the emitters reaching them go out of date), and whether geometry or
// lighting changed at all, so a frame with no change costs nothing.

#include <cstdint>
#include <vector>

#include "svit/math_types.h"

namespace svit::gl {

struct ChangeTracker {
  std::vector<Aabb> moved_boxes;  ///< each changed object's box before and after
  bool dynamic_geometry_changed = false;
  bool lighting_changed = false;
  bool pending_wanted = false;  ///< the last bounce wanted shares it did not have
  uint64_t frame = 0;           ///< update() calls so far

  /// An object occupied `box` before or after a change (empty: nothing).
  void noteBox(const Aabb& box) {
    if (!box.empty()) moved_boxes.push_back(box);
  }
  bool anythingChanged() const {
    return dynamic_geometry_changed || lighting_changed || pending_wanted;
  }
};

}  // namespace svit::gl

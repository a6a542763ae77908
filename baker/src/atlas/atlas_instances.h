#pragma once
// The static instances of a BakeGeometry as triangle ranges, shared by the
// authored-UV and the xatlas paths of buildLightmapAtlas.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "svit/baker/bake_geometry.h"
#include "svit/scene.h"

namespace svit::baker {

/// Static triangles of one instance: BakeGeometry keeps them contiguous.
struct InstanceRange {
  uint32_t instance = 0;
  size_t first = 0, end = 0;  ///< triangles [first, end) of BakeGeometry
};

/// The instances of `geometry` in its (instance) order.
inline std::vector<InstanceRange> instanceRanges(const BakeGeometry& geometry) {
  std::vector<InstanceRange> ranges;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    if (ranges.empty() || ranges.back().instance != geometry.instance[t])
      ranges.push_back({geometry.instance[t], t, t});
    ranges.back().end = t + 1;
  }
  return ranges;
}

/// `ranges` with each range of more than `max_triangles` cut into equal
/// consecutive pieces of at most that many (0: as they are). A mesh's
/// triangle order is mostly spatially coherent (strips, rings, the order
/// it was modelled in), so consecutive pieces are patches of its surface.
inline std::vector<InstanceRange> rangePieces(const std::vector<InstanceRange>& ranges,
                                              size_t max_triangles) {
  std::vector<InstanceRange> pieces;
  for (const InstanceRange& r : ranges) {
    const size_t n = r.end - r.first;
    const size_t count = max_triangles == 0 ? 1 : (n + max_triangles - 1) / max_triangles;
    for (size_t k = 0; k < count; ++k)
      pieces.push_back({r.instance, r.first + n * k / count, r.first + n * (k + 1) / count});
  }
  return pieces;
}

/// "level.gltf: instance 3 (mesh 'Crate')", for error messages.
inline std::string instanceLabel(const Scene& scene, uint32_t instance) {
  const Instance& in = scene.instances[instance];
  return scene.source_path + ": instance " + std::to_string(instance) + " (mesh '" +
         scene.meshes[size_t(in.mesh)].name + "')";
}

}  // namespace svit::baker

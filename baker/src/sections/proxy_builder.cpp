// LOD proxies of the static geometry (docs/architecture/baker-sections.md "LOD proxies"):
// the runtime renders its index shadow maps from these instead of the full
// meshes, so each proxy face names the patch it stands for. Each object is
// simplified on its own (quadric edge collapse, simplify_mesh.h) and every
// proxy face then takes the patch of the nearest original triangle side that
// faces its way (within 90 degrees), found by Embree's closest-point query
// (nearest_side_index.h).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "rays/nearest_side_index.h"
#include "runtime_sections_internal.h"
#include "simplify_mesh.h"
#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"

namespace svit::baker {
namespace {

// Objects this small are kept as they are: nothing worth collapsing.
constexpr size_t kKeepFaces = 4;
// Proxy faces mapped per parallel work item.
constexpr size_t kChunkFaces = 256;

// One instance's triangles welded by exact position (float bits),
// vertices numbered in first-seen order.
struct WeldedMesh {
  std::vector<glm::dvec3> positions;
  std::vector<uint32_t> indices;
  // position hash -> vertices (lookup only)
  std::unordered_map<uint64_t, std::vector<uint32_t>> weld;
};

void weldInstance(const BakeGeometry& geometry, size_t first, size_t last, WeldedMesh& mesh) {
  std::vector<glm::dvec3>& positions = mesh.positions;
  positions.clear();
  mesh.indices.clear();
  mesh.weld.clear();
  for (size_t t = first; t < last; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& q = geometry.corner(t, k);
      uint32_t bits[3];
      std::memcpy(bits, &q, sizeof bits);
      std::vector<uint32_t>& bucket = mesh.weld[hashIds(bits[0], bits[1], bits[2])];
      uint32_t vertex = uint32_t(positions.size());
      for (uint32_t v : bucket) {
        if (positions[v] == dvec(q)) vertex = v;
      }
      if (vertex == positions.size()) {
        bucket.push_back(vertex);
        positions.push_back(dvec(q));
      }
      mesh.indices.push_back(vertex);
    }
  }
}

// The instance's proxy: itself when small, else simplified to `ratio` of
// its faces. The library's collapse threshold is absolute (squared length
// units): the object is scaled to a unit diagonal so the result does not
// depend on its size or units, then scaled back. Rescales mesh.positions.
SimplifiedMesh simplifyInstance(WeldedMesh& mesh, size_t faces, double ratio) {
  SimplifiedMesh simplified;
  if (faces <= kKeepFaces) {
    simplified.positions = mesh.positions;
    simplified.indices = mesh.indices;
    return simplified;
  }
  std::vector<glm::dvec3>& positions = mesh.positions;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()),
      hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& q : positions) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double diagonal = glm::length(hi - lo);
  const double scale = diagonal > 0 ? 1.0 / diagonal : 1.0;
  for (glm::dvec3& q : positions) q = (q - centre) * scale;
  const size_t target = std::max<size_t>(1, size_t(std::llround(double(faces) * ratio)));
  simplified = simplifyMesh(positions, mesh.indices, target);
  for (glm::dvec3& q : simplified.positions) q = q / scale + centre;
  return simplified;
}

// Candidates: the instance's existing triangle sides that belong to a
// patch, and those patches.
struct Candidates {
  std::vector<TriangleSide> sides;
  std::vector<uint32_t> patches;
};

void collectCandidates(const BakeGeometry& geometry, const PatchSet& patches, size_t first,
                       size_t last, Candidates& candidates) {
  candidates.sides.clear();
  candidates.patches.clear();
  for (size_t t = first; t < last; ++t) {
    for (int side = 0; side < 2; ++side) {
      const int32_t patch = patches.element_patch[t * 2 + size_t(side)];
      if (patch < 0) continue;
      const glm::dvec3 n = dvec(geometry.normals[t]) * (side == 0 ? 1.0 : -1.0);
      candidates.sides.push_back({uint32_t(t), n});
      candidates.patches.push_back(uint32_t(patch));
    }
  }
}

// Appends the simplified faces to the proxy, each with the patch of the
// nearest original side facing its way.
Status appendProxyFaces(RTCDevice device, const BakeGeometry& geometry,
                        const Candidates& candidates, const SimplifiedMesh& simplified, int threads,
                        BakeProxyMesh& proxy) {
  Expected<NearestSideIndex> index = NearestSideIndex::build(device, geometry, candidates.sides);
  if (!index.ok()) return index.status();
  const size_t base_vertex = proxy.positions.size();
  const size_t base_face = proxy.face_patch.size();
  const size_t proxy_faces = simplified.indices.size() / 3;
  for (const glm::dvec3& q : simplified.positions) proxy.positions.push_back(vec3(q));
  for (uint32_t i : simplified.indices) proxy.indices.push_back(uint32_t(base_vertex + i));
  proxy.face_patch.resize(base_face + proxy_faces);
  parallelFor(proxy_faces, kChunkFaces, threads, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      const glm::dvec3 a = simplified.positions[simplified.indices[f * 3]];
      const glm::dvec3 b = simplified.positions[simplified.indices[f * 3 + 1]];
      const glm::dvec3 c = simplified.positions[simplified.indices[f * 3 + 2]];
      const glm::dvec3 centroid = (a + b + c) / 3.0;
      // unnormalised: only its sign against sides matters
      const glm::dvec3 n = glm::cross(b - a, c - a);
      int32_t side = index->nearest(centroid, n, false);
      // A face turned against every original side (a collapse fold, or a
      // zero-area face) still stands for the nearest surface.
      if (side < 0) side = index->nearest(centroid, n, true);
      proxy.face_patch[base_face + f] = side < 0 ? 0 : candidates.patches[size_t(side)];
    }
  });
  return Status::okStatus();
}

}  // namespace

Expected<BakeProxyMesh> buildProxy(const BakeGeometry& geometry, const PatchSet& patches,
                                   double ratio, int threads, const std::atomic<bool>* cancel) {
  const EmbreeDevice device(rtcNewDevice(nullptr));
  if (!device) return Status(StatusCode::kInternal, "runtime sections: rtcNewDevice failed");
  BakeProxyMesh proxy;
  const size_t triangles = geometry.triangleCount();
  WeldedMesh welded;
  Candidates candidates;
  for (size_t first = 0; first < triangles;) {
    if (cancel && cancel->load())
      return Status(StatusCode::kCancelled, "runtime sections: proxy cancelled");
    // Triangles of one instance are contiguous (BakeGeometry order).
    size_t last = first;
    while (last < triangles && geometry.instance[last] == geometry.instance[first]) ++last;
    weldInstance(geometry, first, last, welded);
    const SimplifiedMesh simplified = simplifyInstance(welded, last - first, ratio);
    collectCandidates(geometry, patches, first, last, candidates);
    const Status appended =
        appendProxyFaces(device.get(), geometry, candidates, simplified, threads, proxy);
    if (!appended.ok()) return appended;
    first = last;
  }
  return proxy;
}

}  // namespace svit::baker

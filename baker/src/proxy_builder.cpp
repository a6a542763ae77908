// LOD proxies of the static geometry (docs/architecture.md "Runtime: LOD proxies"):
// the runtime renders its index shadow maps from these instead of the full
// meshes, so each proxy face names the patch it stands for. Each object is
// simplified on its own (quadric edge collapse, simplify_mesh.h) and every
// proxy face then takes the patch of the nearest original triangle side that
// faces its way (within 90 degrees).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "double_math.h"
#include "parallel_for.h"
#include "random.h"
#include "runtime_sections_internal.h"
#include "simplify_mesh.h"

namespace svit::baker {
namespace {

// Objects this small are kept as they are: nothing worth collapsing.
constexpr size_t kKeepFaces = 4;
// Proxy faces mapped per parallel work item.
constexpr size_t kChunkFaces = 256;

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
// Detection, 5.1.5), as a squared distance.
double distance2ToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                           const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto d2to = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  if (d1 <= 0 && d2 <= 0) return d2to(a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return d2to(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return d2to(a + ab * (d1 / (d1 - d3)));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return d2to(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return d2to(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return d2to(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return d2to(a + ab * (vb * denom) + ac * (vc * denom));
}

// An original triangle side a proxy face may map to.
struct Candidate {
  uint32_t triangle;
  uint32_t patch;
  glm::dvec3 normal;  // of the side
  glm::dvec3 centre;  // bounding sphere
  double radius;
};

// The candidates ordered along the axis of their widest spread, so a query
// visits only those whose bounding sphere may lie within the best distance
// found so far (a sweep outwards from the query's place on that axis):
// O(F^1.5) per object on curved meshes where a scan of all is O(F^2).
struct CandidateSweep {
  int axis = 0;
  double max_radius = 0;
  std::vector<uint32_t> order;  // candidate indices by centre[axis]
  std::vector<double> keys;     // centre[axis] in that order

  explicit CandidateSweep(const std::vector<Candidate>& candidates) {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()),
        hi(-std::numeric_limits<double>::infinity());
    for (const Candidate& c : candidates) {
      lo = glm::min(lo, c.centre);
      hi = glm::max(hi, c.centre);
      max_radius = std::max(max_radius, c.radius);
    }
    const glm::dvec3 extent = hi - lo;
    axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    order.resize(candidates.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      return candidates[a].centre[axis] < candidates[b].centre[axis];
    });
    keys.resize(order.size());
    for (size_t i = 0; i < order.size(); ++i) keys[i] = candidates[order[i]].centre[axis];
  }
};

// Patch of the nearest candidate to `p` whose normal has dot > 0 with `n`
// (or of any candidate when `any_side`); -1 when none qualifies. Ties go to
// the earliest candidate, as a scan in candidate order would give them.
int32_t nearestPatch(const BakeGeometry& geometry, const std::vector<Candidate>& candidates,
                     const CandidateSweep& sweep, const glm::dvec3& p, const glm::dvec3& n,
                     bool any_side) {
  double best = std::numeric_limits<double>::infinity();
  uint32_t best_index = std::numeric_limits<uint32_t>::max();
  auto visit = [&](uint32_t index) {
    const Candidate& c = candidates[index];
    if (!any_side && !(glm::dot(c.normal, n) > 0)) return;
    // Bounding-sphere cut: a sphere farther than the best cannot be nearer.
    const double lower = std::max(0.0, glm::length(p - c.centre) - c.radius);
    if (lower * lower > best) return;
    const double d2 = distance2ToTriangle(p, dvec(geometry.corner(c.triangle, 0)),
                                          dvec(geometry.corner(c.triangle, 1)),
                                          dvec(geometry.corner(c.triangle, 2)));
    if (d2 < best || (d2 == best && index < best_index)) {
      best = d2;
      best_index = index;
    }
  };
  // Beyond this gap along the axis no sphere can come within `best`.
  auto outOfReach = [&](double key) {
    const double gap = std::abs(key - p[sweep.axis]) - sweep.max_radius;
    return gap > 0 && gap * gap > best;
  };
  const size_t start = size_t(
      std::lower_bound(sweep.keys.begin(), sweep.keys.end(), p[sweep.axis]) - sweep.keys.begin());
  size_t up = start, down = start;  // next to visit: up, and down - 1
  while (up < sweep.keys.size() || down > 0) {
    const bool up_open = up < sweep.keys.size() && !outOfReach(sweep.keys[up]);
    const bool down_open = down > 0 && !outOfReach(sweep.keys[down - 1]);
    if (!up_open && !down_open) break;
    // The nearer side first, so `best` shrinks early.
    const bool go_up = up_open && (!down_open || sweep.keys[up] - p[sweep.axis] <=
                                                     p[sweep.axis] - sweep.keys[down - 1]);
    if (go_up) {
      visit(sweep.order[up++]);
    } else {
      visit(sweep.order[--down]);
    }
  }
  return best_index == std::numeric_limits<uint32_t>::max() ? -1
                                                            : int32_t(candidates[best_index].patch);
}

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

// Candidates: the instance's existing triangle sides that belong to a patch.
void collectCandidates(const BakeGeometry& geometry, const PatchSet& patches, size_t first,
                       size_t last, std::vector<Candidate>& candidates) {
  candidates.clear();
  for (size_t t = first; t < last; ++t) {
    const glm::dvec3 a = dvec(geometry.corner(t, 0)), b = dvec(geometry.corner(t, 1)),
                     c = dvec(geometry.corner(t, 2));
    const glm::dvec3 centre = (a + b + c) / 3.0;
    const double radius =
        std::max({glm::length(a - centre), glm::length(b - centre), glm::length(c - centre)});
    for (int side = 0; side < 2; ++side) {
      const int32_t patch = patches.element_patch[t * 2 + size_t(side)];
      if (patch < 0) continue;
      const glm::dvec3 n = dvec(geometry.normals[t]) * (side == 0 ? 1.0 : -1.0);
      candidates.push_back({uint32_t(t), uint32_t(patch), n, centre, radius});
    }
  }
}

// Appends the simplified faces to the proxy, each with the patch of the
// nearest original side facing its way.
void appendProxyFaces(const BakeGeometry& geometry, const std::vector<Candidate>& candidates,
                      const SimplifiedMesh& simplified, int threads, BakeProxyMesh& proxy) {
  const size_t base_vertex = proxy.positions.size();
  const size_t base_face = proxy.face_patch.size();
  const size_t proxy_faces = simplified.indices.size() / 3;
  for (const glm::dvec3& q : simplified.positions) proxy.positions.push_back(vec3(q));
  for (uint32_t i : simplified.indices) proxy.indices.push_back(uint32_t(base_vertex + i));
  proxy.face_patch.resize(base_face + proxy_faces);
  const CandidateSweep sweep(candidates);
  parallelFor(proxy_faces, kChunkFaces, threads, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      const glm::dvec3 a = simplified.positions[simplified.indices[f * 3]];
      const glm::dvec3 b = simplified.positions[simplified.indices[f * 3 + 1]];
      const glm::dvec3 c = simplified.positions[simplified.indices[f * 3 + 2]];
      const glm::dvec3 centroid = (a + b + c) / 3.0;
      // unnormalised: only its sign against sides matters
      const glm::dvec3 n = glm::cross(b - a, c - a);
      int32_t patch = nearestPatch(geometry, candidates, sweep, centroid, n, false);
      // A face turned against every original side (a collapse fold, or a
      // zero-area face) still stands for the nearest surface.
      if (patch < 0) patch = nearestPatch(geometry, candidates, sweep, centroid, n, true);
      proxy.face_patch[base_face + f] = uint32_t(std::max(patch, 0));
    }
  });
}

}  // namespace

Expected<BakeProxyMesh> buildProxy(const BakeGeometry& geometry, const PatchSet& patches,
                                   double ratio, int threads, const std::atomic<bool>* cancel) {
  BakeProxyMesh proxy;
  const size_t triangles = geometry.triangleCount();
  WeldedMesh welded;
  std::vector<Candidate> candidates;
  for (size_t first = 0; first < triangles;) {
    if (cancel && cancel->load())
      return Status(StatusCode::kCancelled, "runtime sections: proxy cancelled");
    // Triangles of one instance are contiguous (BakeGeometry order).
    size_t last = first;
    while (last < triangles && geometry.instance[last] == geometry.instance[first]) ++last;
    weldInstance(geometry, first, last, welded);
    const SimplifiedMesh simplified = simplifyInstance(welded, last - first, ratio);
    collectCandidates(geometry, patches, first, last, candidates);
    appendProxyFaces(geometry, candidates, simplified, threads, proxy);
    first = last;
  }
  return proxy;
}

}  // namespace svit::baker

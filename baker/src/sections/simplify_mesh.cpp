// The one translation unit that includes fast-simplification's Simplify.h
// (third_party_notes/fast-simplification.md): it defines its globals and
// functions non-inline, so a second includer would not link, and it leaves a
// global min() and loopi/loopj/loopk macros behind. It is included last, as
// a SYSTEM header (its warnings are not ours), and used under one mutex.

#include "simplify_mesh.h"

#include <mutex>

// clang-format off
#include <Simplify.h>  // must stay the last include
// clang-format on

namespace svit::baker {

SimplifiedMesh simplifyMesh(const std::vector<glm::dvec3>& positions,
                            const std::vector<uint32_t>& indices, size_t target_faces) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  Simplify::vertices.clear();
  Simplify::triangles.clear();
  Simplify::refs.clear();
  Simplify::collapses.clear();
  Simplify::vertices.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    Simplify::Vertex& v = Simplify::vertices[i];
    v = Simplify::Vertex();
    v.p.x = positions[i].x;
    v.p.y = positions[i].y;
    v.p.z = positions[i].z;
  }
  Simplify::triangles.resize(indices.size() / 3);
  for (size_t t = 0; t < indices.size() / 3; ++t) {
    Simplify::Triangle& tri = Simplify::triangles[t];
    tri = Simplify::Triangle();
    for (int k = 0; k < 3; ++k) tri.v[k] = int(indices[t * 3 + size_t(k)]);
    tri.attr = 0;
    tri.material = 0;
  }
  Simplify::simplify_mesh(int(target_faces), 7.0, false, false);
  SimplifiedMesh out;
  out.positions.reserve(Simplify::vertices.size());
  for (const Simplify::Vertex& v : Simplify::vertices)
    out.positions.emplace_back(v.p.x, v.p.y, v.p.z);
  out.indices.reserve(Simplify::triangles.size() * 3);
  for (const Simplify::Triangle& tri : Simplify::triangles) {
    for (int k = 0; k < 3; ++k) out.indices.push_back(uint32_t(tri.v[k]));
  }
  // Release the library's memory until the next call.
  Simplify::vertices = {};
  Simplify::triangles = {};
  Simplify::refs = {};
  Simplify::collapses = {};
  return out;
}

}  // namespace svit::baker

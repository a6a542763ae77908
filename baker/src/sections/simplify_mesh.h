#pragma once
// Quadric-error edge-collapse simplification (Garland & Heckbert 1997) by
// fast-simplification's Simplify.h, behind a clean function: the header's
// global state, global min() and loop macros stay inside simplify_mesh.cpp.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace svit::baker {

struct SimplifiedMesh {
  std::vector<glm::dvec3> positions;
  std::vector<uint32_t> indices;  ///< 3 per face, into positions
};

/// Collapses edges of the indexed triangle mesh (`indices` 3 per face, into
/// `positions`; shared vertices are what lets edges collapse) until at most
/// `target_faces` faces remain or the library's 100 iterations run out (the
/// result may stay above the target). Its error threshold is absolute
/// (1e-9 * (iteration + 3)^7 in squared units of `positions`): callers
/// normalise the mesh to a unit size first. Unreferenced vertices are
/// dropped. Deterministic. Thread-safe: serialised by an internal mutex (the
/// library keeps global state).
SimplifiedMesh simplifyMesh(const std::vector<glm::dvec3>& positions,
                            const std::vector<uint32_t>& indices, size_t target_faces);

}  // namespace svit::baker

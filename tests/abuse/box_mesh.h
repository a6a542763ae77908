#pragma once
// A closed box of 12 outward, counter-clockwise triangles centred on the
// origin: the dynamic object the runtime tests, the abuse driver and the
// soak add.

#include <string>

#include "svit/runtime.h"

namespace svit::test {

inline DynamicMesh boxMesh(const std::string& name, float half) {
  DynamicMesh mesh;
  mesh.name = name;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back(
        {(i & 1) ? half : -half, (i & 2) ? half : -half, (i & 4) ? half : -half});
  }
  mesh.indices = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  return mesh;
}

}  // namespace svit::test

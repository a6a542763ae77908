#pragma once
// Bounds-checked reading of glTF accessors into plain arrays. tinygltf parses
// the JSON and loads buffers but does not check that accessors and buffer
// views stay inside their buffers; every read here does, so a malformed file
// gets an error naming the accessor instead of reading past the end.

#include <cstdint>
#include <string>
#include <vector>

#include "svit/status.h"

namespace tinygltf {
class Model;
}

namespace svit::gltf {

/// Reads accessor `accessor_index` as floats, `components` per element
/// (1 SCALAR, 2 VEC2, 3 VEC3, 4 VEC4), converting normalized integers per
/// the glTF spec and applying sparse substitution. `context` starts every
/// error message ("f.gltf: mesh 'A' primitive 0 attribute POSITION").
Status readFloats(const tinygltf::Model& model, int accessor_index, int components,
                  const std::string& context, std::vector<float>& out);

/// Reads an index accessor (unsigned byte, short or int, SCALAR).
Status readIndices(const tinygltf::Model& model, int accessor_index, const std::string& context,
                   std::vector<uint32_t>& out);

/// Number of elements of an accessor, or -1 when the index is out of range.
long accessorCount(const tinygltf::Model& model, int accessor_index);

}  // namespace svit::gltf

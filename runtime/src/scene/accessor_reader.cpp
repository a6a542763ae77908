#include "accessor_reader.h"

#include <algorithm>
#include <cstring>
#include <string_view>

#include <tiny_gltf.h>

namespace svit::gltf {
namespace {

int componentsOfType(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

int componentBytes(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

// One component as float; normalized integers map to [0,1] or [-1,1] exactly
// as glTF 2.0 section 3.11 ("Animations" / KHR_mesh_quantization) specifies.
float decodeComponent(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v = *p;
      return normalized ? float(v) / 255.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? float(v) / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return float(v);
    }
    default: return 0.0f;
  }
}

uint32_t decodeIndex(const unsigned char* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

Status invalid(const std::string& message) { return Status(StatusCode::kInvalidInput, message); }

// Elements of an accessor without a bufferView (zeros, perhaps with sparse
// values) are backed by no bytes of the file, so nothing else bounds their
// count: 2^24 (16.7 M vertices, 200 MB of VEC3) is above any mesh svit
// lights, and stops a count of 2^40 from allocating terabytes.
constexpr size_t kMaxUnbackedElements = size_t(1) << 24;

bool isIndexComponentType(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// A validated view of `count` elements of `element_bytes` each inside one
// buffer view: base pointer and stride.
struct ElementSpan {
  const unsigned char* base = nullptr;
  size_t stride = 0;
};

Status locateElements(const tinygltf::Model& model, int buffer_view_index, size_t byte_offset,
                      size_t count, size_t element_bytes, bool allow_stride,
                      const std::string& what, ElementSpan& span) {
  if (buffer_view_index < 0 || size_t(buffer_view_index) >= model.bufferViews.size()) {
    return invalid(what + ": bufferView " + std::to_string(buffer_view_index) +
                   " does not exist (file has " + std::to_string(model.bufferViews.size()) + ")");
  }
  if (element_bytes == 0)
    return invalid(what + ": elements of 0 bytes");  // callers check types first
  const tinygltf::BufferView& view = model.bufferViews[size_t(buffer_view_index)];
  const std::string view_name = "bufferView " + std::to_string(buffer_view_index);
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
    return invalid(what + ": " + view_name + ": buffer " + std::to_string(view.buffer) +
                   " does not exist");
  }
  const tinygltf::Buffer& buffer = model.buffers[size_t(view.buffer)];
  if (view.byteOffset > buffer.data.size() ||
      view.byteLength > buffer.data.size() - view.byteOffset) {
    return invalid(what + ": " + view_name + " bytes [" + std::to_string(view.byteOffset) + ", " +
                   std::to_string(view.byteOffset + view.byteLength) +
                   ") out of bounds of buffer " + std::to_string(view.buffer) + " (" +
                   std::to_string(buffer.data.size()) + " bytes)");
  }
  size_t stride = element_bytes;
  if (allow_stride && view.byteStride != 0) {
    if (view.byteStride < element_bytes) {
      return invalid(what + ": " + view_name + " byteStride " + std::to_string(view.byteStride) +
                     " < element size " + std::to_string(element_bytes));
    }
    stride = view.byteStride;
  }
  if (count > 0) {
    // Last byte read: offset + stride*(count-1) + element_bytes; checked
    // without overflow by dividing first.
    const size_t available = view.byteLength;
    const bool fits = byte_offset <= available && element_bytes <= available - byte_offset &&
                      (count - 1) <= (available - byte_offset - element_bytes) / stride;
    if (!fits) {
      return invalid(what + ": " + std::to_string(count) + " elements of " +
                     std::to_string(element_bytes) + " bytes (stride " + std::to_string(stride) +
                     ") from byte " + std::to_string(byte_offset) + " out of bounds of " +
                     view_name + " (" + std::to_string(view.byteLength) + " bytes)");
    }
  }
  span.base = buffer.data.data() + view.byteOffset + byte_offset;
  span.stride = stride;
  return Status();
}

Status checkAccessorIndex(const tinygltf::Model& model, int accessor_index,
                          const std::string& context) {
  if (accessor_index < 0 || size_t(accessor_index) >= model.accessors.size()) {
    return invalid(context + ": accessor " + std::to_string(accessor_index) +
                   " does not exist (file has " + std::to_string(model.accessors.size()) + ")");
  }
  return Status();
}

// The dense part of a float accessor: its bufferView's elements, or zeros
// when it has none. The count is bounded by the bytes behind it before
// anything is allocated for it.
Status readDenseFloats(const tinygltf::Model& model, const tinygltf::Accessor& accessor,
                       int components, int bytes, const std::string& what,
                       std::vector<float>& out) {
  const size_t count = accessor.count;
  ElementSpan span;
  if (accessor.bufferView >= 0) {
    if (Status s = locateElements(model, accessor.bufferView, accessor.byteOffset, count,
                                  size_t(bytes) * size_t(components), true, what, span);
        !s.ok()) {
      return s;
    }
  } else if (count > kMaxUnbackedElements) {
    return invalid(what + ": count " + std::to_string(count) + " without a bufferView exceeds " +
                   std::to_string(kMaxUnbackedElements));
  }
  out.assign(count * size_t(components), 0.0f);
  if (accessor.bufferView >= 0) {
    for (size_t i = 0; i < count; ++i) {
      const unsigned char* element = span.base + i * span.stride;
      for (int c = 0; c < components; ++c) {
        out[i * size_t(components) + size_t(c)] =
            decodeComponent(element + c * bytes, accessor.componentType, accessor.normalized);
      }
    }
  }
  return Status();
}

// glTF 2.0 3.6.2.3: sparse values replace the dense elements their indices name.
Status applySparseFloats(const tinygltf::Model& model, const tinygltf::Accessor& accessor,
                         int components, int bytes, const std::string& what,
                         std::vector<float>& out) {
  const size_t count = accessor.count;
  const auto& sparse = accessor.sparse;
  const size_t sparse_count = size_t(sparse.count);
  if (sparse.count < 0 || sparse_count > count) {
    return invalid(what + ": sparse count " + std::to_string(sparse.count) + " > count " +
                   std::to_string(count));
  }
  // Sparse indices are unsigned byte, short or int. An unknown type would
  // give 0-byte elements and a division by zero (found by fuzz_gltf and
  // fuzz_glb); decodeIndex would read a signed byte or short one as 4 bytes
  // of a 1- or 2-byte element.
  if (!isIndexComponentType(sparse.indices.componentType)) {
    return invalid(what + ": sparse indices componentType " +
                   std::to_string(sparse.indices.componentType) +
                   " is not unsigned byte, short or int");
  }
  const int index_bytes = componentBytes(sparse.indices.componentType);
  ElementSpan index_span, value_span;
  if (Status s = locateElements(model, sparse.indices.bufferView, size_t(sparse.indices.byteOffset),
                                sparse_count, size_t(index_bytes), false, what + " sparse indices",
                                index_span);
      !s.ok()) {
    return s;
  }
  if (Status s = locateElements(model, sparse.values.bufferView, size_t(sparse.values.byteOffset),
                                sparse_count, size_t(bytes) * size_t(components), false,
                                what + " sparse values", value_span);
      !s.ok()) {
    return s;
  }
  for (size_t i = 0; i < sparse_count; ++i) {
    const uint32_t target =
        decodeIndex(index_span.base + i * index_span.stride, sparse.indices.componentType);
    if (target >= count) {
      return invalid(what + ": sparse index " + std::to_string(target) + " >= count " +
                     std::to_string(count));
    }
    for (int c = 0; c < components; ++c) {
      out[size_t(target) * size_t(components) + size_t(c)] =
          decodeComponent(value_span.base + i * value_span.stride + c * bytes,
                          accessor.componentType, accessor.normalized);
    }
  }
  return Status();
}

}  // namespace

long accessorCount(const tinygltf::Model& model, int accessor_index) {
  if (accessor_index < 0 || size_t(accessor_index) >= model.accessors.size()) return -1;
  return long(model.accessors[size_t(accessor_index)].count);
}

Status readFloats(const tinygltf::Model& model, int accessor_index, int components,
                  const std::string& context, std::vector<float>& out) {
  if (Status s = checkAccessorIndex(model, accessor_index, context); !s.ok()) return s;
  const tinygltf::Accessor& accessor = model.accessors[size_t(accessor_index)];
  const std::string what = context + ": accessor " + std::to_string(accessor_index);
  const int type_components = componentsOfType(accessor.type);
  if (type_components != components) {
    return invalid(what + ": has " + std::to_string(type_components) + " components, expected " +
                   std::to_string(components));
  }
  const int bytes = componentBytes(accessor.componentType);
  if (bytes == 0) {
    return invalid(what + ": unknown componentType " + std::to_string(accessor.componentType));
  }
  if (Status s = readDenseFloats(model, accessor, components, bytes, what, out); !s.ok()) return s;
  if (!accessor.sparse.isSparse) return Status();
  return applySparseFloats(model, accessor, components, bytes, what, out);
}

Status readIndices(const tinygltf::Model& model, int accessor_index, const std::string& context,
                   std::vector<uint32_t>& out) {
  if (Status s = checkAccessorIndex(model, accessor_index, context); !s.ok()) return s;
  const tinygltf::Accessor& accessor = model.accessors[size_t(accessor_index)];
  const std::string what = context + ": accessor " + std::to_string(accessor_index);
  if (accessor.type != TINYGLTF_TYPE_SCALAR || !isIndexComponentType(accessor.componentType)) {
    return invalid(what + ": indices must be SCALAR unsigned byte/short/int");
  }
  if (accessor.sparse.isSparse) {
    return Status(StatusCode::kUnsupported, what + ": sparse index accessors are not supported");
  }
  if (accessor.bufferView < 0) {
    return invalid(what + ": index accessor without bufferView");
  }
  const int bytes = componentBytes(accessor.componentType);
  ElementSpan span;
  // Index buffer views must be tightly packed (glTF 2.0: byteStride not allowed).
  if (Status s = locateElements(model, accessor.bufferView, accessor.byteOffset, accessor.count,
                                size_t(bytes), false, what, span);
      !s.ok()) {
    return s;
  }
  out.resize(accessor.count);
  for (size_t i = 0; i < accessor.count; ++i) {
    out[i] = decodeIndex(span.base + i * size_t(bytes), accessor.componentType);
  }
  return Status();
}

}  // namespace svit::gltf

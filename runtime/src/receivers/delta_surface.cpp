#include "delta_surface.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <utility>

namespace svit::gl {
namespace {

// Per bake element: (n, first slot); n = 0 where the element has no
// sub-triangles (a single-sided triangle's back, or no patch).
std::vector<uint32_t> elementTable(const RuntimePatches& patches) {
  std::vector<uint32_t> table(patches.element_n.size() * 2);
  for (size_t e = 0; e < patches.element_n.size(); ++e) {
    table[e * 2] = patches.element_n[e];
    table[e * 2 + 1] = patches.element_first_slot[e];
  }
  return table;
}

// Per slot: the welded vertices of its sub-triangle (the fourth entry 1
// when the slot is used), so a lookup takes one read instead of two.
std::vector<uint32_t> slotTable(const RuntimePatches& patches) {
  std::vector<uint32_t> table(patches.slots.size() * 4, 0);
  for (size_t s = 0; s < patches.slots.size(); ++s) {
    const uint32_t sub = patches.slots[s];
    if (sub == kNoReceiver) continue;
    for (size_t k = 0; k < 3; ++k)
      table[s * 4 + k] = patches.triangle_vertices[size_t(sub) * 3 + k];
    table[s * 4 + 3] = 1;
  }
  return table;
}

GlBuffer immutableBuffer(const std::vector<uint32_t>& data) {
  // A zero-sized buffer store is an error: an empty table gets one entry.
  const std::vector<uint32_t> one(4, 0);
  const std::vector<uint32_t>& stored = data.empty() ? one : data;
  GlBuffer buffer = createGlBuffer();
  glNamedBufferStorage(buffer.id(), GLsizeiptr(stored.size() * sizeof(uint32_t)), stored.data(), 0);
  return buffer;
}

}  // namespace

DeltaSurfaceBuffers DeltaSurfaceBuffers::create(const RuntimePatches& patches) {
  DeltaSurfaceBuffers out;
  out.elements_ = immutableBuffer(elementTable(patches));
  out.slots_ = immutableBuffer(slotTable(patches));
  out.vertex_count_ = patches.vertex_count;
  const std::vector<float> zeros(std::max<size_t>(patches.vertex_count, 1) * 4, 0.0f);
  out.vertex_deltas_ = createGlBuffer();
  glNamedBufferStorage(out.vertex_deltas_.id(), GLsizeiptr(zeros.size() * sizeof(float)),
                       zeros.data(), GL_DYNAMIC_STORAGE_BIT);
  return out;
}

void DeltaSurfaceBuffers::upload(const std::vector<glm::dvec3>& vertex_values,
                                 const std::vector<glm::dvec3>& scale_minus_one) {
  if (!vertex_deltas_ || vertex_count_ == 0) return;
  std::vector<float> packed(size_t(vertex_count_) * 4, 0.0f);
  for (size_t v = 0; v < vertex_values.size() && v < vertex_count_; ++v) {
    packed[v * 4] = float(vertex_values[v].x);
    packed[v * 4 + 1] = float(vertex_values[v].y);
    packed[v * 4 + 2] = float(vertex_values[v].z);
    if (v < scale_minus_one.size()) packed[v * 4 + 3] = float(scale_minus_one[v].x);
  }
  glNamedBufferSubData(vertex_deltas_.id(), 0, GLsizeiptr(packed.size() * sizeof(float)),
                       packed.data());
}

DeltaSurfaceBuffers::DeltaSurfaceBuffers(DeltaSurfaceBuffers&& other) noexcept {
  *this = std::move(other);
}

DeltaSurfaceBuffers& DeltaSurfaceBuffers::operator=(DeltaSurfaceBuffers&& other) noexcept {
  if (this != &other) {
    elements_ = std::move(other.elements_);
    slots_ = std::move(other.slots_);
    vertex_deltas_ = std::move(other.vertex_deltas_);
    vertex_count_ = std::exchange(other.vertex_count_, 0);
  }
  return *this;
}

DeltaSurfaceBuffers::~DeltaSurfaceBuffers() = default;

}  // namespace svit::gl

// Per-vertex interpolation of the runtime's patch deltas on the GPU, so a
// frame never reads the deltas back or re-uploads per-vertex data: the
// runtime's delta buffer stays on the GPU and one small dispatch turns it
// into vertex deltas (DESIGN.md "Patches": a per-patch delta interpolated
// on screen).

#include "scene_renderer_delta_interpolation.h"

#include <epoxy/gl.h>

#include <cstring>
#include <utility>
#include <vector>

#include "scene_renderer_bindings.h"

namespace svit::gl {
namespace {
constexpr uint32_t kWorkgroupSize = 64;  // delta_to_vertices.comp local_size_x
}  // namespace

Expected<VertexDeltaInterpolator> VertexDeltaInterpolator::create(const DeltaInterpolation& deltas) {
  VertexDeltaInterpolator out;
  if (deltas.vertex_count == 0) return out;
  Expected<GlProgram> program = linkProgram({"delta_to_vertices.comp"});
  if (!program.ok()) return program.status();
  out.program_ = std::move(program).value();
  out.vertex_count_ = deltas.vertex_count;
  // (patch, weight bits) pairs, as the shader reads them.
  std::vector<uint32_t> entries(deltas.patches.size() * 2);
  for (size_t i = 0; i < deltas.patches.size(); ++i) {
    entries[i * 2] = deltas.patches[i];
    std::memcpy(&entries[i * 2 + 1], &deltas.weights[i], sizeof(float));
  }
  if (entries.empty()) entries.assign(2, 0);  // a zero-sized buffer store is an error
  glCreateBuffers(1, &out.offsets_);
  glNamedBufferStorage(out.offsets_, GLsizeiptr(deltas.offsets.size() * sizeof(uint32_t)), deltas.offsets.data(), 0);
  glCreateBuffers(1, &out.entries_);
  glNamedBufferStorage(out.entries_, GLsizeiptr(entries.size() * sizeof(uint32_t)), entries.data(), 0);
  glCreateBuffers(1, &out.vertex_deltas_);
  const std::vector<float> zeros(size_t(deltas.vertex_count) * 4, 0.0f);
  glNamedBufferStorage(out.vertex_deltas_, GLsizeiptr(zeros.size() * sizeof(float)), zeros.data(),
                       GL_DYNAMIC_STORAGE_BIT);
  Status error = checkGlError("VertexDeltaInterpolator::create");
  if (!error.ok()) return error;
  return out;
}

VertexDeltaInterpolator::VertexDeltaInterpolator(VertexDeltaInterpolator&& other) noexcept { *this = std::move(other); }

VertexDeltaInterpolator& VertexDeltaInterpolator::operator=(VertexDeltaInterpolator&& other) noexcept {
  if (this != &other) {
    release();
    program_ = std::move(other.program_);
    vertex_count_ = std::exchange(other.vertex_count_, 0);
    offsets_ = std::exchange(other.offsets_, 0);
    entries_ = std::exchange(other.entries_, 0);
    vertex_deltas_ = std::exchange(other.vertex_deltas_, 0);
  }
  return *this;
}

VertexDeltaInterpolator::~VertexDeltaInterpolator() { release(); }

void VertexDeltaInterpolator::release() {
  const GLuint buffers[] = {offsets_, entries_, vertex_deltas_};
  if (offsets_ != 0 || entries_ != 0 || vertex_deltas_ != 0) glDeleteBuffers(3, buffers);
  offsets_ = entries_ = vertex_deltas_ = 0;
}

void VertexDeltaInterpolator::update(uint32_t patch_delta_buffer) {
  if (vertex_count_ == 0 || patch_delta_buffer == 0) return;
  glUseProgram(program_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kPatchDeltas, patch_delta_buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kDeltaOffsets, offsets_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kDeltaEntries, entries_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kVertexDeltas, vertex_deltas_);
  glUniform1ui(render_binding::kComputeVertexCount, vertex_count_);
  glDispatchCompute((vertex_count_ + kWorkgroupSize - 1) / kWorkgroupSize, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void VertexDeltaInterpolator::clear() {
  if (vertex_deltas_ == 0) return;
  const float zero = 0.0f;
  glClearNamedBufferData(vertex_deltas_, GL_R32F, GL_RED, GL_FLOAT, &zero);
}

}  // namespace svit::gl

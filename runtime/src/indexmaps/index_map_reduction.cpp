// Index maps, stages 2 and 3: the small-polygon fallback and the reduction
// into per-receiver shares (index_map_renderer.cpp describes the whole;
// index_map_renderer_impl.h holds the shared state).

#include "index_map_renderer_impl.h"

namespace svit::gl {
namespace {

/// Whether the fallback's classify() (shaders/index_map_fallback.comp) is
/// sure to find triangle `corners` not small for perspective sample `s`:
/// its cos / r^2 estimate at or above kSmallTexels of the largest texel
/// solid angle (4 / res^2, at a face's centre), with a margin for float
/// rounding. Such a pair would only read "not small", as a pair never
/// visited does, so it need not be dispatched: in a closed level most
/// triangles a sample draws are near it and large.
bool surelyNotSmall(const PreparedSample& s, const float* corners, int resolution) {
  if (s.layout == MapLayout::kParallel) return false;
  const glm::dvec3 v0(corners[0], corners[1], corners[2]), v1(corners[3], corners[4], corners[5]),
      v2(corners[6], corners[7], corners[8]);
  const glm::dvec3 d =
      (v0 + v1 + v2) / 3.0 -
      glm::dvec3(s.gpu.position_near[0], s.gpu.position_near[1], s.gpu.position_near[2]);
  const double dist = glm::length(d);
  if (!(dist > 0)) return false;
  const double approx_sr =
      std::abs(glm::dot(glm::cross(v1 - v0, v2 - v0), d)) / (2.0 * dist * dist * dist);
  const double largest_texel_sr = 4.0 / (double(resolution) * double(resolution));
  return approx_sr >= 1.01 * double(kSmallTexels) * largest_texel_sr;
}

}  // namespace

void IndexMapRenderer::Impl::reduceBatch(std::span<const PreparedSample> batch) {
  bindReductionInputs();
  if (settings.small_polygon_fallback) {
    collectFallbackPairs(batch);
    dispatchFallback();
  }
  dispatchReduce();
}

void IndexMapRenderer::Impl::bindReductionInputs() {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, receivers.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSamplesBinding, samples.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLayersBinding, layers.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccumulatorBinding, accumulators.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSmallFlagsBinding, small_flags.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPositionsBinding, positions.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCounterBinding, counter.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSeenBinding, seen.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTouchedBinding, touched.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTouchedListBinding, touched_list.id());
  const bool fallback_on = settings.small_polygon_fallback;
  if (fallback_on && small_generation == std::numeric_limits<uint32_t>::max()) clearSmallFlags();
  ++small_generation;
  for (GLuint program : {fallback.id(), reduce.id()}) {
    glProgramUniform1ui(program, kSeenWordsLocation, seen_words);
    glProgramUniform1ui(program, kStaticTrianglesLocation, GLuint(staticTriangleCount()));
    glProgramUniform1ui(program, kSmallGenerationLocation, small_generation);
  }
  glBindTextureUnit(kIdMapUnit, id_map.id());
  glBindTextureUnit(kDepthMapUnit, depth_map.id());
}

// Work items: one (triangle, sample) pair per invocation, for each triangle
// of a chunk the sample drew on some face and, with a static set, each
// static one of the set; so the pass costs what each sample drew, not the
// level, and its work groups are full (llvmpipe pays per group). A triangle
// left out is credited nothing by the sample anyway: outside every face (no
// vertex lands in the map), or hidden behind what the map drew
// (occlusion-culled, or out of its set: the set holds whatever the same
// sample saw of the static level, and only objects were added since). Its
// flag reads "not small", so any texel it wins in a depth tie is reduced as
// usual.
void IndexMapRenderer::Impl::collectFallbackPairs(std::span<const PreparedSample> batch) {
  const int res = settings.resolution;
  batch_pairs.clear();
  for (size_t b = 0; b < batch.size(); ++b) {
    const TriangleBits* set = batch[b].static_triangles;
    const uint32_t own = batch[b].gpu.info[3];
    for (size_t k = 0; k < chunks.size(); ++k) {
      if (batch_drawn[b * chunks.size() + k] == 0) continue;
      const TriangleChunk& c = chunks[k];
      const float* corners =
          c.dynamic ? dynamic_positions.data() + size_t(c.first - staticTriangleCount()) * 9
                    : static_positions.data() + size_t(c.first) * 9;
      for (uint32_t t = c.first; t < c.first + c.count; ++t, corners += 9) {
        if (t == own || (set && !c.dynamic && !triangleInSet(*set, t))) continue;
        if (surelyNotSmall(batch[b], corners, res)) continue;
        batch_pairs.push_back(t);
        batch_pairs.push_back(uint32_t(b));
      }
    }
  }
}

void IndexMapRenderer::Impl::dispatchFallback() {
  reserveUints(pairs, pairs_capacity, batch_pairs.size());
  if (!batch_pairs.empty()) {
    glNamedBufferSubData(pairs.id(), 0, GLsizeiptr(batch_pairs.size() * sizeof(uint32_t)),
                         batch_pairs.data());
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPairsBinding, pairs.id());
  const GLuint p = fallback.id();
  glUseProgram(p);
  glProgramUniform1i(p, 0, settings.resolution);
  glProgramUniform1ui(p, 1, receiver_count);
  glProgramUniform1ui(p, 2, triangleCount());
  glProgramUniform1f(p, 4, kSmallTexels);
  glProgramUniform1i(p, 5, settings.edge_taps ? 1 : 0);
  glProgramUniform1i(p, 6, settings.neighbour_ids ? 1 : 0);
  const GLuint pair_count = GLuint(batch_pairs.size() / 2);
  glProgramUniform1ui(p, 8, pair_count);
  // Pairs over x (<= 65535 groups of 64) and z.
  const GLuint groups = (pair_count + kLocalSize - 1) / kLocalSize;
  const GLuint x = std::min(groups, kMaxGroups);
  if (groups > 0) glDispatchCompute(x, 1, (groups + x - 1) / x);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void IndexMapRenderer::Impl::dispatchReduce() {
  const int res = settings.resolution;
  const GLuint p = reduce.id();
  glUseProgram(p);
  glProgramUniform1i(p, 0, res);
  glProgramUniform1ui(p, 1, receiver_count);
  glProgramUniform1ui(p, 2, triangleCount());
  glProgramUniform1i(p, 3, settings.small_polygon_fallback ? 1 : 0);
  const GLuint texel_runs = GLuint(res) * GLuint((res + kReduceRun - 1) / kReduceRun);
  glDispatchCompute((texel_runs + kLocalSize - 1) / kLocalSize, GLuint(batch_layers.size()), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void IndexMapRenderer::Impl::compactTouched(uint32_t listed, size_t cells) {
  touched_blocks.resize(listed);
  readback.resize(size_t(listed) * 2 * kCellBlock);
  if (listed > 0) {
    reserveUints(packed, packed_capacity, readback.size());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccumulatorBinding, accumulators.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTouchedBinding, touched.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTouchedListBinding, touched_list.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPackedBinding, packed.id());
    const GLuint p = compact.id();
    glUseProgram(p);
    glProgramUniform1ui(p, 0, listed);
    glProgramUniform1ui(p, 1, GLuint(cells));
    const GLuint x = std::min<GLuint>(listed, kMaxGroups);
    glDispatchCompute(x, 1, (listed + x - 1) / x);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(touched_list.id(), 0, GLsizeiptr(listed * sizeof(uint32_t)),
                            touched_blocks.data());
    glGetNamedBufferSubData(packed.id(), 0, GLsizeiptr(readback.size() * sizeof(uint32_t)),
                            readback.data());
  }
  accumulators_zero = true;
}

}  // namespace svit::gl

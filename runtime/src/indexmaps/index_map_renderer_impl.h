#pragma once
// The index-map renderer's internals, shared by its stages: the raster pass
// (index_map_raster.cpp), the fallback and reduction passes
// (index_map_reduction.cpp) and the rest (index_map_renderer.cpp, whose
// header comment describes the whole). Not part of the library's API.

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gl/gl_handle.h"
#include "gl/gl_program.h"
#include "index_map_culling.h"
#include "index_map_layouts.h"
#include "index_map_occlusion.h"
#include "index_map_renderer.h"

namespace svit::gl {

// A triangle is "small" below this many texels of projected solid angle
// (thesis 5.2: a few texels); its texels are then an all-or-nothing lottery.
constexpr float kSmallTexels = 4.0f;
// The id maps' triangle where nothing was drawn.
constexpr uint32_t kNoTriangle = 0xffffffffu;
// Shader storage and texture bindings (shaders/index_map_*.{frag,comp}).
constexpr GLuint kReceiversBinding = 0, kSamplesBinding = 1, kLayersBinding = 2,
                 kAccumulatorBinding = 3, kSmallFlagsBinding = 4, kPositionsBinding = 5,
                 kCounterBinding = 6, kPairsBinding = 7, kSeenBinding = 8, kTouchedBinding = 9,
                 kTouchedListBinding = 10, kPackedBinding = 11;
// Accumulators per touched block (index_map_common.comp kCellBlock; the
// compaction's local size).
constexpr size_t kCellBlock = 64;
// Uniforms both compute programs take from index_map_common.comp, and the
// small flags' generation both the fallback and the reduction read.
constexpr GLint kSeenWordsLocation = 9, kStaticTrianglesLocation = 10,
                kSmallGenerationLocation = 11;
constexpr GLuint kIdMapUnit = 0, kDepthMapUnit = 1;
constexpr int kReduceRun = 16;        // texels per reduce invocation (index_map_reduce.comp kRun)
constexpr int kLocalSize = 64;        // local_size_x of both compute shaders
constexpr GLuint kMaxGroups = 65535;  // GL_MAX_COMPUTE_WORK_GROUP_COUNT guaranteed minimum
// Occlusion culling: a face drawing at least this many chunks first draws
// the nearest ones, until they hold an eighth of its triangles but at least
// 256 and at most 1,024 (the walls and floor around the sample, in a closed
// level; bounded, so a pass does not grow with the level), then in rounds
// the nearest of what their depth does not hide.
constexpr size_t kOcclusionMinChunks = 8;
constexpr int kOcclusionRounds = 3;  // test-and-draw rounds after the first pass
inline uint64_t occlusionFirstTriangles(std::span<const TriangleChunk> chunks,
                                        std::span<const uint32_t> candidates) {
  uint64_t total = 0;
  for (uint32_t i : candidates) total += chunks[i].count;
  return std::clamp<uint64_t>(total / 8, 256, 1024);
}

// The std430 twin of SampleGpu in shaders/index_map_common.comp.
struct SampleGpu {
  float position_near[4];
  float cube_x_far[4];
  float cube_y_half[4];
  float cube_z_scale[4];
  float axis_cube[4];
  float lobe_params[4];
  uint32_t info[4];   // lobe, layout, slot, own triangle
  uint32_t faces[4];  // face mask, half-face mask, first layer
  float reach_lo[4];  // PointSample::reach, or the whole float range
  float reach_hi[4];
};
static_assert(sizeof(SampleGpu) == 160, "SampleGpu must match std430 in index_map_common.comp");

// What the GPU needs of one sample, and the layout it is rendered with.
struct PreparedSample {
  SampleGpu gpu;
  MapLayout layout;
  glm::dmat3 world_from_cube;
  glm::dvec3 reach_lo{1}, reach_hi{0};             // lo > hi: no box
  const TriangleBits* static_triangles = nullptr;  // PointSample::static_triangles
};

struct IndexMapRenderer::Impl {
  IndexMapSettings settings;
  GlProgram raster, reduce, fallback, compact;
  GlVertexArray vao;
  GlFramebuffer fbo;
  GlTexture id_map, depth_map;
  GlFramebuffer view_fbo;  // countViewPixels' target, made on first use
  GlTexture view_ids, view_depth;
  int view_width = 0, view_height = 0;
  std::vector<uint32_t> view_readback;  // scratch, 2 uints per pixel
  GlBuffer positions, receivers, accumulators, samples, layers, small_flags, counter;
  GlBuffer pairs;             // the fallback's work items, (triangle, sample) pairs, grow-only
  size_t pairs_capacity = 0;  // uints
  // per slot, a bit per static triangle its maps showed (gather's `seen`), grow-only
  GlBuffer seen;
  size_t seen_capacity = 1;  // uints
  uint32_t seen_words = 0;   // per slot in this gather; 0 = not asked for
  // scratch: the fallback's items (triangle, sample of the batch)
  std::vector<uint32_t> batch_pairs;
  size_t triangle_capacity = 0;     // of positions / receivers
  size_t accumulator_capacity = 0;  // uints
  size_t small_flags_capacity = 0;  // uints
  // The batch whose flags are current: a pair's flag holds the generation
  // that found it small, so flags of pairs no batch visited since read as
  // "not small" with no clearing (cleared only when the count wraps).
  uint32_t small_generation = 0;
  // CPU copies, so a growing buffer can be refilled: 9 floats and 2 ids per triangle.
  std::vector<float> static_positions, dynamic_positions;
  std::vector<uint32_t> static_receivers, dynamic_receivers;
  std::vector<uint32_t> dynamic_part_starts;  // MapTriangles::part_starts of the dynamic set
  Aabb static_bounds, dynamic_bounds;
  // Culling runs of both sets, dynamic ones numbered after the static set.
  std::vector<TriangleChunk> static_chunks, chunks;
  std::vector<int32_t> draw_firsts, draw_counts;  // scratch of one face's draw, grow-only
  // Occlusion culling (index_map_occlusion.h): a face whose far chunks wait
  // for the depth of its nearest ones.
  struct PendingFace {
    size_t sample = 0;
    GLint layer = 0;
    int first_row = 0;
    FaceProjection face;
    std::array<GLfloat, 9> view_from_world{};
    std::vector<uint32_t> rest;  // chunk indices not drawn nor hidden yet
    std::vector<uint32_t> next;  // chunk indices this round draws
  };
  std::vector<PendingFace> pending_faces;
  // Samples with a static set draw exactly its triangles that may meet
  // each face (and the dynamic runs that do) from one index list per face:
  // all the batch's lists are built and uploaded before its first draw, so
  // the upload never waits on a draw. Spans of whole runs would draw several
  // times as many triangles.
  GlBuffer set_indices;             // element buffer, grow-only
  size_t set_indices_capacity = 0;  // uints
  std::vector<uint32_t> batch_indices;
  std::vector<std::array<uint32_t, 2>> face_index_ranges;  // per (sample, face): first index, count
  std::vector<uint32_t> face_chunks, near_chunks;          // scratch, chunk indices
  std::vector<Box> seen_boxes;  // scratch: per static chunk a face draws, its drawn triangles' box
  std::vector<uint8_t> batch_drawn;  // per (sample of the batch, chunk): drawn on some face
  std::vector<float> depth_scratch;
  DepthPyramid pyramid;
  uint32_t receiver_count = 0;
  // Sticky: a bad triangle set given to a setter, returned by every gather()
  // until a good set replaces it.
  Status static_error, dynamic_error;
  uint32_t allocations = 0;        // buffer (re)allocations since the last gather
  std::vector<uint32_t> readback;  // scratch, grow-only: the packed blocks' words
  // Sparse read-back (index_map_compact.comp): a flag per block of
  // kCellBlock accumulators, the list of flagged blocks, and the packed
  // copy of their sums. All grow-only; the accumulators and flags are zero
  // between gathers (accumulators_zero), so none is cleared per gather.
  GlBuffer touched, touched_list, packed;
  size_t touched_capacity = 0, touched_list_capacity = 0, packed_capacity = 0;  // uints
  bool accumulators_zero = false;
  std::vector<uint32_t> touched_blocks;  // scratch: the listed blocks, in list order
  std::vector<SampleGpu> batch_samples;
  std::vector<std::array<uint32_t, 4>> batch_layers;

  struct CoverageEntry {
    Lobe lobe;
    float cos_inner, cos_outer;
    LobeCoverage coverage;
  };
  mutable std::vector<CoverageEntry> coverage_cache;

  uint32_t triangleCount() const {
    return uint32_t((static_receivers.size() + dynamic_receivers.size()) / 2);
  }
  uint32_t staticTriangleCount() const { return uint32_t(static_receivers.size() / 2); }

  const LobeCoverage& coverage(const PointSample& s) const {
    // Only a spot's cone changes the lobe; the key ignores the cone otherwise.
    const bool spot = s.lobe == Lobe::kSpot;
    const float ci = spot ? s.cos_inner : 0.0f, co = spot ? s.cos_outer : 0.0f;
    for (const CoverageEntry& e : coverage_cache) {
      if (e.lobe == s.lobe && e.cos_inner == ci && e.cos_outer == co) return e.coverage;
    }
    // A handful of distinct spots per level; beyond that drop the oldest.
    constexpr size_t kMaxEntries = 64;
    if (coverage_cache.size() >= kMaxEntries) coverage_cache.erase(coverage_cache.begin());
    coverage_cache.push_back({s.lobe, ci, co, lobeCoverage(s.lobe, ci, co, settings.resolution)});
    return coverage_cache.back().coverage;
  }

  MapLayout chooseLayout(const PointSample& s) const {
    if (s.lobe == Lobe::kParallel) return MapLayout::kParallel;
    const LobeCoverage& c = coverage(s);
    for (MapLayout layout : {MapLayout::kSingle, MapLayout::kTriple, MapLayout::kHemicube}) {
      if (c.missed[size_t(layout)] <= settings.layout_miss_tolerance) return layout;
    }
    return MapLayout::kCube;
  }

  void growBuffer(const GlBuffer& buffer, size_t bytes) {
    glNamedBufferData(buffer.id(), GLsizeiptr(bytes), nullptr, GL_DYNAMIC_DRAW);
    ++allocations;
  }

  // Grows a grow-only buffer of uints to hold `needed` (by half again at
  // least, so growth is rare); true when it was reallocated.
  bool reserveUints(const GlBuffer& buffer, size_t& capacity, size_t needed) {
    if (needed <= capacity) return false;
    capacity = std::max(needed, capacity + capacity / 2);
    growBuffer(buffer, capacity * sizeof(uint32_t));
    return true;
  }

  // Reads back the `listed` touched blocks' sums of the `cells` in use into
  // touched_blocks and readback (2 words per cell, kCellBlock cells per
  // block, in list order), zeroing them on the GPU; index_map_reduction.cpp.
  void compactTouched(uint32_t listed, size_t cells);

  void clearSmallFlags() {
    const GLuint zero = 0;
    glClearNamedBufferData(small_flags.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    small_generation = 0;
  }

  // Uploads the triangle sets (both: their offsets depend on each other),
  // growing the buffers by half again when they no longer fit.
  void uploadTriangles(bool static_changed) {
    const size_t count = triangleCount();
    const size_t static_count = staticTriangleCount();
    if (static_changed) {
      static_chunks.clear();
      appendChunks(static_positions, 0, false, static_chunks);
    }
    chunks = static_chunks;
    appendChunks(dynamic_positions, uint32_t(static_count), true, chunks, dynamic_part_starts);
    bool all = static_changed;
    if (count > triangle_capacity) {
      triangle_capacity = std::max(count, triangle_capacity + triangle_capacity / 2);
      growBuffer(positions, triangle_capacity * 9 * sizeof(float));
      growBuffer(receivers, triangle_capacity * 2 * sizeof(uint32_t));
      all = true;
    }
    // The fallback's flags: one uint per (sample of a batch, triangle).
    const size_t flags = size_t(settings.max_batch_samples) * count;
    if (settings.small_polygon_fallback && reserveUints(small_flags, small_flags_capacity, flags))
      clearSmallFlags();
    if (all && !static_positions.empty()) {
      glNamedBufferSubData(positions.id(), 0, GLsizeiptr(static_positions.size() * sizeof(float)),
                           static_positions.data());
      glNamedBufferSubData(receivers.id(), 0,
                           GLsizeiptr(static_receivers.size() * sizeof(uint32_t)),
                           static_receivers.data());
    }
    if (!dynamic_positions.empty()) {
      glNamedBufferSubData(positions.id(), GLintptr(static_count * 9 * sizeof(float)),
                           GLsizeiptr(dynamic_positions.size() * sizeof(float)),
                           dynamic_positions.data());
      glNamedBufferSubData(receivers.id(), GLintptr(static_count * 2 * sizeof(uint32_t)),
                           GLsizeiptr(dynamic_receivers.size() * sizeof(uint32_t)),
                           dynamic_receivers.data());
    }
  }

  // Copies a triangle set in; a bad set leaves a sticky error and is dropped.
  void setTriangles(const MapTriangles& t, const char* which, std::vector<float>& positions_out,
                    std::vector<uint32_t>& receivers_out, Aabb& bounds, Status& pending);

  // Draws the listed chunks' ranges (appendChunkRanges: `skip` left out);
  // returns the triangles.
  uint64_t drawChunks(std::span<const uint32_t> list, uint32_t skip) {
    draw_firsts.clear();
    draw_counts.clear();
    uint64_t triangles = 0;
    for (uint32_t i : list)
      triangles += appendChunkRanges(chunks[i], skip, draw_firsts, draw_counts);
    if (!draw_firsts.empty()) {
      glMultiDrawArrays(GL_TRIANGLES, draw_firsts.data(), draw_counts.data(),
                        GLsizei(draw_firsts.size()));
    }
    return triangles;
  }

  // The chunks of `rest` that `pyramid` (built from the face's depth) does
  // not hide, into `kept`; returns the triangles hidden.
  uint64_t keepUnhidden(std::span<const uint32_t> rest, const FaceProjection& face,
                        std::vector<uint32_t>& kept) const {
    kept.clear();
    uint64_t hidden = 0;
    for (uint32_t i : rest) {
      if (chunkHidden(chunks[i], face, pyramid)) {
        hidden += chunks[i].count;
      } else {
        kept.push_back(i);
      }
    }
    return hidden;
  }

  // Linking and GL objects, create()'s stages (index_map_renderer.cpp).
  Status linkPrograms();
  Status createMaps();  // the id and depth arrays and their framebuffer
  void createBuffers();

  // gather()'s stages (index_map_renderer.cpp): zero what the sums need,
  // render and reduce batch by batch, list and read back the touched
  // blocks (returns how many), turn the fixed-point sums into shares.
  void clearSums(size_t cells, size_t blocks, size_t seen_word_count);
  Aabb levelBounds() const;  // of both triangle sets
  void renderBatches(std::span<const PointSample> sample_list, const Aabb& bounds, double diagonal,
                     GatherStats& stats);
  uint32_t compactSums(size_t blocks, size_t cells, GatherStats& stats);
  void unpackShares(uint32_t listed, size_t cells, std::vector<float>& shares) const;

  // countViewPixels()'s stages: the target at the view's size (remade when
  // it changes), then the id raster of the view.
  void ensureViewTarget(int width, int height);
  void rasterView(const ViewFrame& view, int width, int height);

  Status validate(std::span<const PointSample> list, uint32_t slot_count) const;
  PreparedSample prepare(const PointSample& s, uint32_t batch_index, const Aabb& bounds,
                         double diagonal) const;
  // The raster pass (index_map_raster.cpp): binds the target, builds the
  // static-set samples' index lists, draws every face once, then the
  // occlusion-culled faces' later rounds.
  void render(std::span<const PreparedSample> batch, GatherStats& stats);
  void bindRasterTarget() const;
  void buildSetIndices(std::span<const PreparedSample> batch, GatherStats& stats);
  void rasterFaces(std::span<const PreparedSample> batch, GatherStats& stats);
  void rasterOcclusionRounds(std::span<const PreparedSample> batch, GatherStats& stats);
  void useSample(const PreparedSample& s) const;    // the raster program's per-sample uniforms
  void useLayer(GLint layer, int first_row) const;  // attaches a face's layer, scissors its rows
  // Draws the listed chunks for sample `b`, never its own triangle (the
  // ranges split around it), marking them drawn.
  void drawForSample(std::span<const PreparedSample> batch, size_t b,
                     std::span<const uint32_t> list, GatherStats& stats);
  // The reduction (index_map_reduction.cpp): binds its inputs, lists and
  // runs the small-polygon fallback's pairs when on, then the reduce pass.
  void reduceBatch(std::span<const PreparedSample> batch);
  void bindReductionInputs();
  void collectFallbackPairs(std::span<const PreparedSample> batch);  // into batch_pairs
  void dispatchFallback();
  void dispatchReduce();
};

}  // namespace svit::gl

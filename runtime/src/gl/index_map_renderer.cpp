// Index shadow maps (thesis "Radiosity in dynamic scenes", Hrbek 2000, ch.
// 5.2; DESIGN.md "Runtime: index shadow maps"). Per batch of point samples:
//   1. raster: each face of each sample's layout into one layer of an RG32UI
//      array (receiver, triangle) with a reversed float depth array, drawing
//      only the triangle runs whose boxes meet the face (index_map_culling),
//      or a sample's static set triangle by triangle;
//   2. fallback (index_map_fallback.comp): triangles projecting to under a
//      few texels credited analytically x vertex visibility, and flagged;
//   3. reduce (index_map_reduce.comp): every texel's weight (solid angle x
//      normalised lobe x sample weight) added in 64-bit fixed point into
//      acc[slot * receivers + receiver], skipping the flagged triangles.
// The CPU twin of the texel weights and layouts is index_map_layouts.cpp.
// Only the accumulators come back (one glGetNamedBufferSubData per gather).
// GL objects are made in create(); buffers only grow (more triangles,
// receivers or slots), so a steady scene allocates nothing per gather.

#include "index_map_renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "gl_program.h"
#include "index_map_culling.h"
#include "index_map_occlusion.h"
#include "index_map_layouts.h"
#include "svit/gl_context.h"

namespace svit::gl {
namespace {

// 2^40 fixed-point units per unit share: a slot summing to 1 needs 41 of the
// accumulators' 64 bits (room for 2^23 x overshoot), and a texel of a 4096^2
// cube map with 1024 samples of a slot (~1e-11) still rounds to ~10 units.
constexpr double kFixedPoint = 1099511627776.0;
// A triangle is "small" below this many texels of projected solid angle
// (thesis 5.2: a few texels); its texels are then an all-or-nothing lottery.
constexpr float kSmallTexels = 4.0f;
// Near plane per metre of scene diagonal (scale-aware), and per metre of the
// sample's coordinates: float positions carry ~6e-8 |p| of error, so a
// sample on its own surface may sit that far behind it.
constexpr double kNearPerSceneSize = 1e-4;
constexpr double kNearPerCoordinate = 1e-6;
constexpr uint32_t kNoTriangle = 0xffffffffu;
// Shader storage and texture bindings (shaders/index_map_*.{frag,comp}).
constexpr GLuint kReceiversBinding = 0, kSamplesBinding = 1, kLayersBinding = 2, kAccumulatorBinding = 3,
                 kSmallFlagsBinding = 4, kPositionsBinding = 5, kCounterBinding = 6, kPairsBinding = 7,
                 kSeenBinding = 8;
// Uniforms both compute programs take from index_map_common.comp, and the
// small flags' generation both the fallback and the reduction read.
constexpr GLint kSeenWordsLocation = 9, kStaticTrianglesLocation = 10, kSmallGenerationLocation = 11;
constexpr GLuint kIdMapUnit = 0, kDepthMapUnit = 1;
constexpr int kReduceRun = 16;         // texels per reduce invocation (index_map_reduce.comp kRun)
constexpr int kLocalSize = 64;         // local_size_x of both compute shaders
constexpr GLuint kMaxGroups = 65535;   // GL_MAX_COMPUTE_WORK_GROUP_COUNT guaranteed minimum
// Occlusion culling: a face drawing at least this many chunks first draws
// the nearest ones, until they hold an eighth of its triangles but at least
// 256 and at most 1,024 (the walls and floor around the sample, in a closed
// level; bounded, so a pass does not grow with the level), then in rounds
// the nearest of what their depth does not hide.
constexpr size_t kOcclusionMinChunks = 8;
constexpr int kOcclusionRounds = 3;  // test-and-draw rounds after the first pass
uint64_t occlusionFirstTriangles(std::span<const TriangleChunk> chunks, std::span<const uint32_t> candidates) {
  uint64_t total = 0;
  for (uint32_t i : candidates) total += chunks[i].count;
  return std::clamp<uint64_t>(total / 8, 256, 1024);
}
constexpr double kMaxMapBytes = 2.0 * 1024 * 1024 * 1024;

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

// The fixed-function state id rasters need (maps and the view pass):
// reversed depth (nearer is larger), every colour channel, CCW fronts.
void setIdRasterState(bool scissor) {
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_RASTERIZER_DISCARD);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_DEPTH_CLAMP);
  if (scissor) {
    glEnable(GL_SCISSOR_TEST);
  } else {
    glDisable(GL_SCISSOR_TEST);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glFrontFace(GL_CCW);
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
std::string str(const Vec3& v) { return "(" + str(v.x) + ", " + str(v.y) + ", " + str(v.z) + ")"; }

// Saves the GL state a gather changes and puts it back, so the host's
// rendering never sees our framebuffer, depth convention or viewport.
// Indexed buffer bindings 0-6, texture units 0-1 and the active program's
// uniforms are not restored (engines re-bind those before use).
class StateGuard {
 public:
  StateGuard() {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fbo_);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fbo_);
    glGetIntegerv(GL_VIEWPORT, viewport_.data());
    glGetIntegerv(GL_SCISSOR_BOX, scissor_.data());
    glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    glGetBooleani_v(GL_COLOR_WRITEMASK, 0, color_mask_.data());
    glGetIntegerv(GL_CLIP_ORIGIN, &clip_origin_);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth_);
    glGetIntegerv(GL_FRONT_FACE, &front_face_);
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao_);
    for (size_t i = 0; i < kCaps.size(); ++i) enabled_[i] = glIsEnabled(kCaps[i]);
  }
  ~StateGuard() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw_fbo_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read_fbo_));
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    glScissor(scissor_[0], scissor_[1], scissor_[2], scissor_[3]);
    glDepthFunc(GLenum(depth_func_));
    glDepthMask(depth_mask_);
    glColorMaski(0, color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
    glClipControl(GLenum(clip_origin_), GLenum(clip_depth_));
    glFrontFace(GLenum(front_face_));
    glUseProgram(GLuint(program_));
    glBindVertexArray(GLuint(vao_));
    for (size_t i = 0; i < kCaps.size(); ++i) {
      if (enabled_[i]) {
        glEnable(kCaps[i]);
      } else {
        glDisable(kCaps[i]);
      }
    }
  }
  StateGuard(const StateGuard&) = delete;
  StateGuard& operator=(const StateGuard&) = delete;

 private:
  static constexpr std::array<GLenum, 8> kCaps = {GL_SCISSOR_TEST, GL_DEPTH_TEST,         GL_CULL_FACE,
                                                  GL_BLEND,        GL_RASTERIZER_DISCARD, GL_POLYGON_OFFSET_FILL,
                                                  GL_STENCIL_TEST, GL_DEPTH_CLAMP};
  GLint draw_fbo_ = 0, read_fbo_ = 0, depth_func_ = GL_LESS, clip_origin_ = GL_LOWER_LEFT,
        clip_depth_ = GL_NEGATIVE_ONE_TO_ONE, front_face_ = GL_CCW, program_ = 0, vao_ = 0;
  std::array<GLint, 4> viewport_{}, scissor_{};
  GLboolean depth_mask_ = GL_TRUE;
  std::array<GLboolean, 4> color_mask_{};
  std::array<GLboolean, kCaps.size()> enabled_{};
};

// What the GPU needs of one sample, and the layout it is rendered with.
struct PreparedSample {
  SampleGpu gpu;
  MapLayout layout;
  glm::dmat3 world_from_cube;
  glm::dvec3 reach_lo{1}, reach_hi{0};  // lo > hi: no box
  const TriangleBits* static_triangles = nullptr;  // PointSample::static_triangles
};

}  // namespace

struct IndexMapRenderer::Impl {
  IndexMapSettings settings;
  GlProgram raster, reduce, fallback;
  GLuint vao = 0, fbo = 0, id_map = 0, depth_map = 0;
  GLuint view_fbo = 0, view_ids = 0, view_depth = 0;  // countViewPixels' target, made on first use
  int view_width = 0, view_height = 0;
  std::vector<uint32_t> view_readback;  // scratch, 2 uints per pixel
  GLuint positions = 0, receivers = 0, accumulators = 0, samples = 0, layers = 0, small_flags = 0, counter = 0;
  GLuint pairs = 0;  // the fallback's work items, (triangle, sample) pairs, grow-only
  size_t pairs_capacity = 0;  // uints
  GLuint seen = 0;  // per slot, a bit per static triangle its maps showed (gather's `seen`), grow-only
  size_t seen_capacity = 1;  // uints
  uint32_t seen_words = 0;   // per slot in this gather; 0 = not asked for
  std::vector<uint32_t> batch_pairs;  // scratch: the fallback's items (triangle, sample of the batch)
  size_t triangle_capacity = 0;     // of positions / receivers
  size_t accumulator_capacity = 0;  // uints
  size_t small_flags_capacity = 0;   // uints
  // The batch whose flags are current: a pair's flag holds the generation
  // that found it small, so flags of pairs no batch visited since read as
  // "not small" with no clearing (cleared only when the count wraps).
  uint32_t small_generation = 0;
  // CPU copies, so a growing buffer can be refilled: 9 floats and 2 ids per triangle.
  std::vector<float> static_positions, dynamic_positions;
  std::vector<uint32_t> static_receivers, dynamic_receivers;
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
  // the upload never waits on a draw. Spans of runs drew 4.6 (2 x 2) to 6.5
  // (8 x 8) times as many triangles on the sample houses.
  GLuint set_indices = 0;  // element buffer, grow-only
  size_t set_indices_capacity = 0;  // uints
  std::vector<uint32_t> batch_indices;
  std::vector<std::array<uint32_t, 2>> face_index_ranges;  // per (sample, face): first index, count
  std::vector<uint32_t> face_chunks, near_chunks;  // scratch, chunk indices
  std::vector<uint8_t> batch_drawn;  // per (sample of the batch, chunk): drawn on some face
  std::vector<float> depth_scratch;
  DepthPyramid pyramid;
  uint32_t receiver_count = 0;
  // Sticky: a bad triangle set given to a setter, returned by every gather()
  // until a good set replaces it.
  Status static_error, dynamic_error;
  uint32_t allocations = 0;  // buffer (re)allocations since the last gather
  std::vector<uint32_t> readback;  // scratch, grow-only
  std::vector<SampleGpu> batch_samples;
  std::vector<std::array<uint32_t, 4>> batch_layers;

  struct CoverageEntry {
    Lobe lobe;
    float cos_inner, cos_outer;
    LobeCoverage coverage;
  };
  mutable std::vector<CoverageEntry> coverage_cache;

  ~Impl() {
    const GLuint buffers[] = {positions,   receivers, accumulators, samples, layers,
                              small_flags, counter,   pairs,        seen,    set_indices};
    for (GLuint b : buffers) {
      if (b != 0) glDeleteBuffers(1, &b);
    }
    const GLuint textures[] = {id_map, depth_map, view_ids, view_depth};
    for (GLuint t : textures) {
      if (t != 0) glDeleteTextures(1, &t);
    }
    if (fbo != 0) glDeleteFramebuffers(1, &fbo);
    if (view_fbo != 0) glDeleteFramebuffers(1, &view_fbo);
    if (vao != 0) glDeleteVertexArrays(1, &vao);
  }

  uint32_t triangleCount() const { return uint32_t((static_receivers.size() + dynamic_receivers.size()) / 2); }
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

  void growBuffer(GLuint buffer, size_t bytes) {
    glNamedBufferData(buffer, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_DRAW);
    ++allocations;
  }

  void clearSmallFlags() {
    const GLuint zero = 0;
    glClearNamedBufferData(small_flags, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
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
    appendChunks(dynamic_positions, uint32_t(static_count), true, chunks);
    bool all = static_changed;
    if (count > triangle_capacity) {
      triangle_capacity = std::max(count, triangle_capacity + triangle_capacity / 2);
      growBuffer(positions, triangle_capacity * 9 * sizeof(float));
      growBuffer(receivers, triangle_capacity * 2 * sizeof(uint32_t));
      all = true;
    }
    // The fallback's flags: one uint per (sample of a batch, triangle).
    const size_t flags = size_t(settings.max_batch_samples) * count;
    if (settings.small_polygon_fallback && flags > small_flags_capacity) {
      small_flags_capacity = std::max(flags, small_flags_capacity + small_flags_capacity / 2);
      growBuffer(small_flags, small_flags_capacity * sizeof(uint32_t));
      clearSmallFlags();
    }
    if (all && !static_positions.empty()) {
      glNamedBufferSubData(positions, 0, GLsizeiptr(static_positions.size() * sizeof(float)), static_positions.data());
      glNamedBufferSubData(receivers, 0, GLsizeiptr(static_receivers.size() * sizeof(uint32_t)),
                           static_receivers.data());
    }
    if (!dynamic_positions.empty()) {
      glNamedBufferSubData(positions, GLintptr(static_count * 9 * sizeof(float)),
                           GLsizeiptr(dynamic_positions.size() * sizeof(float)), dynamic_positions.data());
      glNamedBufferSubData(receivers, GLintptr(static_count * 2 * sizeof(uint32_t)),
                           GLsizeiptr(dynamic_receivers.size() * sizeof(uint32_t)), dynamic_receivers.data());
    }
  }

  // Copies a triangle set in; a bad set leaves a sticky error and is dropped.
  void setTriangles(const MapTriangles& t, const char* which, std::vector<float>& positions_out,
                    std::vector<uint32_t>& receivers_out, Aabb& bounds, Status& pending) {
    pending = Status();
    const size_t n = t.triangleCount();
    positions_out.clear();
    receivers_out.clear();
    bounds = Aabb{};
    if (t.positions.size() != 3 * n || t.back_receiver.size() != n) {
      pending = Status(StatusCode::kInvalidInput,
                       std::string("index map ") + which + " triangles: " + std::to_string(t.positions.size()) +
                           " positions and " + std::to_string(t.back_receiver.size()) + " back receivers for " +
                           std::to_string(n) + " triangles (need 3 and 1 per triangle)");
      return;
    }
    positions_out.reserve(9 * n);
    receivers_out.reserve(2 * n);
    for (size_t i = 0; i < 3 * n; ++i) {
      const Vec3& p = t.positions[i];
      if (!finite(p)) {
        pending = Status(StatusCode::kInvalidInput, std::string("index map ") + which + " triangle " +
                                                        std::to_string(i / 3) + ": corner " +
                                                        std::to_string(i % 3) + " is not finite " + str(p));
        positions_out.clear();
        receivers_out.clear();
        bounds = Aabb{};
        return;
      }
      positions_out.insert(positions_out.end(), {p.x, p.y, p.z});
      bounds.min = {std::min(bounds.min.x, p.x), std::min(bounds.min.y, p.y), std::min(bounds.min.z, p.z)};
      bounds.max = {std::max(bounds.max.x, p.x), std::max(bounds.max.y, p.y), std::max(bounds.max.z, p.z)};
    }
    for (size_t i = 0; i < n; ++i) receivers_out.insert(receivers_out.end(), {t.front_receiver[i], t.back_receiver[i]});
  }

  // Draws the listed chunks' ranges (appendChunkRanges: `skip` left out);
  // returns the triangles.
  uint64_t drawChunks(std::span<const uint32_t> list, uint32_t skip) {
    draw_firsts.clear();
    draw_counts.clear();
    uint64_t triangles = 0;
    for (uint32_t i : list) triangles += appendChunkRanges(chunks[i], skip, draw_firsts, draw_counts);
    if (!draw_firsts.empty()) {
      glMultiDrawArrays(GL_TRIANGLES, draw_firsts.data(), draw_counts.data(), GLsizei(draw_firsts.size()));
    }
    return triangles;
  }

  // The chunks of `rest` that `pyramid` (built from the face's depth) does
  // not hide, into `kept`; returns the triangles hidden.
  uint64_t keepUnhidden(std::span<const uint32_t> rest, const FaceProjection& face, std::vector<uint32_t>& kept) const {
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

  Status validate(std::span<const PointSample> list, uint32_t slot_count) const;
  PreparedSample prepare(const PointSample& s, uint32_t batch_index, const Aabb& bounds, double diagonal) const;
  void render(std::span<const PreparedSample> batch, GatherStats& stats);
  void reduceBatch(std::span<const PreparedSample> batch);
};

IndexMapRenderer::IndexMapRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
IndexMapRenderer::~IndexMapRenderer() = default;

Expected<std::unique_ptr<IndexMapRenderer>> IndexMapRenderer::create(const IndexMapSettings& settings) {
  // Settings first: they need no context, and a bad one is the caller's to fix.
  auto bad = [](const std::string& what) {
    return Status(StatusCode::kInvalidInput, "IndexMapSettings: " + what);
  };
  if (settings.resolution < 8 || settings.resolution > 8192) {
    return bad("resolution " + std::to_string(settings.resolution) + " is outside [8, 8192]");
  }
  if (settings.max_batch_samples < 1 || settings.max_batch_samples > 1024) {
    return bad("max_batch_samples " + std::to_string(settings.max_batch_samples) + " is outside [1, 1024]");
  }
  if (!(settings.layout_miss_tolerance >= 0 && settings.layout_miss_tolerance <= 1)) {
    return bad("layout_miss_tolerance " + str(settings.layout_miss_tolerance) + " is outside [0, 1]");
  }
  const double texels = double(settings.resolution) * settings.resolution * settings.max_batch_samples * kCubeFaceCount;
  const double map_bytes = texels * (8 + 4);  // RG32UI + DEPTH32F
  if (map_bytes > kMaxMapBytes) {
    return bad("resolution " + std::to_string(settings.resolution) + " with max_batch_samples " +
               std::to_string(settings.max_batch_samples) + " needs " + str(map_bytes / (1 << 20)) +
               " MiB of maps (limit " + str(kMaxMapBytes / (1 << 20)) + ")");
  }
  Expected<GlContextInfo> context = checkGlContext();
  if (!context.ok()) return context.status();
  // Errors the host left behind are not ours to report.
  while (glGetError() != GL_NO_ERROR) {
  }
  GLint max_size = 0, max_layers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  const int layer_count = settings.max_batch_samples * kCubeFaceCount;
  if (settings.resolution > max_size || layer_count > max_layers) {
    return Status(StatusCode::kUnsupported, "IndexMapSettings: resolution " + std::to_string(settings.resolution) +
                                                " x " + std::to_string(layer_count) + " layers exceed this GL's " +
                                                std::to_string(max_size) + " x " + std::to_string(max_layers));
  }

  auto impl = std::make_unique<Impl>();
  impl->settings = settings;
  Expected<GlProgram> raster = linkProgram({"index_map.vert", "index_map.frag"});
  if (!raster.ok()) return raster.status();
  Expected<GlProgram> reduce = linkProgram({"index_map_reduce.comp", "index_map_common.comp"});
  if (!reduce.ok()) return reduce.status();
  Expected<GlProgram> fallback = linkProgram({"index_map_fallback.comp", "index_map_common.comp"});
  if (!fallback.ok()) return fallback.status();
  impl->raster = std::move(raster).value();
  impl->reduce = std::move(reduce).value();
  impl->fallback = std::move(fallback).value();

  Impl& m = *impl;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &m.id_map);
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &m.depth_map);
  glTextureStorage3D(m.id_map, 1, GL_RG32UI, settings.resolution, settings.resolution, layer_count);
  glTextureStorage3D(m.depth_map, 1, GL_DEPTH_COMPONENT32F, settings.resolution, settings.resolution, layer_count);
  for (GLuint t : {m.id_map, m.depth_map}) {
    // Integer textures are incomplete with linear filters (texelFetch would read 0).
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glCreateFramebuffers(1, &m.fbo);
  glNamedFramebufferTextureLayer(m.fbo, GL_COLOR_ATTACHMENT0, m.id_map, 0, 0);
  glNamedFramebufferTextureLayer(m.fbo, GL_DEPTH_ATTACHMENT, m.depth_map, 0, 0);
  glNamedFramebufferDrawBuffer(m.fbo, GL_COLOR_ATTACHMENT0);
  const GLenum fbo_status = glCheckNamedFramebufferStatus(m.fbo, GL_DRAW_FRAMEBUFFER);
  if (fbo_status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(fbo_status));
    return Status(StatusCode::kUnsupported, std::string("index map framebuffer (RG32UI + DEPTH32F array) is incomplete: ") + code);
  }
  GLuint* buffers[] = {&m.set_indices, &m.positions, &m.receivers, &m.accumulators, &m.samples, &m.layers, &m.small_flags, &m.counter, &m.pairs,
                      &m.seen};
  for (GLuint* b : buffers) glCreateBuffers(1, b);
  glNamedBufferData(m.samples, GLsizeiptr(sizeof(SampleGpu) * size_t(settings.max_batch_samples)), nullptr,
                    GL_DYNAMIC_DRAW);
  glNamedBufferData(m.layers, GLsizeiptr(4 * sizeof(uint32_t) * size_t(layer_count)), nullptr, GL_DYNAMIC_DRAW);
  glNamedBufferData(m.counter, sizeof(uint32_t), nullptr, GL_DYNAMIC_DRAW);
  glNamedBufferData(m.seen, sizeof(uint32_t), nullptr, GL_DYNAMIC_DRAW);  // bound even when unused
  glCreateVertexArrays(1, &m.vao);
  glEnableVertexArrayAttrib(m.vao, 0);
  glVertexArrayAttribFormat(m.vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(m.vao, 0, 0);
  glVertexArrayVertexBuffer(m.vao, 0, m.positions, 0, GLsizei(3 * sizeof(float)));
  glVertexArrayElementBuffer(m.vao, m.set_indices);
  if (Status s = checkGlError("IndexMapRenderer::create"); !s.ok()) return s;
  return std::unique_ptr<IndexMapRenderer>(new IndexMapRenderer(std::move(impl)));
}

MapTriangles inRunOrder(const MapTriangles& triangles) {
  const size_t count = triangles.triangleCount();
  if (triangles.positions.size() != 3 * count || triangles.back_receiver.size() != count) return triangles;  // as below
  std::vector<glm::vec3> centroids(count);
  for (size_t t = 0; t < count; ++t) {
    const Vec3* p = &triangles.positions[3 * t];
    centroids[t] = (glm::vec3(p[0].x, p[0].y, p[0].z) + glm::vec3(p[1].x, p[1].y, p[1].z) +
                    glm::vec3(p[2].x, p[2].y, p[2].z)) / 3.0f;
    if (!(std::isfinite(centroids[t].x) && std::isfinite(centroids[t].y) && std::isfinite(centroids[t].z))) return triangles;  // setStaticTriangles says which
  }
  MapTriangles out;
  out.positions.reserve(triangles.positions.size());
  out.front_receiver.reserve(count);
  out.back_receiver.reserve(count);
  for (uint32_t t : spatialRunOrder(centroids)) {
    out.positions.insert(out.positions.end(), triangles.positions.begin() + ptrdiff_t(3 * t),
                         triangles.positions.begin() + ptrdiff_t(3 * t + 3));
    out.front_receiver.push_back(triangles.front_receiver[t]);
    out.back_receiver.push_back(triangles.back_receiver[t]);
  }
  return out;
}

void IndexMapRenderer::setStaticTriangles(const MapTriangles& triangles) {
  Impl& m = *impl_;
  m.setTriangles(triangles, "static", m.static_positions, m.static_receivers, m.static_bounds, m.static_error);
  m.uploadTriangles(true);
}

void IndexMapRenderer::setDynamicTriangles(const MapTriangles& triangles) {
  Impl& m = *impl_;
  m.setTriangles(triangles, "dynamic", m.dynamic_positions, m.dynamic_receivers, m.dynamic_bounds, m.dynamic_error);
  m.uploadTriangles(false);
}

void IndexMapRenderer::setReceiverCount(uint32_t receivers) { impl_->receiver_count = receivers; }

MapLayout IndexMapRenderer::chooseLayout(const PointSample& sample) const { return impl_->chooseLayout(sample); }

double IndexMapRenderer::missedShare(MapLayout layout, const PointSample& sample) const {
  return impl_->coverage(sample).missed[size_t(layout)];
}

const IndexMapSettings& IndexMapRenderer::settings() const { return impl_->settings; }

Status IndexMapRenderer::Impl::validate(std::span<const PointSample> list, uint32_t slot_count) const {
  const size_t static_words = triangleBitWords(staticTriangleCount());
  for (size_t i = 0; i < list.size(); ++i) {
    const PointSample& s = list[i];
    auto bad = [&](const std::string& what) {
      return Status(StatusCode::kInvalidInput, "index map sample " + std::to_string(i) + ": " + what);
    };
    if (!finite(s.position)) return bad("position " + str(s.position) + " is not finite");
    const double len2 = double(s.axis.x) * s.axis.x + double(s.axis.y) * s.axis.y + double(s.axis.z) * s.axis.z;
    if (!finite(s.axis) || !(len2 > 1e-24)) return bad("axis " + str(s.axis) + " is not a direction");
    if (uint32_t(s.lobe) > uint32_t(Lobe::kParallel)) return bad("lobe " + std::to_string(uint32_t(s.lobe)) + " is unknown");
    if (!(s.weight >= 0) || !std::isfinite(s.weight)) return bad("weight " + str(s.weight) + " is not finite and >= 0");
    if (!std::isfinite(s.roll_rad)) return bad("roll_rad " + str(s.roll_rad) + " is not finite");
    if (s.slot >= slot_count) {
      return bad("slot " + std::to_string(s.slot) + " >= slot count " + std::to_string(slot_count));
    }
    if (s.lobe == Lobe::kSpot && !(s.cos_inner >= -1 && s.cos_inner <= 1 && s.cos_outer >= -1 && s.cos_outer <= 1)) {
      return bad("spot cosines inner " + str(s.cos_inner) + ", outer " + str(s.cos_outer) + " are outside [-1, 1]");
    }
    if (s.lobe == Lobe::kParallel && !(s.half_extent_m > 0 && std::isfinite(s.half_extent_m))) {
      return bad("half_extent_m " + str(s.half_extent_m) + " is not a positive length");
    }
    if (s.static_triangles && s.static_triangles->size() != static_words) {
      return bad("static_triangles has " + std::to_string(s.static_triangles->size()) + " words, the static set needs " +
                 std::to_string(static_words));
    }
  }
  return Status();
}

PreparedSample IndexMapRenderer::Impl::prepare(const PointSample& s, uint32_t batch_index, const Aabb& bounds,
                                               double diagonal) const {
  PreparedSample out{};
  out.layout = chooseLayout(s);
  const float inf = std::numeric_limits<float>::infinity();
  const Vec3 lo = s.reach.empty() ? Vec3{-inf, -inf, -inf} : s.reach.min;
  const Vec3 hi = s.reach.empty() ? Vec3{inf, inf, inf} : s.reach.max;
  out.static_triangles = s.static_triangles;
  if (!s.reach.empty()) {
    out.reach_lo = glm::dvec3(lo.x, lo.y, lo.z);
    out.reach_hi = glm::dvec3(hi.x, hi.y, hi.z);
  }
  const float lo4[4] = {lo.x, lo.y, lo.z, 0}, hi4[4] = {hi.x, hi.y, hi.z, 0};
  std::copy(lo4, lo4 + 4, out.gpu.reach_lo);
  std::copy(hi4, hi4 + 4, out.gpu.reach_hi);
  out.world_from_cube = worldFromCube(out.layout, mapFrame(s.axis, s.roll_rad));
  const glm::dvec3 p(s.position.x, s.position.y, s.position.z);
  const double coordinate = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), 1.0});
  const double near_m = std::max(kNearPerSceneSize * diagonal, kNearPerCoordinate * coordinate);
  double far_m = 2 * near_m;
  const glm::dvec3 travel = out.world_from_cube[2];
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? bounds.max.x : bounds.min.x, (k & 2) ? bounds.max.y : bounds.min.y,
                            (k & 4) ? bounds.max.z : bounds.min.z);
    far_m = std::max(far_m, glm::dot(corner - p, travel) * 1.001 + near_m);
  }
  const double res = settings.resolution;
  double scale;
  if (s.lobe == Lobe::kParallel) {
    scale = double(s.weight) * kFixedPoint / (res * res);
  } else {
    const LobeCoverage& c = coverage(s);
    double normaliser = out.layout == MapLayout::kTriple ? c.normaliser_corner_axis : c.normaliser_face_axis;
    // A cone narrower than a texel has no discrete sum; the analytic one
    // still gives the right order of magnitude.
    if (!(normaliser > 0)) normaliser = lobeIntegral(s.lobe, s.cos_inner, s.cos_outer);
    scale = double(s.weight) * kFixedPoint / normaliser;
  }
  const glm::dmat3& w = out.world_from_cube;
  const glm::dvec3 axis = cubeAxis(out.layout);
  SampleGpu& g = out.gpu;
  auto put = [](float* dst, const glm::dvec3& v, double last) {
    dst[0] = float(v.x);
    dst[1] = float(v.y);
    dst[2] = float(v.z);
    dst[3] = float(last);
  };
  put(g.position_near, p, near_m);
  put(g.cube_x_far, w[0], far_m);
  put(g.cube_y_half, w[1], s.half_extent_m);
  put(g.cube_z_scale, w[2], scale);
  put(g.axis_cube, axis, 0);
  put(g.lobe_params, glm::dvec3(s.cos_inner, s.cos_outer, 0), 0);
  g.info[0] = uint32_t(s.lobe);
  g.info[1] = uint32_t(out.layout);
  g.info[2] = s.slot;
  g.info[3] = s.own_triangle < triangleCount() ? s.own_triangle : kNoTriangle;
  g.faces[0] = layoutFaceMask(out.layout);
  g.faces[1] = 0;
  for (int f = 0; f < kCubeFaceCount; ++f) {
    if (isHalfFace(out.layout, f)) g.faces[1] |= 1u << f;
  }
  g.faces[2] = batch_index * kCubeFaceCount;
  return out;
}

void IndexMapRenderer::Impl::render(std::span<const PreparedSample> batch, GatherStats& stats) {
  const int res = settings.resolution;
  const GLuint program = raster.id();
  glUseProgram(program);
  glBindVertexArray(vao);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, receivers);
  glViewport(0, 0, res, res);
  const GLuint clear_id[4] = {kNoReceiver, kNoTriangle, 0, 0};
  const GLfloat clear_depth = 0.0f;  // reversed depth: 0 = infinitely far
  batch_drawn.assign(batch.size() * chunks.size(), 0);
  pending_faces.clear();
  auto useSample = [&](const PreparedSample& s) {
    glProgramUniform3f(program, 0, s.gpu.position_near[0], s.gpu.position_near[1], s.gpu.position_near[2]);
    glProgramUniform1i(program, 2, s.layout == MapLayout::kParallel ? 1 : 0);
    glProgramUniform1f(program, 3, s.gpu.position_near[3]);
    glProgramUniform1f(program, 4, s.gpu.cube_x_far[3]);
    glProgramUniform1f(program, 5, s.gpu.cube_y_half[3]);
  };
  auto useLayer = [&](GLint layer, int first_row) {
    glNamedFramebufferTextureLayer(fbo, GL_COLOR_ATTACHMENT0, id_map, 0, layer);
    glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, depth_map, 0, layer);
    // Half faces: only the rows above the horizon are drawn, cleared and reduced.
    glScissor(0, first_row, res, res - first_row);
  };
  // Draws the listed chunks for sample b, never its own triangle (the
  // ranges split around it).
  auto draw = [&](size_t b, std::span<const uint32_t> list) {
    for (uint32_t i : list) batch_drawn[b * chunks.size() + i] = 1;
    stats.triangles_drawn += drawChunks(list, batch[b].gpu.info[3]);
  };
  // A face's rows (right, up, forward in world) and frustum.
  struct FaceSetup {
    glm::dvec3 rows[3];
    glm::dvec3 eye;
    Frustum frustum;
  };
  auto faceSetup = [](const PreparedSample& s, int face) {
    FaceSetup f;
    const FaceBasis basis = cubeFaceBasis(face);
    f.rows[0] = s.world_from_cube * basis.right;
    f.rows[1] = s.world_from_cube * basis.up;
    f.rows[2] = s.world_from_cube * basis.forward;
    f.eye = glm::dvec3(s.gpu.position_near[0], s.gpu.position_near[1], s.gpu.position_near[2]);
    f.frustum = faceFrustum(f.eye, f.rows[0], f.rows[1], f.rows[2], s.gpu.position_near[3], isHalfFace(s.layout, face),
                            s.layout == MapLayout::kParallel, s.gpu.cube_y_half[3], s.gpu.cube_x_far[3]);
    return f;
  };
  // The index lists of the samples with a static set (see set_indices).
  batch_indices.clear();
  face_index_ranges.assign(batch.size() * kCubeFaceCount, {0u, 0u});
  for (size_t b = 0; b < batch.size(); ++b) {
    const PreparedSample& s = batch[b];
    if (!s.static_triangles) continue;
    const LayoutFaces faces = layoutFaces(s.layout);
    for (int i = 0; i < faces.count; ++i) {
      const int face = faces.faces[size_t(i)];
      const Frustum frustum = faceSetup(s, face).frustum;
      candidateChunks(chunks, frustum, s.reach_lo, s.reach_hi, s.static_triangles, face_chunks);
      const size_t first = batch_indices.size();
      for (uint32_t c : face_chunks) {
        batch_drawn[b * chunks.size() + c] = 1;
        stats.triangles_drawn +=
            appendSetIndices(chunks[c], static_positions, frustum, s.gpu.info[3], *s.static_triangles, batch_indices);
      }
      face_index_ranges[b * kCubeFaceCount + size_t(face)] = {uint32_t(first), uint32_t(batch_indices.size() - first)};
    }
  }
  if (!batch_indices.empty()) {
    if (batch_indices.size() > set_indices_capacity) {
      set_indices_capacity = std::max(batch_indices.size(), set_indices_capacity + set_indices_capacity / 2);
      growBuffer(set_indices, set_indices_capacity * sizeof(uint32_t));
    }
    glNamedBufferSubData(set_indices, 0, GLsizeiptr(batch_indices.size() * sizeof(uint32_t)), batch_indices.data());
  }
  for (size_t b = 0; b < batch.size(); ++b) {
    const PreparedSample& s = batch[b];
    const bool parallel = s.layout == MapLayout::kParallel;
    useSample(s);
    const LayoutFaces faces = layoutFaces(s.layout);
    for (int i = 0; i < faces.count; ++i) {
      const int face = faces.faces[size_t(i)];
      const GLint layer = GLint(b * kCubeFaceCount + size_t(face));
      const int first_row = firstRow(s.layout, face, res);
      useLayer(layer, first_row);
      glClearBufferuiv(GL_COLOR, 0, clear_id);
      glClearBufferfv(GL_DEPTH, 0, &clear_depth);
      const FaceSetup setup = faceSetup(s, face);
      const glm::dvec3* rows = setup.rows;
      const glm::dvec3& eye = setup.eye;
      PendingFace pending;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) pending.view_from_world[size_t(r * 3 + c)] = GLfloat(rows[r][c]);
      }
      glProgramUniformMatrix3fv(program, 1, 1, GL_TRUE, pending.view_from_world.data());  // row-major rows
      if (s.static_triangles) {
        // Its index list, built above: only what the sample saw.
        const auto [first, count] = face_index_ranges[b * kCubeFaceCount + size_t(face)];
        if (count > 0) {
          glDrawElements(GL_TRIANGLES, GLsizei(count), GL_UNSIGNED_INT,
                         reinterpret_cast<const void*>(uintptr_t(first) * sizeof(uint32_t)));
        }
      } else {
        candidateChunks(chunks, setup.frustum, s.reach_lo, s.reach_hi, nullptr, face_chunks);
        // Occlusion culling where it can spare much: perspective faces
        // drawing many chunks.
        if (settings.occlusion_culling && !parallel && face_chunks.size() >= kOcclusionMinChunks) {
          splitNearest(chunks, face_chunks, eye, occlusionFirstTriangles(chunks, face_chunks), near_chunks,
                       pending.rest);
          draw(b, near_chunks);
          pending.sample = b;
          pending.layer = layer;
          pending.first_row = first_row;
          pending.face = {eye, rows[0], rows[1], rows[2], 1.0, 1.0, double(s.gpu.position_near[3])};
          pending_faces.push_back(std::move(pending));
        } else {
          draw(b, face_chunks);
        }
      }
      ++stats.faces_rendered;
      stats.texels += uint64_t(res) * uint64_t(res - first_row);
      batch_layers.push_back({uint32_t(b), uint32_t(face), uint32_t(first_row), uint32_t(layer)});
    }
  }
  // Then rounds: each reads back the faces' depth (one sync per batch, not
  // per face), leaves out what it hides, and draws the nearest of the rest
  // (the last round: all of it), so the occluders build up front to back.
  depth_scratch.resize(size_t(res) * size_t(res));
  size_t current = batch.size();
  for (int round = 1; round <= kOcclusionRounds && !pending_faces.empty(); ++round) {
    // Every face's test first, then every face's draw: a read-back after a
    // draw would wait for it, face by face.
    for (PendingFace& p : pending_faces) {
      glGetTextureSubImage(depth_map, 0, 0, 0, p.layer, res, res, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                           GLsizei(depth_scratch.size() * sizeof(float)), depth_scratch.data());
      buildDepthPyramid(depth_scratch, res, res, p.first_row, pyramid);
      stats.triangles_hidden += keepUnhidden(p.rest, p.face, face_chunks);
      if (round == kOcclusionRounds) {
        p.rest.clear();
        p.next.swap(face_chunks);
      } else {
        splitNearest(chunks, face_chunks, p.face.eye, occlusionFirstTriangles(chunks, face_chunks), p.next, p.rest);
      }
    }
    for (PendingFace& p : pending_faces) {
      if (p.next.empty()) continue;
      if (p.sample != current) {
        useSample(batch[p.sample]);
        current = p.sample;
      }
      useLayer(p.layer, p.first_row);
      glProgramUniformMatrix3fv(program, 1, 1, GL_TRUE, p.view_from_world.data());
      draw(p.sample, p.next);
    }
    std::erase_if(pending_faces, [](const PendingFace& p) { return p.rest.empty(); });
  }
}

void IndexMapRenderer::Impl::reduceBatch(std::span<const PreparedSample> batch) {
  const int res = settings.resolution;
  const uint32_t count = triangleCount();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, receivers);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSamplesBinding, samples);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLayersBinding, layers);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccumulatorBinding, accumulators);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSmallFlagsBinding, small_flags);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPositionsBinding, positions);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kCounterBinding, counter);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSeenBinding, seen);
  const bool fallback_on = settings.small_polygon_fallback;
  if (fallback_on && small_generation == std::numeric_limits<uint32_t>::max()) clearSmallFlags();
  ++small_generation;
  for (GLuint program : {fallback.id(), reduce.id()}) {
    glProgramUniform1ui(program, kSeenWordsLocation, seen_words);
    glProgramUniform1ui(program, kStaticTrianglesLocation, GLuint(staticTriangleCount()));
    glProgramUniform1ui(program, kSmallGenerationLocation, small_generation);
  }
  glBindTextureUnit(kIdMapUnit, id_map);
  glBindTextureUnit(kDepthMapUnit, depth_map);
  if (fallback_on) {
    // Work items: one (triangle, sample) pair per invocation, for each
    // triangle of a chunk the sample drew on some face and, with a static
    // set, each static one of the set; so the pass costs what each sample
    // drew, not the level, and its work groups are full (llvmpipe pays per
    // group, ~8 us). A triangle left out is credited nothing by the sample
    // anyway: outside every face (no vertex lands in the map), or hidden
    // behind what the map drew (occlusion-culled, or out of its set: the
    // set holds whatever the same sample saw of the static level, and only
    // objects were added since). Its flag reads "not small", so any texel
    // it wins in a depth tie is reduced as usual.
    batch_pairs.clear();
    for (size_t b = 0; b < batch.size(); ++b) {
      const TriangleBits* set = batch[b].static_triangles;
      const uint32_t own = batch[b].gpu.info[3];
      for (size_t k = 0; k < chunks.size(); ++k) {
        if (batch_drawn[b * chunks.size() + k] == 0) continue;
        const TriangleChunk& c = chunks[k];
        for (uint32_t t = c.first; t < c.first + c.count; ++t) {
          if (t == own || (set && !c.dynamic && !triangleInSet(*set, t))) continue;
          batch_pairs.push_back(t);
          batch_pairs.push_back(uint32_t(b));
        }
      }
    }
    if (batch_pairs.size() > pairs_capacity) {
      pairs_capacity = std::max(batch_pairs.size(), pairs_capacity + pairs_capacity / 2);
      growBuffer(pairs, pairs_capacity * sizeof(uint32_t));
    }
    if (!batch_pairs.empty()) {
      glNamedBufferSubData(pairs, 0, GLsizeiptr(batch_pairs.size() * sizeof(uint32_t)), batch_pairs.data());
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPairsBinding, pairs);
    const GLuint p = fallback.id();
    glUseProgram(p);
    glProgramUniform1i(p, 0, res);
    glProgramUniform1ui(p, 1, receiver_count);
    glProgramUniform1ui(p, 2, count);
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
  const GLuint p = reduce.id();
  glUseProgram(p);
  glProgramUniform1i(p, 0, res);
  glProgramUniform1ui(p, 1, receiver_count);
  glProgramUniform1ui(p, 2, count);
  glProgramUniform1i(p, 3, fallback_on ? 1 : 0);
  const GLuint texel_runs = GLuint(res) * GLuint((res + kReduceRun - 1) / kReduceRun);
  glDispatchCompute((texel_runs + kLocalSize - 1) / kLocalSize, GLuint(batch_layers.size()), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

Status IndexMapRenderer::gather(std::span<const PointSample> sample_list, uint32_t slot_count,
                                std::vector<float>& shares, GatherStats* stats_out,
                                std::vector<uint32_t>* seen_out) {
  Impl& m = *impl_;
  if (!m.static_error.ok()) return m.static_error;
  if (!m.dynamic_error.ok()) return m.dynamic_error;
  if (Status s = m.validate(sample_list, slot_count); !s.ok()) return s;
  const size_t cells = size_t(slot_count) * m.receiver_count;
  // The accumulators are indexed with 32-bit uints (2 words per cell).
  if (cells > (size_t(1) << 30)) {
    return Status(StatusCode::kInvalidInput, "index map gather: " + std::to_string(slot_count) + " slots x " +
                                                 std::to_string(m.receiver_count) + " receivers exceed 2^30 sums");
  }
  GatherStats stats;
  const uint32_t triangles = m.triangleCount();
  // The fallback's flags are indexed with 32-bit uints too.
  if (uint64_t(triangles) * uint64_t(m.settings.max_batch_samples) > (uint64_t(1) << 31)) {
    return Status(StatusCode::kInvalidInput, "index map gather: " + std::to_string(triangles) + " triangles x " +
                                                 std::to_string(m.settings.max_batch_samples) +
                                                 " max_batch_samples exceed 2^31 (use proxies or smaller batches)");
  }
  m.seen_words = seen_out ? uint32_t(triangleBitWords(m.staticTriangleCount())) : 0u;
  const size_t seen_words = size_t(slot_count) * m.seen_words;
  if (sample_list.empty() || cells == 0 || triangles == 0) {
    shares.assign(cells, 0.0f);
    if (seen_out) seen_out->assign(seen_words, 0u);
    stats.buffer_allocations = std::exchange(m.allocations, 0u);
    if (stats_out) *stats_out = stats;
    return Status();
  }
  if (2 * cells > m.accumulator_capacity) {
    m.accumulator_capacity = std::max(2 * cells, m.accumulator_capacity + m.accumulator_capacity / 2);
    m.growBuffer(m.accumulators, m.accumulator_capacity * sizeof(uint32_t));
  }
  const GLuint zero = 0;
  glClearNamedBufferSubData(m.accumulators, GL_R32UI, 0, GLsizeiptr(2 * cells * sizeof(uint32_t)), GL_RED_INTEGER,
                            GL_UNSIGNED_INT, &zero);
  glClearNamedBufferSubData(m.counter, GL_R32UI, 0, sizeof(uint32_t), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  if (seen_words > 0) {
    if (seen_words > m.seen_capacity) {
      m.seen_capacity = std::max(seen_words, m.seen_capacity + m.seen_capacity / 2);
      m.growBuffer(m.seen, m.seen_capacity * sizeof(uint32_t));
    }
    glClearNamedBufferSubData(m.seen, GL_R32UI, 0, GLsizeiptr(seen_words * sizeof(uint32_t)), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
  }

  Aabb bounds = m.static_bounds;
  for (const Vec3& v : {m.dynamic_bounds.min, m.dynamic_bounds.max}) {
    if (m.dynamic_bounds.empty()) break;
    bounds.min = {std::min(bounds.min.x, v.x), std::min(bounds.min.y, v.y), std::min(bounds.min.z, v.z)};
    bounds.max = {std::max(bounds.max.x, v.x), std::max(bounds.max.y, v.y), std::max(bounds.max.z, v.z)};
  }
  const double diagonal = bounds.empty() ? 0.0
                                         : std::hypot(double(bounds.max.x) - bounds.min.x,
                                                      double(bounds.max.y) - bounds.min.y,
                                                      double(bounds.max.z) - bounds.min.z);
  {
    StateGuard guard;
    setIdRasterState(true);

    std::vector<PreparedSample> batch;
    batch.reserve(size_t(m.settings.max_batch_samples));
    const size_t batch_size = size_t(m.settings.max_batch_samples);
    for (size_t begin = 0; begin < sample_list.size(); begin += batch_size) {
      const size_t end = std::min(sample_list.size(), begin + batch_size);
      batch.clear();
      m.batch_samples.clear();
      m.batch_layers.clear();
      for (size_t i = begin; i < end; ++i) {
        batch.push_back(m.prepare(sample_list[i], uint32_t(i - begin), bounds, diagonal));
        m.batch_samples.push_back(batch.back().gpu);
      }
      glNamedBufferSubData(m.samples, 0, GLsizeiptr(m.batch_samples.size() * sizeof(SampleGpu)),
                           m.batch_samples.data());
      auto t0 = Clock::now();
      m.render(batch, stats);
      glFinish();
      stats.render_ms += msSince(t0);
      glNamedBufferSubData(m.layers, 0, GLsizeiptr(m.batch_layers.size() * sizeof(m.batch_layers[0])),
                           m.batch_layers.data());
      t0 = Clock::now();
      m.reduceBatch(batch);
      glFinish();
      stats.reduce_ms += msSince(t0);
      stats.samples += uint32_t(batch.size());
    }
  }
  const auto t0 = Clock::now();
  if (m.readback.size() < 2 * cells) m.readback.resize(2 * cells);
  glGetNamedBufferSubData(m.accumulators, 0, GLsizeiptr(2 * cells * sizeof(uint32_t)), m.readback.data());
  uint32_t credited = 0;
  glGetNamedBufferSubData(m.counter, 0, sizeof(uint32_t), &credited);
  stats.fallback_triangles = credited;
  if (seen_out) {
    seen_out->resize(seen_words);
    if (seen_words > 0) glGetNamedBufferSubData(m.seen, 0, GLsizeiptr(seen_words * sizeof(uint32_t)), seen_out->data());
  }
  shares.resize(cells);
  for (size_t i = 0; i < cells; ++i) {
    const double fixed = double(m.readback[2 * i + 1]) * 4294967296.0 + double(m.readback[2 * i]);
    shares[i] = float(fixed / kFixedPoint);
  }
  stats.readback_ms = msSince(t0);
  stats.buffer_allocations = std::exchange(m.allocations, 0u);
  if (Status s = checkGlError("IndexMapRenderer::gather"); !s.ok()) return s;
  if (stats_out) *stats_out = stats;
  return Status();
}

Status IndexMapRenderer::countViewPixels(const ViewFrame& view, int width, int height, std::vector<uint32_t>& pixels) {
  Impl& m = *impl_;
  if (!m.static_error.ok()) return m.static_error;
  if (!m.dynamic_error.ok()) return m.dynamic_error;
  if (width < 1 || height < 1 || width > 4096 || height > 4096) {
    return Status(StatusCode::kInvalidInput, "index map view pass: " + std::to_string(width) + " x " +
                                                 std::to_string(height) + " pixels is outside 1..4096");
  }
  const float values[] = {view.eye.x, view.eye.y, view.eye.z, view.right.x, view.right.y, view.right.z,
                          view.up.x, view.up.y, view.up.z, view.forward.x, view.forward.y, view.forward.z,
                          view.tan_half_x, view.tan_half_y, view.near_m};
  for (float v : values) {
    if (!std::isfinite(v)) return Status(StatusCode::kInvalidInput, "index map view pass: the view is not finite");
  }
  if (!(view.tan_half_x > 0 && view.tan_half_y > 0 && view.near_m > 0)) {
    return Status(StatusCode::kInvalidInput, "index map view pass: field of view and near plane must be positive");
  }
  if (width != m.view_width || height != m.view_height) {
    if (m.view_fbo != 0) glDeleteFramebuffers(1, &m.view_fbo);
    const GLuint old[] = {m.view_ids, m.view_depth};
    for (GLuint t : old) {
      if (t != 0) glDeleteTextures(1, &t);
    }
    glCreateTextures(GL_TEXTURE_2D, 1, &m.view_ids);
    glTextureStorage2D(m.view_ids, 1, GL_RG32UI, width, height);
    glCreateTextures(GL_TEXTURE_2D, 1, &m.view_depth);
    glTextureStorage2D(m.view_depth, 1, GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &m.view_fbo);
    glNamedFramebufferTexture(m.view_fbo, GL_COLOR_ATTACHMENT0, m.view_ids, 0);
    glNamedFramebufferTexture(m.view_fbo, GL_DEPTH_ATTACHMENT, m.view_depth, 0);
    glNamedFramebufferDrawBuffer(m.view_fbo, GL_COLOR_ATTACHMENT0);
    m.view_width = width;
    m.view_height = height;
    ++m.allocations;
  }
  const uint32_t triangles = m.triangleCount();
  {
    StateGuard guard;
    setIdRasterState(false);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.view_fbo);
    glViewport(0, 0, width, height);
    const GLuint clear_id[4] = {kNoReceiver, kNoTriangle, 0, 0};
    const GLfloat clear_depth = 0.0f;
    glClearBufferuiv(GL_COLOR, 0, clear_id);
    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
    if (triangles > 0) {
      const GLuint program = m.raster.id();
      glUseProgram(program);
      glBindVertexArray(m.vao);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, m.receivers);
      // The maps' perspective face with the rows scaled by the field of
      // view: clip x = right.d / tan_half_x, w = forward.d.
      const Vec3 rows[3] = {view.right, view.up, view.forward};
      const float scale[3] = {1.0f / view.tan_half_x, 1.0f / view.tan_half_y, 1.0f};
      GLfloat view_from_world[9];
      for (int r = 0; r < 3; ++r) {
        const float row[3] = {rows[r].x, rows[r].y, rows[r].z};
        for (int c = 0; c < 3; ++c) view_from_world[r * 3 + c] = row[c] * scale[r];
      }
      glProgramUniform3f(program, 0, view.eye.x, view.eye.y, view.eye.z);
      glProgramUniformMatrix3fv(program, 1, 1, GL_TRUE, view_from_world);
      glProgramUniform1i(program, 2, 0);
      glProgramUniform1f(program, 3, view.near_m);
      // Only the runs that may meet the view's frustum: |right.d| <= tx
      // forward.d, |up.d| <= ty forward.d, forward.d >= near.
      Frustum frustum;
      frustum.eye = glm::dvec3(view.eye.x, view.eye.y, view.eye.z);
      const glm::dvec3 r(view.right.x, view.right.y, view.right.z), u(view.up.x, view.up.y, view.up.z),
          f(view.forward.x, view.forward.y, view.forward.z);
      const double tx = view.tan_half_x, ty = view.tan_half_y;
      frustum.normal = {f * tx - r, f * tx + r, f * ty - u, f * ty + u, f, f};
      frustum.offset = {0, 0, 0, 0, double(view.near_m), double(view.near_m)};
      frustum.count = 5;
      const glm::dvec3 no_box_lo(1.0), no_box_hi(0.0);
      auto draw = [&](std::span<const uint32_t> list) { m.drawChunks(list, kNoTriangle); };
      candidateChunks(m.chunks, frustum, no_box_lo, no_box_hi, nullptr, m.face_chunks);
      if (!m.settings.occlusion_culling || m.face_chunks.size() < kOcclusionMinChunks) {
        draw(m.face_chunks);
      } else {
        // As the maps' faces: the nearest chunks, then what they leave in view.
        std::vector<uint32_t> rest;
        splitNearest(m.chunks, m.face_chunks, frustum.eye, occlusionFirstTriangles(m.chunks, m.face_chunks),
                     m.near_chunks, rest);
        draw(m.near_chunks);
        m.depth_scratch.resize(size_t(width) * size_t(height));
        glGetTextureImage(m.view_depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                          GLsizei(m.depth_scratch.size() * sizeof(float)), m.depth_scratch.data());
        buildDepthPyramid(m.depth_scratch, width, height, 0, m.pyramid);
        const FaceProjection face{frustum.eye, r, u, f, 1.0 / tx, 1.0 / ty, double(view.near_m)};
        m.keepUnhidden(rest, face, m.face_chunks);
        draw(m.face_chunks);
      }
    }
  }
  const size_t count = size_t(width) * size_t(height);
  m.view_readback.resize(2 * count);
  glGetTextureImage(m.view_ids, 0, GL_RG_INTEGER, GL_UNSIGNED_INT, GLsizei(m.view_readback.size() * sizeof(uint32_t)),
                    m.view_readback.data());
  pixels.assign(m.receiver_count, 0u);
  for (size_t i = 0; i < count; ++i) {
    const uint32_t r = m.view_readback[2 * i];
    if (r < m.receiver_count) ++pixels[r];
  }
  return checkGlError("IndexMapRenderer::countViewPixels");
}

std::vector<GlObject> IndexMapRenderer::mapObjects() const {
  const Impl& m = *impl_;
  std::vector<GlObject> out = {glTextureObject(m.id_map), glTextureObject(m.depth_map)};
  for (GLuint b : {m.positions, m.receivers, m.accumulators, m.samples, m.layers, m.small_flags, m.counter, m.pairs,
                   m.seen, m.set_indices}) {
    out.push_back(glBufferObject(b));
  }
  return out;
}

std::vector<GlObject> IndexMapRenderer::viewObjects() const {
  return {glTextureObject(impl_->view_ids), glTextureObject(impl_->view_depth)};
}

uint64_t IndexMapRenderer::hostBytes() const {
  const Impl& m = *impl_;
  auto bytes = [](const auto& v) { return uint64_t(v.capacity()) * sizeof(v[0]); };
  return bytes(m.static_positions) + bytes(m.dynamic_positions) + bytes(m.static_receivers) +
         bytes(m.dynamic_receivers) + bytes(m.static_chunks) + bytes(m.chunks) + bytes(m.readback) +
         bytes(m.view_readback) + bytes(m.batch_samples) + bytes(m.batch_layers) + bytes(m.batch_pairs) +
         bytes(m.batch_indices) + bytes(m.face_index_ranges);
}

}  // namespace svit::gl

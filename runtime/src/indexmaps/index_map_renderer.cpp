// Index shadow maps (thesis "Radiosity in dynamic scenes", Hrbek 2000, ch.
// 5.2; docs/architecture/runtime-indexmaps.md "Index shadow maps"). Per
// batch of point samples:
//   1. raster: each face of each sample's layout into one layer of an RG32UI
//      array (receiver, triangle) with a reversed float depth array, drawing
//      only the triangle runs whose boxes meet the face (index_map_culling),
//      or a sample's static set triangle by triangle;
//   2. fallback (index_map_fallback.comp): triangles projecting to under a
//      few texels credited analytically x vertex visibility, and flagged;
//   3. reduce (index_map_reduce.comp): every texel's weight (solid angle x
//      normalised lobe x sample weight) added in 64-bit fixed point into
//      acc[slot * receivers + receiver], skipping the flagged triangles.
// Stage 1 is index_map_raster.cpp, stages 2 and 3 index_map_reduction.cpp;
// the state they share is index_map_renderer_impl.h. The CPU twin of the
// texel weights and layouts is index_map_layouts.cpp.
// Only the accumulators come back, and only the blocks of kCellBlock a
// gather added to (4. compaction, index_map_compact.comp, which also zeroes
// them for the next gather): two read-backs per gather of what was lit.
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

#include "index_map_renderer_impl.h"
#include "scene/numeric.h"
#include "svit/gl_context.h"

namespace svit::gl {
namespace {

// 2^40 fixed-point units per unit share: a slot summing to 1 needs 41 of the
// accumulators' 64 bits (room for 2^23 x overshoot), and a texel of a 4096^2
// cube map with 1024 samples of a slot (~1e-11) still rounds to ~10 units.
constexpr double kFixedPoint = 1099511627776.0;
// Near plane per metre of scene diagonal (scale-aware), and per metre of the
// sample's coordinates: float positions carry ~6e-8 |p| of error, so a
// sample on its own surface may sit that far behind it.
constexpr double kNearPerSceneSize = 1e-4;
constexpr double kNearPerCoordinate = 1e-6;
constexpr double kMaxMapBytes = 2.0 * 1024 * 1024 * 1024;

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
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

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
  static constexpr std::array<GLenum, 8> kCaps = {
      GL_SCISSOR_TEST,       GL_DEPTH_TEST,          GL_CULL_FACE,    GL_BLEND,
      GL_RASTERIZER_DISCARD, GL_POLYGON_OFFSET_FILL, GL_STENCIL_TEST, GL_DEPTH_CLAMP};
  GLint draw_fbo_ = 0, read_fbo_ = 0, depth_func_ = GL_LESS, clip_origin_ = GL_LOWER_LEFT,
        clip_depth_ = GL_NEGATIVE_ONE_TO_ONE, front_face_ = GL_CCW, program_ = 0, vao_ = 0;
  std::array<GLint, 4> viewport_{}, scissor_{};
  GLboolean depth_mask_ = GL_TRUE;
  std::array<GLboolean, 4> color_mask_{};
  std::array<GLboolean, kCaps.size()> enabled_{};
};

}  // namespace

void IndexMapRenderer::Impl::setTriangles(const MapTriangles& t, const char* which,
                                          std::vector<float>& positions_out,
                                          std::vector<uint32_t>& receivers_out, Aabb& bounds,
                                          Status& pending) {
  pending = Status();
  const size_t n = t.triangleCount();
  positions_out.clear();
  receivers_out.clear();
  bounds = Aabb{};
  if (t.positions.size() != 3 * n || t.back_receiver.size() != n) {
    pending = Status(StatusCode::kInvalidInput,
                     std::string("index map ") + which +
                         " triangles: " + std::to_string(t.positions.size()) + " positions and " +
                         std::to_string(t.back_receiver.size()) + " back receivers for " +
                         std::to_string(n) + " triangles (need 3 and 1 per triangle)");
    return;
  }
  positions_out.reserve(9 * n);
  receivers_out.reserve(2 * n);
  for (size_t i = 0; i < 3 * n; ++i) {
    const Vec3& p = t.positions[i];
    if (!finite(p)) {
      pending = Status(StatusCode::kInvalidInput,
                       std::string("index map ") + which + " triangle " + std::to_string(i / 3) +
                           ": corner " + std::to_string(i % 3) + " is not finite " + str(p));
      positions_out.clear();
      receivers_out.clear();
      bounds = Aabb{};
      return;
    }
    positions_out.insert(positions_out.end(), {p.x, p.y, p.z});
    bounds.min = {std::min(bounds.min.x, p.x), std::min(bounds.min.y, p.y),
                  std::min(bounds.min.z, p.z)};
    bounds.max = {std::max(bounds.max.x, p.x), std::max(bounds.max.y, p.y),
                  std::max(bounds.max.z, p.z)};
  }
  for (size_t i = 0; i < n; ++i)
    receivers_out.insert(receivers_out.end(), {t.front_receiver[i], t.back_receiver[i]});
}

IndexMapRenderer::IndexMapRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
IndexMapRenderer::~IndexMapRenderer() = default;

namespace {

// Settings first: they need no context, and a bad one is the caller's to fix.
Status validateSettings(const IndexMapSettings& settings) {
  auto bad = [](const std::string& what) {
    return Status(StatusCode::kInvalidInput, "IndexMapSettings: " + what);
  };
  if (settings.resolution < 8 || settings.resolution > 8192) {
    return bad("resolution " + std::to_string(settings.resolution) + " is outside [8, 8192]");
  }
  if (settings.max_batch_samples < 1 || settings.max_batch_samples > 1024) {
    return bad("max_batch_samples " + std::to_string(settings.max_batch_samples) +
               " is outside [1, 1024]");
  }
  if (!(settings.layout_miss_tolerance >= 0 && settings.layout_miss_tolerance <= 1)) {
    return bad("layout_miss_tolerance " + str(settings.layout_miss_tolerance) +
               " is outside [0, 1]");
  }
  const double texels = double(settings.resolution) * settings.resolution *
                        settings.max_batch_samples * kCubeFaceCount;
  const double map_bytes = texels * (8 + 4);  // RG32UI + DEPTH32F
  if (map_bytes > kMaxMapBytes) {
    return bad("resolution " + std::to_string(settings.resolution) + " with max_batch_samples " +
               std::to_string(settings.max_batch_samples) + " needs " + str(map_bytes / (1 << 20)) +
               " MiB of maps (limit " + str(kMaxMapBytes / (1 << 20)) + ")");
  }
  return Status();
}

// The maps' size against this GL's limits.
Status checkMapLimits(const IndexMapSettings& settings) {
  GLint max_size = 0, max_layers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  const int layer_count = settings.max_batch_samples * kCubeFaceCount;
  if (settings.resolution > max_size || layer_count > max_layers) {
    return Status(StatusCode::kUnsupported,
                  "IndexMapSettings: resolution " + std::to_string(settings.resolution) + " x " +
                      std::to_string(layer_count) + " layers exceed this GL's " +
                      std::to_string(max_size) + " x " + std::to_string(max_layers));
  }
  return Status();
}

}  // namespace

Expected<std::unique_ptr<IndexMapRenderer>> IndexMapRenderer::create(
    const IndexMapSettings& settings) {
  if (Status s = validateSettings(settings); !s.ok()) return s;
  Expected<GlContextInfo> context = checkGlContext();
  if (!context.ok()) return context.status();
  // Errors the host left behind are not ours to report.
  while (glGetError() != GL_NO_ERROR) {}
  if (Status s = checkMapLimits(settings); !s.ok()) return s;
  auto impl = std::make_unique<Impl>();
  impl->settings = settings;
  if (Status s = impl->linkPrograms(); !s.ok()) return s;
  if (Status s = impl->createMaps(); !s.ok()) return s;
  impl->createBuffers();
  if (Status s = checkGlError("IndexMapRenderer::create"); !s.ok()) return s;
  return std::unique_ptr<IndexMapRenderer>(new IndexMapRenderer(std::move(impl)));
}

Status IndexMapRenderer::Impl::linkPrograms() {
  Expected<GlProgram> linked_raster = linkProgram({"index_map.vert", "index_map.frag"});
  if (!linked_raster.ok()) return linked_raster.status();
  Expected<GlProgram> linked_reduce =
      linkProgram({"index_map_reduce.comp", "index_map_common.comp"});
  if (!linked_reduce.ok()) return linked_reduce.status();
  Expected<GlProgram> linked_fallback =
      linkProgram({"index_map_fallback.comp", "index_map_common.comp"});
  if (!linked_fallback.ok()) return linked_fallback.status();
  Expected<GlProgram> linked_compact = linkProgram({"index_map_compact.comp"});
  if (!linked_compact.ok()) return linked_compact.status();
  raster = std::move(linked_raster).value();
  reduce = std::move(linked_reduce).value();
  fallback = std::move(linked_fallback).value();
  compact = std::move(linked_compact).value();
  return Status();
}

Status IndexMapRenderer::Impl::createMaps() {
  const int layer_count = settings.max_batch_samples * kCubeFaceCount;
  id_map = createGlTexture(GL_TEXTURE_2D_ARRAY);
  depth_map = createGlTexture(GL_TEXTURE_2D_ARRAY);
  glTextureStorage3D(id_map.id(), 1, GL_RG32UI, settings.resolution, settings.resolution,
                     layer_count);
  glTextureStorage3D(depth_map.id(), 1, GL_DEPTH_COMPONENT32F, settings.resolution,
                     settings.resolution, layer_count);
  for (GLuint t : {id_map.id(), depth_map.id()}) {
    // Integer textures are incomplete with linear filters (texelFetch would read 0).
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  fbo = createGlFramebuffer();
  glNamedFramebufferTextureLayer(fbo.id(), GL_COLOR_ATTACHMENT0, id_map.id(), 0, 0);
  glNamedFramebufferTextureLayer(fbo.id(), GL_DEPTH_ATTACHMENT, depth_map.id(), 0, 0);
  glNamedFramebufferDrawBuffer(fbo.id(), GL_COLOR_ATTACHMENT0);
  const GLenum fbo_status = glCheckNamedFramebufferStatus(fbo.id(), GL_DRAW_FRAMEBUFFER);
  if (fbo_status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(fbo_status));
    return Status(
        StatusCode::kUnsupported,
        std::string("index map framebuffer (RG32UI + DEPTH32F array) is incomplete: ") + code);
  }
  return Status();
}

void IndexMapRenderer::Impl::createBuffers() {
  const int layer_count = settings.max_batch_samples * kCubeFaceCount;
  GlBuffer* buffers[] = {&set_indices, &positions,    &receivers, &accumulators, &samples,
                         &layers,      &small_flags,  &counter,   &pairs,        &seen,
                         &touched,     &touched_list, &packed};
  for (GlBuffer* b : buffers) *b = createGlBuffer();
  glNamedBufferData(samples.id(),
                    GLsizeiptr(sizeof(SampleGpu) * size_t(settings.max_batch_samples)), nullptr,
                    GL_DYNAMIC_DRAW);
  glNamedBufferData(layers.id(), GLsizeiptr(4 * sizeof(uint32_t) * size_t(layer_count)), nullptr,
                    GL_DYNAMIC_DRAW);
  glNamedBufferData(counter.id(), 2 * sizeof(uint32_t), nullptr, GL_DYNAMIC_DRAW);
  // bound even when unused
  glNamedBufferData(seen.id(), sizeof(uint32_t), nullptr, GL_DYNAMIC_DRAW);
  vao = createGlVertexArray();
  glEnableVertexArrayAttrib(vao.id(), 0);
  glVertexArrayAttribFormat(vao.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao.id(), 0, 0);
  glVertexArrayVertexBuffer(vao.id(), 0, positions.id(), 0, GLsizei(3 * sizeof(float)));
  glVertexArrayElementBuffer(vao.id(), set_indices.id());
}

MapTriangles inRunOrder(const MapTriangles& triangles) {
  const size_t count = triangles.triangleCount();
  // as below
  if (triangles.positions.size() != 3 * count || triangles.back_receiver.size() != count)
    return triangles;
  std::vector<glm::vec3> centroids(count);
  for (size_t t = 0; t < count; ++t) {
    const Vec3* p = &triangles.positions[3 * t];
    centroids[t] = (glm::vec3(p[0].x, p[0].y, p[0].z) + glm::vec3(p[1].x, p[1].y, p[1].z) +
                    glm::vec3(p[2].x, p[2].y, p[2].z)) /
                   3.0f;
    // setStaticTriangles says which
    if (!(std::isfinite(centroids[t].x) && std::isfinite(centroids[t].y) &&
          std::isfinite(centroids[t].z)))
      return triangles;
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
  m.setTriangles(triangles, "static", m.static_positions, m.static_receivers, m.static_bounds,
                 m.static_error);
  m.uploadTriangles(true);
}

void IndexMapRenderer::setDynamicTriangles(const MapTriangles& triangles) {
  Impl& m = *impl_;
  m.setTriangles(triangles, "dynamic", m.dynamic_positions, m.dynamic_receivers, m.dynamic_bounds,
                 m.dynamic_error);
  m.dynamic_part_starts = m.dynamic_error.ok() ? triangles.part_starts : std::vector<uint32_t>{};
  m.uploadTriangles(false);
}

void IndexMapRenderer::setReceiverCount(uint32_t receivers) { impl_->receiver_count = receivers; }

MapLayout IndexMapRenderer::chooseLayout(const PointSample& sample) const {
  return impl_->chooseLayout(sample);
}

double IndexMapRenderer::missedShare(MapLayout layout, const PointSample& sample) const {
  return impl_->coverage(sample).missed[size_t(layout)];
}

const IndexMapSettings& IndexMapRenderer::settings() const { return impl_->settings; }

Status IndexMapRenderer::Impl::validate(std::span<const PointSample> list,
                                        uint32_t slot_count) const {
  const size_t static_words = triangleBitWords(staticTriangleCount());
  for (size_t i = 0; i < list.size(); ++i) {
    const PointSample& s = list[i];
    auto bad = [&](const std::string& what) {
      return Status(StatusCode::kInvalidInput,
                    "index map sample " + std::to_string(i) + ": " + what);
    };
    if (!finite(s.position)) return bad("position " + str(s.position) + " is not finite");
    const double len2 =
        double(s.axis.x) * s.axis.x + double(s.axis.y) * s.axis.y + double(s.axis.z) * s.axis.z;
    if (!finite(s.axis) || !(len2 > 1e-24))
      return bad("axis " + str(s.axis) + " is not a direction");
    if (uint32_t(s.lobe) > uint32_t(Lobe::kParallel))
      return bad("lobe " + std::to_string(uint32_t(s.lobe)) + " is unknown");
    if (!(s.weight >= 0) || !std::isfinite(s.weight))
      return bad("weight " + str(s.weight) + " is not finite and >= 0");
    if (!std::isfinite(s.roll_rad)) return bad("roll_rad " + str(s.roll_rad) + " is not finite");
    if (s.slot >= slot_count) {
      return bad("slot " + std::to_string(s.slot) + " >= slot count " + std::to_string(slot_count));
    }
    if (s.lobe == Lobe::kSpot &&
        !(s.cos_inner >= -1 && s.cos_inner <= 1 && s.cos_outer >= -1 && s.cos_outer <= 1)) {
      return bad("spot cosines inner " + str(s.cos_inner) + ", outer " + str(s.cos_outer) +
                 " are outside [-1, 1]");
    }
    if (s.lobe == Lobe::kParallel && !(s.half_extent_m > 0 && std::isfinite(s.half_extent_m))) {
      return bad("half_extent_m " + str(s.half_extent_m) + " is not a positive length");
    }
    if (s.static_triangles && s.static_triangles->size() != static_words) {
      return bad("static_triangles has " + std::to_string(s.static_triangles->size()) +
                 " words, the static set needs " + std::to_string(static_words));
    }
  }
  return Status();
}

PreparedSample IndexMapRenderer::Impl::prepare(const PointSample& s, uint32_t batch_index,
                                               const Aabb& bounds, double diagonal) const {
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
    const glm::dvec3 corner((k & 1) ? bounds.max.x : bounds.min.x,
                            (k & 2) ? bounds.max.y : bounds.min.y,
                            (k & 4) ? bounds.max.z : bounds.min.z);
    far_m = std::max(far_m, glm::dot(corner - p, travel) * 1.001 + near_m);
  }
  const double res = settings.resolution;
  double scale;
  if (s.lobe == Lobe::kParallel) {
    scale = double(s.weight) * kFixedPoint / (res * res);
  } else {
    const LobeCoverage& c = coverage(s);
    double normaliser =
        out.layout == MapLayout::kTriple ? c.normaliser_corner_axis : c.normaliser_face_axis;
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
    return Status(StatusCode::kInvalidInput, "index map gather: " + std::to_string(slot_count) +
                                                 " slots x " + std::to_string(m.receiver_count) +
                                                 " receivers exceed 2^30 sums");
  }
  GatherStats stats;
  const uint32_t triangles = m.triangleCount();
  // The fallback's flags are indexed with 32-bit uints too.
  if (uint64_t(triangles) * uint64_t(m.settings.max_batch_samples) > (uint64_t(1) << 31)) {
    return Status(StatusCode::kInvalidInput,
                  "index map gather: " + std::to_string(triangles) + " triangles x " +
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
  const size_t blocks = (cells + kCellBlock - 1) / kCellBlock;
  m.clearSums(cells, blocks, seen_words);
  const Aabb bounds = m.levelBounds();
  const double diagonal = bounds.empty() ? 0.0
                                         : std::hypot(double(bounds.max.x) - bounds.min.x,
                                                      double(bounds.max.y) - bounds.min.y,
                                                      double(bounds.max.z) - bounds.min.z);
  Clock::time_point readback_start;
  uint32_t listed = 0;
  {
    StateGuard guard;
    setIdRasterState(true);
    m.renderBatches(sample_list, bounds, diagonal, stats);
    // The sums come back by touched block (inside the guard: the
    // compaction uses a program of its own).
    readback_start = Clock::now();
    listed = m.compactSums(blocks, cells, stats);
  }
  if (seen_out) {
    seen_out->resize(seen_words);
    if (seen_words > 0)
      glGetNamedBufferSubData(m.seen.id(), 0, GLsizeiptr(seen_words * sizeof(uint32_t)),
                              seen_out->data());
  }
  m.unpackShares(listed, cells, shares);
  stats.readback_ms = msSince(readback_start);
  stats.buffer_allocations = std::exchange(m.allocations, 0u);
  if (Status s = checkGlError("IndexMapRenderer::gather"); !s.ok()) return s;
  if (stats_out) *stats_out = stats;
  return Status();
}

// The accumulators and block flags are left zero by every gather's
// compaction; only new storage (or an interrupted gather) needs clearing.
void IndexMapRenderer::Impl::clearSums(size_t cells, size_t blocks, size_t seen_word_count) {
  bool fresh = reserveUints(accumulators, accumulator_capacity, 2 * cells);
  fresh |= reserveUints(touched, touched_capacity, blocks);
  reserveUints(touched_list, touched_list_capacity, blocks);
  const GLuint zero = 0;
  if (fresh || !accumulators_zero) {
    glClearNamedBufferData(accumulators.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glClearNamedBufferData(touched.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  accumulators_zero = false;
  glClearNamedBufferData(counter.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  if (seen_word_count > 0) {
    reserveUints(seen, seen_capacity, seen_word_count);
    glClearNamedBufferSubData(seen.id(), GL_R32UI, 0,
                              GLsizeiptr(seen_word_count * sizeof(uint32_t)), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
  }
}

Aabb IndexMapRenderer::Impl::levelBounds() const {
  Aabb bounds = static_bounds;
  for (const Vec3& v : {dynamic_bounds.min, dynamic_bounds.max}) {
    if (dynamic_bounds.empty()) break;
    bounds.min = {std::min(bounds.min.x, v.x), std::min(bounds.min.y, v.y),
                  std::min(bounds.min.z, v.z)};
    bounds.max = {std::max(bounds.max.x, v.x), std::max(bounds.max.y, v.y),
                  std::max(bounds.max.z, v.z)};
  }
  return bounds;
}

void IndexMapRenderer::Impl::renderBatches(std::span<const PointSample> sample_list,
                                           const Aabb& bounds, double diagonal,
                                           GatherStats& stats) {
  std::vector<PreparedSample> batch;
  batch.reserve(size_t(settings.max_batch_samples));
  const size_t batch_size = size_t(settings.max_batch_samples);
  for (size_t begin = 0; begin < sample_list.size(); begin += batch_size) {
    const size_t end = std::min(sample_list.size(), begin + batch_size);
    batch.clear();
    batch_samples.clear();
    batch_layers.clear();
    for (size_t i = begin; i < end; ++i) {
      batch.push_back(prepare(sample_list[i], uint32_t(i - begin), bounds, diagonal));
      batch_samples.push_back(batch.back().gpu);
    }
    glNamedBufferSubData(samples.id(), 0, GLsizeiptr(batch_samples.size() * sizeof(SampleGpu)),
                         batch_samples.data());
    auto t0 = Clock::now();
    render(batch, stats);
    glFinish();
    stats.render_ms += msSince(t0);
    glNamedBufferSubData(layers.id(), 0, GLsizeiptr(batch_layers.size() * sizeof(batch_layers[0])),
                         batch_layers.data());
    t0 = Clock::now();
    reduceBatch(batch);
    glFinish();
    stats.reduce_ms += msSince(t0);
    stats.samples += uint32_t(batch.size());
  }
}

uint32_t IndexMapRenderer::Impl::compactSums(size_t blocks, size_t cells, GatherStats& stats) {
  uint32_t counts[2] = {0, 0};  // credited triangles, listed blocks
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  glGetNamedBufferSubData(counter.id(), 0, sizeof counts, counts);
  stats.fallback_triangles = counts[0];
  const uint32_t listed = std::min<uint32_t>(counts[1], uint32_t(blocks));
  compactTouched(listed, cells);
  return listed;
}

void IndexMapRenderer::Impl::unpackShares(uint32_t listed, size_t cells,
                                          std::vector<float>& shares) const {
  shares.assign(cells, 0.0f);
  for (size_t i = 0; i < listed; ++i) {
    const size_t first = size_t(touched_blocks[i]) * kCellBlock;
    const uint32_t* words = readback.data() + 2 * kCellBlock * i;
    for (size_t c = 0; c < kCellBlock && first + c < cells; ++c) {
      const double fixed = double(words[2 * c + 1]) * 4294967296.0 + double(words[2 * c]);
      shares[first + c] = float(fixed / kFixedPoint);
    }
  }
}

namespace {

// The view pass's frustum: |right.d| <= tx forward.d, |up.d| <= ty
// forward.d, forward.d >= near.
Frustum viewFrustum(const ViewFrame& view) {
  Frustum frustum;
  frustum.eye = glm::dvec3(view.eye.x, view.eye.y, view.eye.z);
  const glm::dvec3 r(view.right.x, view.right.y, view.right.z), u(view.up.x, view.up.y, view.up.z),
      f(view.forward.x, view.forward.y, view.forward.z);
  const double tx = view.tan_half_x, ty = view.tan_half_y;
  frustum.normal = {f * tx - r, f * tx + r, f * ty - u, f * ty + u, f, f};
  frustum.offset = {0, 0, 0, 0, double(view.near_m), double(view.near_m)};
  frustum.count = 5;
  return frustum;
}

Status checkView(const ViewFrame& view, int width, int height) {
  if (width < 1 || height < 1 || width > 4096 || height > 4096) {
    return Status(StatusCode::kInvalidInput, "index map view pass: " + std::to_string(width) +
                                                 " x " + std::to_string(height) +
                                                 " pixels is outside 1..4096");
  }
  const float values[] = {view.eye.x,      view.eye.y,      view.eye.z,     view.right.x,
                          view.right.y,    view.right.z,    view.up.x,      view.up.y,
                          view.up.z,       view.forward.x,  view.forward.y, view.forward.z,
                          view.tan_half_x, view.tan_half_y, view.near_m};
  for (float v : values) {
    if (!std::isfinite(v))
      return Status(StatusCode::kInvalidInput, "index map view pass: the view is not finite");
  }
  if (!(view.tan_half_x > 0 && view.tan_half_y > 0 && view.near_m > 0)) {
    return Status(StatusCode::kInvalidInput,
                  "index map view pass: field of view and near plane must be positive");
  }
  return Status();
}

}  // namespace

Status IndexMapRenderer::countViewPixels(const ViewFrame& view, int width, int height,
                                         std::vector<uint32_t>& pixels) {
  Impl& m = *impl_;
  if (!m.static_error.ok()) return m.static_error;
  if (!m.dynamic_error.ok()) return m.dynamic_error;
  if (Status s = checkView(view, width, height); !s.ok()) return s;
  m.ensureViewTarget(width, height);
  {
    StateGuard guard;
    setIdRasterState(false);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.view_fbo.id());
    glViewport(0, 0, width, height);
    const GLuint clear_id[4] = {kNoReceiver, kNoTriangle, 0, 0};
    const GLfloat clear_depth = 0.0f;
    glClearBufferuiv(GL_COLOR, 0, clear_id);
    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
    if (m.triangleCount() > 0) m.rasterView(view, width, height);
  }
  const size_t count = size_t(width) * size_t(height);
  m.view_readback.resize(2 * count);
  glGetTextureImage(m.view_ids.id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                    GLsizei(m.view_readback.size() * sizeof(uint32_t)), m.view_readback.data());
  pixels.assign(m.receiver_count, 0u);
  for (size_t i = 0; i < count; ++i) {
    const uint32_t r = m.view_readback[2 * i];
    if (r < m.receiver_count) ++pixels[r];
  }
  return checkGlError("IndexMapRenderer::countViewPixels");
}

void IndexMapRenderer::Impl::ensureViewTarget(int width, int height) {
  if (width == view_width && height == view_height) return;
  view_fbo.reset();
  view_ids.reset();
  view_depth.reset();
  view_ids = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(view_ids.id(), 1, GL_RG32UI, width, height);
  view_depth = createGlTexture(GL_TEXTURE_2D);
  glTextureStorage2D(view_depth.id(), 1, GL_DEPTH_COMPONENT32F, width, height);
  view_fbo = createGlFramebuffer();
  glNamedFramebufferTexture(view_fbo.id(), GL_COLOR_ATTACHMENT0, view_ids.id(), 0);
  glNamedFramebufferTexture(view_fbo.id(), GL_DEPTH_ATTACHMENT, view_depth.id(), 0);
  glNamedFramebufferDrawBuffer(view_fbo.id(), GL_COLOR_ATTACHMENT0);
  view_width = width;
  view_height = height;
  ++allocations;
}

void IndexMapRenderer::Impl::rasterView(const ViewFrame& view, int width, int height) {
  const GLuint program = raster.id();
  glUseProgram(program);
  glBindVertexArray(vao.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, receivers.id());
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
  // Only the runs that may meet the view's frustum.
  const Frustum frustum = viewFrustum(view);
  const glm::dvec3 no_box_lo(1.0), no_box_hi(0.0);
  auto draw = [&](std::span<const uint32_t> list) { drawChunks(list, kNoTriangle); };
  candidateChunks(chunks, frustum, no_box_lo, no_box_hi, nullptr, face_chunks);
  if (!settings.occlusion_culling || face_chunks.size() < kOcclusionMinChunks) {
    draw(face_chunks);
    return;
  }
  // As the maps' faces: the nearest chunks, then what they leave in view.
  std::vector<uint32_t> rest;
  splitNearest(chunks, face_chunks, frustum.eye, occlusionFirstTriangles(chunks, face_chunks),
               near_chunks, rest);
  draw(near_chunks);
  depth_scratch.resize(size_t(width) * size_t(height));
  glGetTextureImage(view_depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    GLsizei(depth_scratch.size() * sizeof(float)), depth_scratch.data());
  buildDepthPyramid(depth_scratch, width, height, 0, pyramid);
  const glm::dvec3 r(view.right.x, view.right.y, view.right.z), u(view.up.x, view.up.y, view.up.z),
      f(view.forward.x, view.forward.y, view.forward.z);
  const double tx = view.tan_half_x, ty = view.tan_half_y;
  const FaceProjection face{frustum.eye, r, u, f, 1.0 / tx, 1.0 / ty, double(view.near_m)};
  keepUnhidden(rest, face, face_chunks);
  draw(face_chunks);
}

std::vector<GlObject> IndexMapRenderer::mapObjects() const {
  const Impl& m = *impl_;
  std::vector<GlObject> out = {glTextureObject(m.id_map.id()), glTextureObject(m.depth_map.id())};
  for (const GlBuffer* b :
       {&m.positions, &m.receivers, &m.accumulators, &m.samples, &m.layers, &m.small_flags,
        &m.counter, &m.pairs, &m.seen, &m.set_indices, &m.touched, &m.touched_list, &m.packed}) {
    out.push_back(glBufferObject(b->id()));
  }
  return out;
}

std::vector<GlObject> IndexMapRenderer::viewObjects() const {
  return {glTextureObject(impl_->view_ids.id()), glTextureObject(impl_->view_depth.id())};
}

uint64_t IndexMapRenderer::hostBytes() const {
  const Impl& m = *impl_;
  auto bytes = [](const auto& v) { return uint64_t(v.capacity()) * sizeof(v[0]); };
  return bytes(m.static_positions) + bytes(m.dynamic_positions) + bytes(m.static_receivers) +
         bytes(m.dynamic_receivers) + bytes(m.static_chunks) + bytes(m.chunks) + bytes(m.readback) +
         bytes(m.view_readback) + bytes(m.batch_samples) + bytes(m.batch_layers) +
         bytes(m.batch_pairs) + bytes(m.batch_indices) + bytes(m.face_index_ranges) +
         bytes(m.touched_blocks) + bytes(m.dynamic_part_starts) + bytes(m.seen_boxes);
}

}  // namespace svit::gl

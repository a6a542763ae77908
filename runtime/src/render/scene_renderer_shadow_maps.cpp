// Depth shadow maps of the lights shaded per pixel (runtime lights on all
// geometry; baked lights and the sun on dynamic objects). Soft edges come
// from multi-tap PCF in svit_shading.frag; here the maps are rendered with
// a slope-scaled polygon offset (the shader adds a normal offset too).

#include "scene_renderer_shadow_maps.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "scene/glm_interop.h"
#include "scene_renderer_bindings.h"

namespace svit::gl {
namespace {

constexpr float kKindNone = 0, kKindCube = 1, kKindFace = 2;
// A spot narrower than this half angle fits one perspective face (with
// kSpotMargin to spare for the PCF taps at the cone's edge).
constexpr float kMaxFaceSpotRad = 0.7853981634f;  // 45 degrees
constexpr float kSpotMarginRad = 0.0349f;         // 2 degrees

// GL's cube-map face order and orientations (OpenGL 4.5 spec table 8.19):
// rendering each face with these views makes texture(samplerCube, d) find
// the texel d points at.
const glm::vec3 kCubeForward[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                   {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
const glm::vec3 kCubeUp[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1},
                              {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};

glm::vec3 anyPerpendicular(const glm::vec3& v) {
  return std::abs(v.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

// Near and far planes (metres) enclosing `bounds` as seen from `p`. Near is
// a fixed ratio of far: 1e-4 keeps fp32 depth precise to ~1e-3 of distance.
std::pair<float, float> nearFar(const glm::vec3& p, const Aabb& bounds) {
  float far_m = 0;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 corner((c & 1) ? bounds.max.x : bounds.min.x,
                           (c & 2) ? bounds.max.y : bounds.min.y,
                           (c & 4) ? bounds.max.z : bounds.min.z);
    far_m = std::max(far_m, glm::length(corner - p));
  }
  far_m = std::max(far_m * 1.01f, 1e-3f);
  return {far_m * 1e-4f, far_m};
}

}  // namespace

Expected<LightShadowMaps> LightShadowMaps::create(int map_size) {
  if (map_size < 16 || map_size > 8192) {
    return Status(StatusCode::kInvalidInput,
                  "shadow_map_size " + std::to_string(map_size) + " is outside 16..8192");
  }
  LightShadowMaps out;
  Expected<GlProgram> program = linkProgram({"shadow_depth.vert", "shadow_depth.frag"});
  if (!program.ok()) return program.status();
  out.program_ = std::move(program).value();
  out.map_size_ = map_size;
  return out;
}

LightShadowMaps::LightShadowMaps(LightShadowMaps&& other) noexcept { *this = std::move(other); }

LightShadowMaps& LightShadowMaps::operator=(LightShadowMaps&& other) noexcept {
  if (this != &other) {
    release();
    program_ = std::move(other.program_);
    map_size_ = other.map_size_;
    framebuffer_ = std::move(other.framebuffer_);
    cube_array_ = std::move(other.cube_array_);
    face_array_ = std::move(other.face_array_);
    lights_buffer_ = std::move(other.lights_buffer_);
    cube_capacity_ = std::exchange(other.cube_capacity_, 0);
    face_capacity_ = std::exchange(other.face_capacity_, 0);
    light_capacity_ = std::exchange(other.light_capacity_, 0);
    box_vao_ = std::move(other.box_vao_);
    box_buffer_ = std::move(other.box_buffer_);
    box_query_ = std::move(other.box_query_);
    box_capacity_ = std::exchange(other.box_capacity_, 0);
    gpu_lights_ = std::move(other.gpu_lights_);
    dynamic_only_ = std::move(other.dynamic_only_);
    rendered_keys_ = std::move(other.rendered_keys_);
  }
  return *this;
}

LightShadowMaps::~LightShadowMaps() { release(); }

void LightShadowMaps::release() {
  framebuffer_.reset();
  cube_array_.reset();
  face_array_.reset();
  lights_buffer_.reset();
  box_buffer_.reset();
  box_vao_.reset();
  box_query_.reset();
  cube_capacity_ = face_capacity_ = light_capacity_ = 0;
  box_capacity_ = 0;
}

void LightShadowMaps::ensureCapacity(uint32_t cubes, uint32_t faces) {
  auto makeDepthArray = [&](GLenum target, uint32_t layers) {
    GlTexture owned = createGlTexture(target);
    const GLuint texture = owned.id();
    glTextureStorage3D(texture, 1, GL_DEPTH_COMPONENT32F, map_size_, map_size_, GLsizei(layers));
    // Hardware 2x2 PCF under each of the shader's taps.
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(texture, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return owned;
  };
  if (cubes > cube_capacity_) {
    cube_array_.reset();
    cube_capacity_ = std::max(cubes, cube_capacity_ * 2);
    cube_array_ = makeDepthArray(GL_TEXTURE_CUBE_MAP_ARRAY, cube_capacity_ * 6);
    rendered_keys_.clear();  // the old maps are gone
  }
  if (faces > face_capacity_) {
    face_array_.reset();
    face_capacity_ = std::max(faces, face_capacity_ * 2);
    face_array_ = makeDepthArray(GL_TEXTURE_2D_ARRAY, face_capacity_);
    rendered_keys_.clear();
  }
  if (!framebuffer_ && (cubes > 0 || faces > 0)) {
    framebuffer_ = createGlFramebuffer();
    glNamedFramebufferDrawBuffer(framebuffer_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(framebuffer_.id(), GL_NONE);
  }
}

void LightShadowMaps::setDepthState(bool write) const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, map_size_, map_size_);
  glUseProgram(program_.id());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(write ? GL_TRUE : GL_FALSE);
  glDisable(GL_CULL_FACE);  // backs absorb light too (the baker's rule)
  if (write) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 4.0f);
  } else {
    glDisable(GL_POLYGON_OFFSET_FILL);  // tests against the stored (offset) depths
  }
}

void LightShadowMaps::forEachFace(size_t light, const glm::mat4& face_view,
                                  const std::function<void()>& draw) const {
  const GpuLight& g = gpu_lights_[light];
  auto face = [&](GLuint texture, int layer, const glm::mat4& clip_from_world) {
    glNamedFramebufferTextureLayer(framebuffer_.id(), GL_DEPTH_ATTACHMENT, texture, 0, layer);
    glUniformMatrix4fv(render_binding::kShadowClipFromWorld, 1, GL_FALSE,
                       glm::value_ptr(clip_from_world));
    draw();
  };
  if (g.shadow[0] == kKindFace) {
    face(face_array_.id(), int(g.shadow[1]), face_view);
    return;
  }
  const glm::vec3 p(g.position[0], g.position[1], g.position[2]);
  const glm::mat4 projection =
      glm::perspective(glm::radians(90.0f), 1.0f, g.shadow[2], g.shadow[3]);
  for (int f = 0; f < 6; ++f) {
    face(cube_array_.id(), int(g.shadow[1]) * 6 + f,
         projection * glm::lookAt(p, p + kCubeForward[f], kCubeUp[f]));
  }
}

uint32_t LightShadowMaps::uploadBoxes(const std::vector<Aabb>& boxes) {
  std::vector<glm::vec3> corners;
  corners.reserve(boxes.size() * 36);
  // Two triangles per face of each box (winding is irrelevant: no culling).
  static constexpr int kFaces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const Aabb& b : boxes) {
    glm::vec3 c[8];
    for (int k = 0; k < 8; ++k) {
      c[k] = {(k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
              (k & 4) ? b.max.z : b.min.z};
    }
    for (const auto& f : kFaces) {
      for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) corners.push_back(c[k]);
    }
  }
  if (corners.size() > box_capacity_) {
    box_buffer_.reset();
    box_capacity_ = std::max(corners.size(), box_capacity_ * 2);
    box_buffer_ = createGlBuffer();
    glNamedBufferStorage(box_buffer_.id(), GLsizeiptr(box_capacity_ * sizeof(glm::vec3)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    if (!box_vao_) {
      box_vao_ = createGlVertexArray();
      glEnableVertexArrayAttrib(box_vao_.id(), 0);
      glVertexArrayAttribFormat(box_vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(box_vao_.id(), 0, 0);
    }
    glVertexArrayVertexBuffer(box_vao_.id(), 0, box_buffer_.id(), 0, sizeof(glm::vec3));
  }
  if (!box_query_) box_query_ = createGlQuery(GL_ANY_SAMPLES_PASSED);
  if (!corners.empty()) {
    glNamedBufferSubData(box_buffer_.id(), 0, GLsizeiptr(corners.size() * sizeof(glm::vec3)),
                         corners.data());
  }
  return uint32_t(corners.size());
}

bool LightShadowMaps::boxesSeen(size_t light, uint32_t box_vertices,
                                const glm::mat4& face_view) const {
  setDepthState(false);
  glBindVertexArray(box_vao_.id());
  glBeginQuery(GL_ANY_SAMPLES_PASSED, box_query_.id());
  forEachFace(light, face_view, [&] { glDrawArrays(GL_TRIANGLES, 0, GLsizei(box_vertices)); });
  glEndQuery(GL_ANY_SAMPLES_PASSED);
  glDepthMask(GL_TRUE);
  GLuint passed = 1;
  glGetQueryObjectuiv(box_query_.id(), GL_QUERY_RESULT, &passed);
  return passed != 0;
}

uint32_t LightShadowMaps::update(const std::vector<FrameLight>& lights, const Aabb& scene_bounds,
                                 const Aabb& dynamic_bounds, bool casters_changed,
                                 const std::vector<Aabb>* moved_boxes,
                                 const DrawCasters& draw_casters) {
  std::vector<glm::mat4> face_views(lights.size());
  const MapCounts counts = layOutLights(lights, scene_bounds, dynamic_bounds, face_views);
  ensureCapacity(counts.cubes, counts.faces);
  uploadLights();
  std::vector<Aabb> light_bounds(lights.size());
  for (size_t i = 0; i < lights.size(); ++i)
    light_bounds[i] = lights[i].dynamic_casters_only ? dynamic_bounds : scene_bounds;
  return renderMaps(light_bounds, face_views, casters_changed, moved_boxes, draw_casters);
}

void LightShadowMaps::layOutMap(const Light& l, const Aabb& bounds, bool fit_cone, GpuLight& g,
                                glm::mat4& view, MapCounts& counts) const {
  const glm::vec3 p = toGlm(l.position);
  glm::vec3 d = toGlm(l.direction);
  d = glm::length(d) > 0 ? glm::normalize(d) : glm::vec3(0, -1, 0);
  const glm::vec3 lo = toGlm(bounds.min), hi = toGlm(bounds.max);
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  if (l.type == LightType::kDirectional) {
    const glm::vec3 eye = centre - d * (radius * 1.05f);
    view = glm::ortho(-radius, radius, -radius, radius, 0.0f, radius * 2.1f) *
           glm::lookAt(eye, centre, anyPerpendicular(d));
    g.shadow[0] = kKindFace, g.shadow[1] = float(counts.faces++), g.shadow[2] = 0,
    g.shadow[3] = radius * 2.1f;
    g.shadow_texel[1] = 2.0f * radius / float(map_size_);
    return;
  }
  const float to_centre = glm::length(centre - p);
  if (fit_cone && to_centre > radius * 1.05f) {
    // The cone from the light around the casters' sphere: texels over them only.
    const glm::vec3 axis = (centre - p) / to_centre;
    const float half = std::asin(std::min(radius / to_centre, 1.0f)) + kSpotMarginRad;
    const float far_m = to_centre + radius, near_m = std::max(to_centre - radius, far_m * 1e-4f);
    view = glm::perspective(2.0f * half, 1.0f, near_m, far_m) *
           glm::lookAt(p, centre, anyPerpendicular(axis));
    g.shadow[0] = kKindFace, g.shadow[1] = float(counts.faces++), g.shadow[2] = near_m,
    g.shadow[3] = far_m;
    g.shadow_texel[0] = 2.0f * std::tan(half) / float(map_size_);
    return;
  }
  const auto [near_m, far_m] = nearFar(p, bounds);
  g.shadow[2] = near_m, g.shadow[3] = far_m;
  if (l.type == LightType::kSpot && l.outer_cone_rad <= kMaxFaceSpotRad) {
    const float fov = 2.0f * (l.outer_cone_rad + kSpotMarginRad);
    view = glm::perspective(fov, 1.0f, near_m, far_m) * glm::lookAt(p, p + d, anyPerpendicular(d));
    g.shadow[0] = kKindFace, g.shadow[1] = float(counts.faces++);
    g.shadow_texel[0] = 2.0f * std::tan(0.5f * fov) / float(map_size_);
  } else {
    g.shadow[0] = kKindCube, g.shadow[1] = float(counts.cubes++);
    g.shadow_texel[0] = 2.0f / float(map_size_);
  }
}

LightShadowMaps::MapCounts LightShadowMaps::layOutLights(const std::vector<FrameLight>& lights,
                                                         const Aabb& scene_bounds,
                                                         const Aabb& dynamic_bounds,
                                                         std::vector<glm::mat4>& face_views) {
  gpu_lights_.assign(lights.size(), GpuLight{});
  dynamic_only_.assign(lights.size(), 0);
  MapCounts counts;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& l = lights[i].light;
    GpuLight& g = gpu_lights_[i];
    const glm::vec3 p = toGlm(l.position);
    glm::vec3 d = toGlm(l.direction);
    d = glm::length(d) > 0 ? glm::normalize(d) : glm::vec3(0, -1, 0);
    const FrameLight& f = lights[i];
    const float type = f.area_sample                 ? 3.0f
                       : l.type == LightType::kPoint ? 0.0f
                       : l.type == LightType::kSpot  ? 1.0f
                                                     : 2.0f;
    const float cos_inner = std::cos(l.inner_cone_rad), cos_outer = std::cos(l.outer_cone_rad);
    std::memcpy(g.position, glm::value_ptr(glm::vec4(p, type)), sizeof g.position);
    const glm::vec4 direction = f.area_sample
                                    ? glm::vec4(toGlm(f.area_normal), float(f.area_offset))
                                    : glm::vec4(d, cos_outer);
    std::memcpy(g.direction, glm::value_ptr(direction), sizeof g.direction);
    const Rgb& c = f.rgb_intensity;
    const float intensity[4] = {c.r, c.g, c.b, f.area_sample ? float(f.area_samples) : cos_inner};
    std::memcpy(g.intensity, intensity, sizeof g.intensity);
    g.shadow_texel[2] = float(lights[i].mask_channel);
    g.shadow_texel[3] = float(lights[i].mask_owner);
    const bool dynamic_only = lights[i].dynamic_casters_only;
    dynamic_only_[i] = dynamic_only ? 1 : 0;
    const Aabb& bounds = dynamic_only ? dynamic_bounds : scene_bounds;
    if (!lights[i].casts_shadows || bounds.empty()) continue;
    layOutMap(l, bounds, dynamic_only, g, face_views[i], counts);
    std::memcpy(g.shadow_from_world, glm::value_ptr(face_views[i]), sizeof g.shadow_from_world);
  }
  return counts;
}

// The lights buffer: grows, never shrinks (no allocation in steady state).
void LightShadowMaps::uploadLights() {
  if (gpu_lights_.size() > light_capacity_) {
    lights_buffer_.reset();
    light_capacity_ = uint32_t(std::max<size_t>(gpu_lights_.size(), size_t(light_capacity_) * 2));
    lights_buffer_ = createGlBuffer();
    glNamedBufferStorage(lights_buffer_.id(), GLsizeiptr(light_capacity_ * sizeof(GpuLight)),
                         nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  if (!gpu_lights_.empty()) {
    glNamedBufferSubData(lights_buffer_.id(), 0, GLsizeiptr(gpu_lights_.size() * sizeof(GpuLight)),
                         gpu_lights_.data());
  }
}

// Renders the maps whose light changed, or whose light sees where the
// casters moved from or to.
uint32_t LightShadowMaps::renderMaps(const std::vector<Aabb>& light_bounds,
                                     const std::vector<glm::mat4>& face_views, bool casters_changed,
                                     const std::vector<Aabb>* moved_boxes,
                                     const DrawCasters& draw_casters) {
  uint32_t rendered = 0;
  rendered_keys_.resize(gpu_lights_.size());
  bool state_set = false;
  const bool test_boxes = casters_changed && moved_boxes != nullptr;
  const uint32_t box_vertices = test_boxes ? uploadBoxes(*moved_boxes) : 0;
  for (size_t i = 0; i < gpu_lights_.size(); ++i) {
    const GpuLight& g = gpu_lights_[i];
    if (g.shadow[0] == kKindNone) continue;
    std::vector<float> key(reinterpret_cast<const float*>(&g),
                           reinterpret_cast<const float*>(&g) + 4 * 5 + 16);
    const Aabb& bounds = light_bounds[i];
    key.insert(key.end(), {bounds.min.x, bounds.min.y, bounds.min.z, bounds.max.x, bounds.max.y,
                           bounds.max.z});
    if (rendered_keys_[i] == key) {
      if (!casters_changed) continue;
      if (test_boxes) {
        if (box_vertices == 0) continue;
        state_set = false;  // the test leaves its own state
        if (!boxesSeen(i, box_vertices, face_views[i])) continue;
      }
    }
    rendered_keys_[i] = std::move(key);
    if (!state_set) {
      state_set = true;
      setDepthState(true);
    }
    forEachFace(i, face_views[i], [&] {
      glClear(GL_DEPTH_BUFFER_BIT);
      draw_casters(dynamic_only_[i] != 0);
    });
    ++rendered;
  }
  if (state_set) glDisable(GL_POLYGON_OFFSET_FILL);
  return rendered;
}

void LightShadowMaps::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, render_binding::kLights, lights_buffer_.id());
  glBindTextureUnit(render_binding::kShadowCubeUnit, cube_array_.id());
  glBindTextureUnit(render_binding::kShadowFaceUnit, face_array_.id());
}

}  // namespace svit::gl

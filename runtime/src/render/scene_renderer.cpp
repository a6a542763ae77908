// svit::SceneRenderer: one forward pass over the static mesh (lightmap +
// interpolated runtime deltas + runtime lights) and the dynamic objects
// (probe grid + lights + the runtime's patch deltas), tone mapped in the
// shaders into an RGBA8 target, with the linear radiance beside it in an
// RGBA32F one (docs/architecture/runtime-render.md "Drawing"). Everything
// that depends only on the level is built in create(); a frame allocates GL
// objects only when something grows (more dynamic triangles or lights than
// before), and does no work for features the level lacks.

#include "svit/scene_renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <optional>
#include <utility>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "facade/runtime_checks.h"
#include "gl/gl_handle.h"
#include "gl/gl_memory.h"
#include "gl/gl_program.h"
#include "gl/shader_sources.h"
#include "scene/glm_interop.h"
#include "scene/numeric.h"
#include "scene_renderer_bindings.h"
#include "scene_renderer_dynamic_objects.h"
#include "scene_renderer_lightmaps.h"
#include "scene_renderer_masks.h"
#include "scene_renderer_materials.h"
#include "scene_renderer_probe_grid.h"
#include "scene_renderer_shadow_maps.h"
#include "scene_renderer_static_mesh.h"
#include "scene_renderer_target.h"
#include "svit/gl_context.h"
#include "svit/runtime.h"

namespace svit {
namespace {

namespace b = gl::render_binding;

// Auto exposure: a white surface at the lightmaps' log-mean irradiance E
// has radiance E/pi; it is scaled to kExposureKey before the filmic curve,
// which puts typical walls (albedo ~0.7) at ~0.55 display value and leaves
// headroom for the lit spots the log-mean discounts.
constexpr double kExposureKey = 0.35;

// A copy of what frames need from the level, so the caller's Scene need not
// outlive the renderer: materials, instances, lights, sun, and the meshes
// of dynamic instances (static meshes live on the GPU; textures too).
Scene frameSceneOf(const Scene& scene) {
  Scene out;
  out.source_path = scene.source_path;
  out.materials = scene.materials;
  out.instances = scene.instances;
  out.lights = scene.lights;
  out.sun = scene.sun;
  out.meshes.resize(scene.meshes.size());
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic && instance.mesh >= 0 && size_t(instance.mesh) < scene.meshes.size()) {
      out.meshes[size_t(instance.mesh)] = scene.meshes[size_t(instance.mesh)];
    }
  }
  return out;
}

bool sceneHasDynamicInstances(const Scene& scene) {
  return std::any_of(scene.instances.begin(), scene.instances.end(),
                     [](const Instance& i) { return i.dynamic; });
}

Status validateSettings(const SceneRendererSettings& s) {
  auto bad = [](const std::string& what) {
    return Status(StatusCode::kInvalidInput, "SceneRendererSettings: " + what);
  };
  if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384) {
    return bad("size " + std::to_string(s.width) + "x" + std::to_string(s.height) +
               " is outside 1..16384");
  }
  if (!(s.exposure > 0) || !std::isfinite(s.exposure))
    return bad("exposure " + std::to_string(s.exposure) + " is not > 0");
  if (s.shadow_map_size < 16 || s.shadow_map_size > 8192) {
    return bad("shadow_map_size " + std::to_string(s.shadow_map_size) + " is outside 16..8192");
  }
  if (s.shadow_taps < 1 || s.shadow_taps > 256)
    return bad("shadow_taps " + std::to_string(s.shadow_taps) + " is outside 1..256");
  return Status();
}

// What both lit passes of a frame share.
struct FramePass {
  glm::mat4 clip_from_world;
  ShadingView view;
  int baked_lights = 0;  // FrameLights before the runtime's
  int light_count = 0;   // baked and runtime lights (the masked ones follow)
  int masked_end = 0;    // masked baked lights are [light_count, masked_end)
};

// A camera that can be drawn from, or an error naming what is wrong.
Status checkCamera(const Camera& camera) {
  auto error = [](const std::string& why) {
    return Status(StatusCode::kInvalidInput, "SceneRenderer::render: camera " + why);
  };
  if (!finite(camera.position)) return error("position is not finite");
  if (!finite(camera.look_at)) return error("look_at is not finite");
  if (!finite(camera.up)) return error("up is not finite");
  const glm::vec3 eye = toGlm(camera.position), centre = toGlm(camera.look_at),
                  up = toGlm(camera.up);
  const glm::vec3 forward = centre - eye;
  if (!(glm::length(forward) > 0) || !(glm::length(glm::cross(forward, up)) > 0))
    return error("looks nowhere (look_at == position, or up zero or along the view)");
  if (!(camera.yfov_rad > 0 && camera.yfov_rad < float(kPi)))
    return error("yfov_rad " + std::to_string(camera.yfov_rad) + " is outside (0, pi)");
  if (!(camera.near_m > 0 && camera.far_m > camera.near_m && finite(camera.far_m))) {
    return error("near/far " + std::to_string(camera.near_m) + "/" + std::to_string(camera.far_m) +
                 " needs 0 < near < far < infinity");
  }
  return Status();
}

Status checkShadingView(ShadingView view) {
  if (view == ShadingView::kBakedOnly || view == ShadingView::kRuntime ||
      view == ShadingView::kPatchDelta)
    return Status();
  return Status(StatusCode::kInvalidInput, "SceneRenderer::render: view " +
                                               std::to_string(int(view)) +
                                               " is not a ShadingView (0, 1 or 2)");
}

// A side with a lightmap of its own is drawn with the other side culled.
void setDrawnSides(gl::DrawnSides sides) {
  if (sides == gl::DrawnSides::kBoth) {
    glDisable(GL_CULL_FACE);
    return;
  }
  glEnable(GL_CULL_FACE);
  glCullFace(sides == gl::DrawnSides::kFront ? GL_BACK : GL_FRONT);
}

}  // namespace

struct SceneRenderer::Impl {
  Scene scene;  // frameSceneOf() the level
  const Runtime* runtime = nullptr;
  SceneRendererSettings settings;

  std::vector<gl::StaticBatch> batches;
  uint32_t static_vertex_count = 0;
  Aabb static_bounds;
  gl::GlVertexArray static_vao;
  gl::GlBuffer static_buffer;

  gl::GlProgram static_program, dynamic_program;
  gl::LightmapTextures lightmaps;
  gl::ShadowMaskTextures masks;
  std::vector<BakeMaskedLight> masked_lights;
  std::vector<BakeEmitter> masked_emitters;  // each masked light's bake emitter
  MaskedLightField masked_field;             // their parameters; areas' samples
  gl::AreaLightBuffer area_lights;
  gl::MaterialTextures materials;
  gl::LightShadowMaps shadows;
  gl::ProbeGridTextures probes;
  gl::DynamicObjectMeshes dynamic_objects;
  gl::OffscreenTarget target;
  bool has_offscreen_frame = false;

  // Bake emitters as the host scaled them (setBakedEmitterScale), and which
  // baked light / the sun each stands for (-1: none; kLight emitters carry
  // the Scene::lights index).
  std::vector<float> emitter_scale;
  std::vector<int> light_emitter;  // per Scene::lights entry
  int sun_emitter = -1;

  float exposure = 1;
  float delta_reference_lux = 1;

  void uploadStaticMesh(const gl::StaticMesh& mesh);
  float emitterScale(int emitter) const {
    return emitter >= 0 ? emitter_scale[size_t(emitter)] : 1.0f;
  }
  std::vector<gl::FrameLight> frameLights(bool with_runtime_lights, bool with_baked_lights,
                                          bool scale_baked, size_t* baked_count) const;
  /// Appends the masked baked lights (scaled like their emitters when
  /// `scale_baked`; caster maps of the dynamic objects when `with_casters`).
  void appendMaskedLights(bool scale_baked, bool with_casters,
                          std::vector<gl::FrameLight>& lights) const;
  void appendAreaSamples(size_t k, float dimmer, bool with_casters,
                         std::vector<gl::FrameLight>& lights) const;
  Expected<double> loadMaskedLights(const Scene& level, const BakeData& bake,
                                    const std::string& bake_dir);
  gl::FrameLight sunLight(float dimmer) const;
  void setSharedUniforms(const glm::mat4& clip_from_world, ShadingView view, int light_begin,
                         int light_end) const;

  // render()'s stages: the shadow maps of `lights` (casters: everything
  // drawn); the target bound, its state set and cleared; the static mesh's
  // batches; the dynamic objects; the target released.
  void renderShadowMaps(const std::vector<gl::FrameLight>& lights, bool has_dynamic,
                        bool casters_changed, RenderStats& stats);
  void beginFrame(bool to_default_framebuffer) const;
  void drawStatic(const FramePass& pass, const ShadingResources& resources, bool runtime_view,
                  RenderStats& stats) const;
  void drawDynamic(const FramePass& pass, uint32_t delta_buffer, RenderStats& stats) const;
  void endFrame(bool to_default_framebuffer) const;
};

void SceneRenderer::Impl::uploadStaticMesh(const gl::StaticMesh& mesh) {
  batches = mesh.batches;
  static_vertex_count = uint32_t(mesh.vertices.size());
  static_bounds = mesh.bounds;
  static_buffer = gl::createGlBuffer();
  glNamedBufferStorage(static_buffer.id(),
                       GLsizeiptr(mesh.vertices.size() * sizeof(gl::StaticVertex)),
                       mesh.vertices.data(), 0);
  static_vao = gl::createGlVertexArray();
  const GLuint vao = static_vao.id();
  struct Attribute {
    GLint size;
    GLuint offset;
  };
  const Attribute floats[5] = {{3, offsetof(gl::StaticVertex, position)},
                               {3, offsetof(gl::StaticVertex, normal)},
                               {2, offsetof(gl::StaticVertex, uv0)},
                               {2, offsetof(gl::StaticVertex, uv1)},
                               {2, offsetof(gl::StaticVertex, uv_lightmap)}};
  for (GLuint a = 0; a < 5; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, floats[a].size, GL_FLOAT, GL_FALSE, floats[a].offset);
    glVertexArrayAttribBinding(vao, a, 0);
  }
  glEnableVertexArrayAttrib(vao, 5);
  glVertexArrayAttribIFormat(vao, 5, 2, GL_UNSIGNED_INT, offsetof(gl::StaticVertex, delta_element));
  glVertexArrayAttribBinding(vao, 5, 0);
  glVertexArrayVertexBuffer(vao, 0, static_buffer.id(), 0, sizeof(gl::StaticVertex));
}

// Baked lights first (stable slots: their maps survive view switches and
// dimming to 0), scaled like their bake emitters when `scale_baked`, then
// the runtime's enabled lights.
std::vector<gl::FrameLight> SceneRenderer::Impl::frameLights(bool with_runtime_lights,
                                                             bool with_baked_lights,
                                                             bool scale_baked,
                                                             size_t* baked_count) const {
  std::vector<gl::FrameLight> lights;
  auto scaled = [](const Light& l, float dimmer) {
    const float s = l.intensity * dimmer;
    return Rgb{l.color.r * s, l.color.g * s, l.color.b * s};
  };
  if (with_baked_lights) {
    for (size_t i = 0; i < scene.lights.size(); ++i) {
      const Light& l = scene.lights[i];
      const float dimmer = scale_baked ? emitterScale(light_emitter[i]) : 1.0f;
      if (!l.dynamic && l.intensity > 0) lights.push_back({l, scaled(l, dimmer), true});
    }
    if (scene.sun.enabled && scene.sun.illuminance_lux > 0)
      lights.push_back(sunLight(scale_baked ? emitterScale(sun_emitter) : 1.0f));
  }
  *baked_count = lights.size();
  if (with_runtime_lights) {
    if (runtime != nullptr) {
      for (LightId id : runtime->lights()) {
        Expected<RuntimeLightInfo> info = runtime->lightInfo(id);
        if (!info.ok() || !info->enabled || !(info->dimmer * info->light.intensity > 0)) continue;
        lights.push_back({info->light, scaled(info->light, info->dimmer), true});
      }
    } else {
      // No runtime: the level's runtime lights as the level places them.
      for (const Light& l : scene.lights) {
        if (l.dynamic && l.intensity > 0 && l.type != LightType::kDirectional)
          lights.push_back({l, scaled(l, 1.0f), true});
      }
    }
  }
  return lights;
}

// Area light k's point samples, each with a caster map: as many as the
// light's solid angle at the casters asks for (one without casters).
void SceneRenderer::Impl::appendAreaSamples(size_t k, float dimmer, bool with_casters,
                                            std::vector<gl::FrameLight>& lights) const {
  const Aabb& casters = dynamic_objects.bounds();
  const Vec3 centre{0.5f * (casters.min.x + casters.max.x), 0.5f * (casters.min.y + casters.max.y),
                    0.5f * (casters.min.z + casters.max.z)};
  const uint32_t count = with_casters ? masked_field.areaSampleCount(k, centre) : 1;
  for (const MaskedAreaSample& sample : masked_field.areaSamples(k, count)) {
    gl::FrameLight light;
    light.light = masked_field.light(k);
    light.light.position = sample.point;
    light.rgb_intensity = {dimmer, dimmer, dimmer};
    light.casts_shadows = with_casters;
    light.dynamic_casters_only = true;
    light.mask_channel = masked_lights[k].channel;
    light.mask_owner = masked_lights[k].owner;
    light.area_sample = true;
    light.area_normal = sample.normal;
    light.area_samples = count;
    light.area_offset = area_lights.offset(k);
    lights.push_back(light);
  }
}

gl::FrameLight SceneRenderer::Impl::sunLight(float dimmer) const {
  Light sun;
  sun.name = "sun";
  sun.type = LightType::kDirectional;
  sun.direction = {-scene.sun.direction_to_sun.x, -scene.sun.direction_to_sun.y,
                   -scene.sun.direction_to_sun.z};
  sun.color = scene.sun.color;
  sun.intensity = scene.sun.illuminance_lux;
  const float s = sun.intensity * dimmer;
  return {sun, Rgb{sun.color.r * s, sun.color.g * s, sun.color.b * s}, true};
}

void SceneRenderer::Impl::appendMaskedLights(bool scale_baked, bool with_casters,
                                             std::vector<gl::FrameLight>& lights) const {
  for (size_t k = 0; k < masked_lights.size(); ++k) {
    const BakeMaskedLight& m = masked_lights[k];
    const float dimmer = scale_baked ? emitterScale(int(m.emitter)) : 1.0f;
    if (masked_field.isArea(k)) {
      appendAreaSamples(k, dimmer, with_casters, lights);
      continue;
    }
    gl::FrameLight light;
    if (masked_emitters[k].kind == BakeEmitter::Kind::kSun) {
      light = sunLight(dimmer);
    } else {
      const Light& l = scene.lights[masked_emitters[k].index];
      const float s = l.intensity * dimmer;
      light = {l, Rgb{l.color.r * s, l.color.g * s, l.color.b * s}, true};
    }
    light.casts_shadows = with_casters;
    light.dynamic_casters_only = true;
    light.mask_channel = m.channel;
    light.mask_owner = m.owner;
    lights.push_back(light);
  }
}

void SceneRenderer::Impl::setSharedUniforms(const glm::mat4& clip_from_world, ShadingView view,
                                            int light_begin, int light_end) const {
  glUniformMatrix4fv(b::kClipFromWorld, 1, GL_FALSE, glm::value_ptr(clip_from_world));
  glUniform1i(b::kView, int(view));
  glUniform1f(b::kExposure, exposure);
  glUniform1i(b::kLightBegin, light_begin);
  glUniform1i(b::kLightEnd, light_end);
  glUniform1i(b::kShadowTaps, settings.shadow_taps);
  glUniform1f(b::kShadowTexel, 1.0f / float(settings.shadow_map_size));
  glUniform1f(b::kDeltaReference, delta_reference_lux);
}

// The bake's masked lights: their mask textures, emitters, parameters and
// area lights' triangles. Returns how much brighter they make the level
// than its lightmap (for auto exposure).
Expected<double> SceneRenderer::Impl::loadMaskedLights(const Scene& level, const BakeData& bake,
                                                       const std::string& bake_dir) {
  Expected<gl::ShadowMaskTextures> mask_textures = gl::ShadowMaskTextures::create(bake);
  if (!mask_textures.ok()) return mask_textures.status();
  masks = std::move(mask_textures).value();
  masked_lights = bake.masks.lights;
  for (const BakeMaskedLight& m : bake.masks.lights) {
    const BakeEmitter& e = bake.emitters[m.emitter];
    if (e.kind == BakeEmitter::Kind::kLight && e.index >= level.lights.size()) {
      return Status(StatusCode::kInvalidInput, bake_dir + "/bake.svit: section SMSK masks light " +
                                                   std::to_string(e.index) + " of a level with " +
                                                   std::to_string(level.lights.size()) + " lights");
    }
    masked_emitters.push_back({e.kind, e.index, e.flux, {}, {}});
  }
  Expected<gl::MaskedShading> masked = gl::prepareMaskedShading(level, bake, bake_dir);
  if (!masked.ok())
    return Status(masked.status().code(), bake_dir + ": " + masked.status().message());
  masked_field = std::move(masked->field);
  area_lights = gl::AreaLightBuffer::create(masked_field);
  return masked->exposure_ratio;
}

SceneRenderer::SceneRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SceneRenderer::~SceneRenderer() = default;

Expected<std::unique_ptr<SceneRenderer>> SceneRenderer::create(
    const Scene& scene, const BakeData& bake, const std::string& bake_dir, const Runtime* runtime,
    const SceneRendererSettings& settings) {
  Expected<GlContextInfo> context = checkGlContext();
  if (!context.ok())
    return Status(context.status().code(), "SceneRenderer: " + context.status().message());
  Status valid = validateSettings(settings);
  if (!valid.ok()) return valid;
  Expected<gl::StaticMesh> mesh = gl::buildStaticMesh(scene, bake);
  if (!mesh.ok())
    return Status(mesh.status().code(), bake_dir + "/bake.svit: " + mesh.status().message());

  auto impl = std::make_unique<Impl>();
  impl->scene = frameSceneOf(scene);
  impl->runtime = runtime;
  impl->settings = settings;
  impl->emitter_scale.assign(bake.emitters.size(), 1.0f);
  impl->light_emitter.assign(scene.lights.size(), -1);
  for (size_t e = 0; e < bake.emitters.size(); ++e) {
    const BakeEmitter& be = bake.emitters[e];
    if (be.kind == BakeEmitter::Kind::kLight && be.index < scene.lights.size())
      impl->light_emitter[be.index] = int(e);
    if (be.kind == BakeEmitter::Kind::kSun) impl->sun_emitter = int(e);
  }

  // The runtime already holds the pages on the GPU: share them.
  Expected<gl::LightmapTextures> lightmaps =
      runtime != nullptr && !bake.pages.empty()
          ? gl::LightmapTextures::borrow(bake, runtime->shadingResources().lightmap_textures)
          : gl::LightmapTextures::create(bake, bake_dir);
  if (!lightmaps.ok()) return lightmaps.status();
  impl->lightmaps = std::move(lightmaps).value();
  Expected<double> masked_exposure = impl->loadMaskedLights(scene, bake, bake_dir);
  if (!masked_exposure.ok()) return masked_exposure.status();
  Expected<gl::MaterialTextures> materials = gl::MaterialTextures::create(scene);
  if (!materials.ok()) return materials.status();
  impl->materials = std::move(materials).value();

  Expected<gl::GlProgram> static_program = gl::linkProgram(
      {"lit_static.vert", "lit_static.frag", "svit_shading.frag", "svit_runtime_delta.frag"});
  if (!static_program.ok()) return static_program.status();
  impl->static_program = std::move(static_program).value();
  Expected<gl::GlProgram> dynamic_program =
      gl::linkProgram({"lit_dynamic.vert", "lit_dynamic.frag", "svit_shading.frag"});
  if (!dynamic_program.ok()) return dynamic_program.status();
  impl->dynamic_program = std::move(dynamic_program).value();
  Expected<gl::LightShadowMaps> shadows = gl::LightShadowMaps::create(settings.shadow_map_size);
  if (!shadows.ok()) return shadows.status();
  impl->shadows = std::move(shadows).value();

  impl->uploadStaticMesh(*mesh);
  // Pay for what is used: probes only when dynamic objects can exist.
  if (runtime != nullptr || sceneHasDynamicInstances(scene)) {
    Expected<gl::ProbeGridTextures> probes = gl::ProbeGridTextures::create(bake.probes);
    if (!probes.ok()) return probes.status();
    impl->probes = std::move(probes).value();
  }
  Expected<gl::OffscreenTarget> target =
      gl::OffscreenTarget::create(settings.width, settings.height);
  if (!target.ok()) return target.status();
  impl->target = std::move(target).value();

  const double log_mean = impl->lightmaps.logMeanIrradiance() * *masked_exposure;
  impl->delta_reference_lux = log_mean > 0 ? float(log_mean) : 1.0f;
  impl->exposure = settings.auto_exposure && log_mean > 0
                       ? float(settings.exposure * kExposureKey * kPi / log_mean)
                       : settings.exposure;
  Status error = gl::checkGlError("SceneRenderer::create");
  if (!error.ok()) return error;
  return std::unique_ptr<SceneRenderer>(new SceneRenderer(std::move(impl)));
}

Expected<RenderStats> SceneRenderer::render(const Camera& camera, ShadingView view,
                                            bool to_default_framebuffer) {
  Impl& s = *impl_;
  const auto start = std::chrono::steady_clock::now();
  if (Status valid = checkCamera(camera); !valid.ok()) return valid;
  if (Status valid = checkShadingView(view); !valid.ok()) return valid;
  RenderStats stats;
  const bool runtime_view = view != ShadingView::kBakedOnly;

  // Runtime deltas (static: per runtime patch, looked up per pixel, or the
  // runtime's lightmap-space maps when it makes them; dynamic: per patch).
  const ShadingResources resources =
      runtime_view && s.runtime != nullptr ? s.runtime->shadingResources() : ShadingResources{};

  // Dynamic objects and the lights that shade per pixel.
  const bool casters_changed = s.dynamic_objects.update(s.scene, s.runtime);
  const bool has_dynamic = s.dynamic_objects.vertexCount() > 0;
  size_t baked_lights = 0;
  std::vector<gl::FrameLight> lights =
      s.frameLights(view == ShadingView::kRuntime, has_dynamic, runtime_view, &baked_lights);
  const size_t light_count = lights.size();
  // The baked-only view shows the bake as it is: no dynamic shadow, no dimmer.
  s.appendMaskedLights(runtime_view, runtime_view && has_dynamic, lights);
  if (!lights.empty()) s.renderShadowMaps(lights, has_dynamic, casters_changed, stats);

  // The frame.
  s.beginFrame(to_default_framebuffer);
  const int width = s.settings.width, height = s.settings.height;
  const glm::vec3 eye = toGlm(camera.position), centre = toGlm(camera.look_at),
                  up = toGlm(camera.up);
  FramePass pass;
  pass.clip_from_world =
      glm::perspective(camera.yfov_rad, float(width) / float(height), camera.near_m, camera.far_m) *
      glm::lookAt(eye, centre, up);
  pass.view = view;
  pass.baked_lights = int(baked_lights);
  pass.light_count = int(light_count);
  pass.masked_end = int(lights.size());
  if (!lights.empty()) s.shadows.bind();
  s.drawStatic(pass, resources, runtime_view, stats);
  if (has_dynamic) s.drawDynamic(pass, resources.patch_delta_buffer, stats);
  s.endFrame(to_default_framebuffer);
  Status error = gl::checkGlError("SceneRenderer::render");
  if (!error.ok()) return error;
  if (!to_default_framebuffer) s.has_offscreen_frame = true;
  stats.shading_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

void SceneRenderer::Impl::renderShadowMaps(const std::vector<gl::FrameLight>& lights,
                                           bool has_dynamic, bool casters_changed,
                                           RenderStats& stats) {
  Aabb bounds = static_bounds;
  if (has_dynamic) {
    const Aabb& d = dynamic_objects.bounds();
    bounds.min = {std::min(bounds.min.x, d.min.x), std::min(bounds.min.y, d.min.y),
                  std::min(bounds.min.z, d.min.z)};
    bounds.max = {std::max(bounds.max.x, d.max.x), std::max(bounds.max.y, d.max.y),
                  std::max(bounds.max.z, d.max.z)};
  }
  const std::vector<Aabb>& moved = dynamic_objects.movedBoxes();
  const Aabb dynamic_bounds = has_dynamic ? dynamic_objects.bounds() : Aabb{};
  stats.shadow_maps_rendered = shadows.update(
      lights, bounds, dynamic_bounds, casters_changed, &moved, [&](bool dynamic_only) {
        if (!dynamic_only) {
          glBindVertexArray(static_vao.id());
          glDrawArrays(GL_TRIANGLES, 0, GLsizei(static_vertex_count));
          ++stats.draw_calls;
        }
        if (has_dynamic) {
          dynamic_objects.draw();
          ++stats.draw_calls;
        }
      });
}

void SceneRenderer::Impl::beginFrame(bool to_default_framebuffer) const {
  glBindFramebuffer(GL_FRAMEBUFFER, to_default_framebuffer ? 0 : target.framebuffer());
  // The lit passes write display colour and radiance (the clear too).
  if (!to_default_framebuffer) target.drawRadiance(true);
  glViewport(0, 0, settings.width, settings.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);  // backs are drawn: black when single-sided, lit when double-sided
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!to_default_framebuffer) target.clearRadiance();  // surface kind 0 where nothing is drawn
}

// Static geometry: runtime lights and the masked baked lights per pixel
// (the other baked lights are in the lightmap).
void SceneRenderer::Impl::drawStatic(const FramePass& pass, const ShadingResources& resources,
                                     bool runtime_view, RenderStats& stats) const {
  const std::vector<uint32_t>& delta_maps = resources.delta_textures;
  const bool static_deltas = delta_maps.empty() && resources.vertex_deltas != 0;
  glUseProgram(static_program.id());
  setSharedUniforms(pass.clip_from_world, pass.view, pass.baked_lights,
                    pass.view == ShadingView::kRuntime ? pass.light_count : pass.baked_lights);
  glUniform1i(b::kUseDeltas, static_deltas ? 1 : 0);
  glUniform1i(b::kMaskedBegin, pass.light_count);
  glUniform1i(b::kMaskedEnd, masks.empty() ? pass.light_count : pass.masked_end);
  area_lights.bind();
  if (static_deltas) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b::kDeltaElements, resources.delta_elements);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b::kDeltaSlots, resources.delta_slots);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b::kVertexDeltas, resources.vertex_deltas);
  }
  glBindVertexArray(static_vao.id());
  uint32_t bound_material = UINT32_MAX;
  std::optional<uint32_t> bound_page;  // kUnlitBackPage is a page value too
  float bound_emission_scale = 1.0f;
  glUniform1f(b::kEmissionScale, 1.0f);
  gl::DrawnSides bound_sides = gl::DrawnSides::kBoth;  // culling off (beginFrame)
  for (const gl::StaticBatch& batch : batches) {
    if (batch.sides != bound_sides) {
      setDrawnSides(batch.sides);
      bound_sides = batch.sides;
    }
    if (batch.material != bound_material) {
      materials.bind(scene.materials[batch.material]);
      bound_material = batch.material;
    }
    // A dimmed lamp looks dimmed (the bake as baked in kBakedOnly).
    const float emission_scale = runtime_view && batch.emitter != gl::kNoBakeEmitter
                                     ? emitterScale(int(batch.emitter))
                                     : 1.0f;
    if (emission_scale != bound_emission_scale) {
      glUniform1f(b::kEmissionScale, emission_scale);
      bound_emission_scale = emission_scale;
    }
    if (batch.page != bound_page) {
      // A back no baked light reaches has no page: black but for the runtime.
      const bool unlit = batch.page == kUnlitBackPage;
      glUniform1i(b::kUnlitSide, unlit ? 1 : 0);
      if (!unlit) glBindTextureUnit(b::kLightmapUnit, lightmaps.texture(batch.page));
      if (!masks.empty() && !unlit)
        glBindTextureUnit(b::kShadowMaskUnit, masks.texture(batch.page));
      // The runtime's deltas in lightmap space, when it makes them.
      const bool delta_map = batch.page < delta_maps.size();
      glUniform1i(b::kUseDeltaMap, delta_map ? 1 : 0);
      if (delta_map) glBindTextureUnit(b::kDeltaMapUnit, delta_maps[batch.page]);
      bound_page = batch.page;
    }
    glDrawArrays(GL_TRIANGLES, GLint(batch.first_vertex), GLsizei(batch.vertex_count));
    ++stats.draw_calls;
  }
  setDrawnSides(gl::DrawnSides::kBoth);
}

// Dynamic objects: probes + baked lights, + runtime lights and deltas.
void SceneRenderer::Impl::drawDynamic(const FramePass& pass, uint32_t delta_buffer,
                                      RenderStats& stats) const {
  glUseProgram(dynamic_program.id());
  setSharedUniforms(pass.clip_from_world, pass.view, 0,
                    pass.view == ShadingView::kRuntime ? pass.light_count : pass.baked_lights);
  glUniform1i(b::kBakedLightEnd, pass.baked_lights);
  glUniform1i(b::kUseDeltas, delta_buffer != 0 ? 1 : 0);
  if (delta_buffer != 0) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b::kPatchDeltas, delta_buffer);
  probes.bind();
  dynamic_objects.draw();
  ++stats.draw_calls;
}

void SceneRenderer::Impl::endFrame(bool to_default_framebuffer) const {
  glBindVertexArray(0);
  glUseProgram(0);
  // A host's HUD drawn next writes output 0 only: with both attachments
  // drawn, its unwritten output 1 would leave undefined radiance.
  if (!to_default_framebuffer) target.drawRadiance(false);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glFinish();  // honest timings on any driver (RenderStats::shading_ms)
}

Status SceneRenderer::setBakedEmitterScale(uint32_t bake_emitter, float scale) {
  Impl& s = *impl_;
  if (bake_emitter >= s.emitter_scale.size()) {
    return Status(StatusCode::kNotFound, "SceneRenderer: no baked emitter " +
                                             std::to_string(bake_emitter) + " (the bake has " +
                                             std::to_string(s.emitter_scale.size()) + ")");
  }
  // The runtime's bounds, so that both take or refuse the same scales.
  if (Status valid = checkScale(
          scale, "SceneRenderer: baked emitter " + std::to_string(bake_emitter) + ": scale");
      !valid.ok())
    return valid;
  s.emitter_scale[bake_emitter] = scale;
  return Status();
}

uint32_t SceneRenderer::offscreenFramebuffer() const { return impl_->target.framebuffer(); }

std::vector<uint8_t> SceneRenderer::readPixels() const {
  if (!impl_->has_offscreen_frame) return {};
  return impl_->target.readRgb();
}

Status SceneRenderer::writePng(const std::string& path) const {
  if (!impl_->has_offscreen_frame)
    return Status(StatusCode::kInvalidInput, path + ": no offscreen frame rendered yet");
  return gl::writeRgbPng(path, impl_->target.width(), impl_->target.height(), readPixels());
}

std::vector<float> SceneRenderer::readRadiance() const {
  if (!impl_->has_offscreen_frame) return {};
  return impl_->target.readRadiance();
}

std::vector<uint8_t> SceneRenderer::readSurfaceKinds() const {
  if (!impl_->has_offscreen_frame) return {};
  return impl_->target.readSurfaceKinds();
}

Status SceneRenderer::writeExr(const std::string& path) const {
  if (!impl_->has_offscreen_frame)
    return Status(StatusCode::kInvalidInput, path + ": no offscreen frame rendered yet");
  return gl::writeRgbExr(path, impl_->target.width(), impl_->target.height(), readRadiance());
}

int SceneRenderer::width() const { return impl_->settings.width; }
int SceneRenderer::height() const { return impl_->settings.height; }

Status SceneRenderer::resize(int width, int height) {
  Impl& s = *impl_;
  if (width == s.settings.width && height == s.settings.height) return Status();
  Expected<gl::OffscreenTarget> target = gl::OffscreenTarget::create(width, height);
  if (!target.ok()) {
    return Status(target.status().code(), "SceneRenderer::resize: " + target.status().message() +
                                              " (the size stays " +
                                              std::to_string(s.settings.width) + "x" +
                                              std::to_string(s.settings.height) + ")");
  }
  s.target = std::move(target).value();
  s.settings.width = width;
  s.settings.height = height;
  s.has_offscreen_frame = false;
  return Status();
}

std::vector<ResourceUse> SceneRenderer::resources() const {
  const Impl& s = *impl_;
  auto use = [](std::string name, const std::vector<gl::GlObject>& objects, std::string why,
                std::string why_not) {
    ResourceUse out = gl::measuredUse(std::move(name), objects);
    out.reason = out.allocated ? std::move(why) : std::move(why_not);
    return out;
  };
  std::vector<ResourceUse> out;
  out.push_back(use("static mesh vertex buffer", {gl::glBufferObject(s.static_buffer.id())},
                    std::to_string(s.static_vertex_count) + " vertices", "no static triangles"));
  const size_t skipped = s.materials.skippedCount();
  out.push_back(use("material textures", s.materials.glObjects(),
                    "base colour of the materials that use one; " + std::to_string(skipped) +
                        " scene textures no material samples (normal, roughness) not uploaded",
                    ""));
  out.push_back(use("lightmap textures", s.lightmaps.glObjects(),
                    "its own copy: drawn without a runtime",
                    s.lightmaps.borrowed() ? "borrowed from the runtime (counted there): one copy"
                                           : "no lightmap pages"));
  out.push_back(use(
      "light shadow maps", s.shadows.glObjects(),
      std::to_string(s.shadows.lightCount()) +
          " lights drawn per pixel (runtime lights; baked ones while dynamic objects need them; "
          "masked baked lights' caster maps of the dynamic objects)",
      "no light to draw per pixel: no runtime lights, and no baked point, spot or sun light while "
      "dynamic objects exist (or nothing rendered yet)"));
  std::vector<gl::GlObject> mask_objects = s.masks.glObjects();
  for (const gl::GlObject& o : s.area_lights.glObjects()) mask_objects.push_back(o);
  out.push_back(use("shadow mask textures", mask_objects,
                    std::to_string(s.masked_lights.size()) +
                        " masked baked lights' static visibility, shaded per pixel (and the "
                        "area lights' triangles)",
                    "the bake masks no light (no dynamic objects, or --no-shadow-masks)"));
  out.push_back(use(
      "probe grid textures", s.probes.glObjects(), "indirect light of dynamic objects",
      "no dynamic objects can exist (no runtime, none in the level), or the bake has no probes"));
  ResourceUse dynamic = use("dynamic object vertex buffer", s.dynamic_objects.glObjects(),
                            "the objects as last drawn", "no dynamic objects drawn");
  dynamic.cpu_bytes = s.dynamic_objects.hostBytes();
  out.push_back(dynamic);
  out.push_back(use("offscreen target (colour + radiance + depth)", s.target.glObjects(),
                    std::to_string(s.settings.width) + " x " + std::to_string(s.settings.height),
                    ""));
  return out;
}

std::string_view shadingSource(std::string_view file_name) { return gl::shaderSource(file_name); }

}  // namespace svit

// svit::Runtime: creation, validation at the API boundary, and the object
// and light bookkeeping. The per-frame pipeline is in runtime_update.cpp.

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "aabb_ops.h"
#include "glm_interop.h"
#include "runtime_impl.h"
#include "svit/gl_context.h"

namespace svit {
namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const Mat4& m) {
  for (float x : m.m) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

Status settingError(const std::string& name, double value, const std::string& range) {
  return Status(StatusCode::kInvalidInput,
                "svit runtime: setting " + name + " = " + std::to_string(value) + " is out of range (" + range + ")");
}

Status checkSettings(const RuntimeSettings& s) {
  if (s.map_resolution < 16 || s.map_resolution > 2048) return settingError("map_resolution", s.map_resolution, "16..2048");
  if (s.target_patches < 16 || s.target_patches > 1 << 20) return settingError("target_patches", s.target_patches, "16..1048576");
  if (s.target_shooters < 1 || s.target_shooters > s.target_patches) {
    return settingError("target_shooters", s.target_shooters, "1..target_patches");
  }
  if (s.min_samples_per_emitter < 1) return settingError("min_samples_per_emitter", s.min_samples_per_emitter, ">= 1");
  if (s.max_samples_per_emitter < s.min_samples_per_emitter || s.max_samples_per_emitter > 1024) {
    return settingError("max_samples_per_emitter", s.max_samples_per_emitter, "min_samples_per_emitter..1024");
  }
  if (!(s.secondary_emitter_share > 0 && s.secondary_emitter_share <= 1)) {
    return settingError("secondary_emitter_share", s.secondary_emitter_share, "(0, 1]");
  }
  if (s.max_bounces < 0 || s.max_bounces > 64) return settingError("max_bounces", s.max_bounces, "0..64");
  if (!(s.bounce_stop_share >= 0 && s.bounce_stop_share < 1)) {
    return settingError("bounce_stop_share", s.bounce_stop_share, "[0, 1)");
  }
  if (!(s.temporal_blend > 0 && s.temporal_blend <= 1)) return settingError("temporal_blend", s.temporal_blend, "(0, 1]");
  if (s.view_pass_width < 16 || s.view_pass_width > 1024) return settingError("view_pass_width", s.view_pass_width, "16..1024");
  if (s.max_refresh_interval < 1 || s.max_refresh_interval > 1024) {
    return settingError("max_refresh_interval", s.max_refresh_interval, "1..1024");
  }
  if (s.max_samples_per_frame < 0) return settingError("max_samples_per_frame", s.max_samples_per_frame, ">= 0");
  return Status();
}

Status checkLight(const Light& light, const std::string& what) {
  if (light.type == LightType::kDirectional) {
    return Status(StatusCode::kInvalidInput, what + ": a directional runtime light is not supported (the sun is baked)");
  }
  if (!finite(light.position) || !finite(light.direction) || !std::isfinite(light.intensity) ||
      !std::isfinite(light.color.r) || !std::isfinite(light.color.g) || !std::isfinite(light.color.b)) {
    return Status(StatusCode::kInvalidInput, what + ": a value is not finite");
  }
  if (light.intensity < 0 || light.color.r < 0 || light.color.g < 0 || light.color.b < 0) {
    return Status(StatusCode::kInvalidInput, what + ": negative intensity or colour");
  }
  if (light.type == LightType::kSpot &&
      !(light.inner_cone_rad >= 0 && light.inner_cone_rad < light.outer_cone_rad && light.outer_cone_rad <= 1.5707964f)) {
    return Status(StatusCode::kInvalidInput, what + ": spot cone needs 0 <= inner < outer <= pi/2");
  }
  const float length = std::sqrt(light.direction.x * light.direction.x + light.direction.y * light.direction.y +
                                 light.direction.z * light.direction.z);
  if (light.type == LightType::kSpot && !(length > 0)) {
    return Status(StatusCode::kInvalidInput, what + ": spot direction is zero");
  }
  return Status();
}

Light normalisedLight(Light light) {
  const float length = std::sqrt(light.direction.x * light.direction.x + light.direction.y * light.direction.y +
                                 light.direction.z * light.direction.z);
  if (length > 0) light.direction = {light.direction.x / length, light.direction.y / length, light.direction.z / length};
  light.dynamic = true;
  return light;
}

rt::DynamicObject objectFromMesh(const DynamicMesh& mesh, const Mat4& world_from_object) {
  rt::DynamicObject object;
  object.name = mesh.name;
  object.double_sided = mesh.double_sided;
  object.world_from_object = world_from_object;
  for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    for (int k = 0; k < 3; ++k) object.object_positions.push_back(mesh.positions[mesh.indices[t * 3 + size_t(k)]]);
    object.albedo.push_back(mesh.albedo);
    object.emission.push_back(mesh.emission);
  }
  return object;
}

Status checkMesh(const DynamicMesh& mesh) {
  const std::string what = "svit runtime: object '" + mesh.name + "'";
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
    return Status(StatusCode::kInvalidInput, what + ": needs a non-empty multiple of 3 indices");
  }
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      return Status(StatusCode::kInvalidInput, what + ": index " + std::to_string(i) + " = " +
                                                   std::to_string(mesh.indices[i]) + " >= vertex count " +
                                                   std::to_string(mesh.positions.size()));
    }
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i])) return Status(StatusCode::kInvalidInput, what + ": position " + std::to_string(i) + " is not finite");
  }
  const Rgb& a = mesh.albedo;
  if (!(a.r >= 0 && a.r < 1 && a.g >= 0 && a.g < 1 && a.b >= 0 && a.b < 1)) {
    return Status(StatusCode::kInvalidInput, what + ": albedo must lie in [0, 1)");
  }
  const Rgb& e = mesh.emission;
  if (!(e.r >= 0 && e.g >= 0 && e.b >= 0 && std::isfinite(e.r) && std::isfinite(e.g) && std::isfinite(e.b))) {
    return Status(StatusCode::kInvalidInput, what + ": emission must be finite and >= 0");
  }
  return Status();
}

}  // namespace

Runtime::Runtime(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Runtime::~Runtime() {
  if (impl_ && (impl_->delta_buffer != 0 || !impl_->lightmap_textures.empty())) {
    if (impl_->delta_buffer != 0) glDeleteBuffers(1, &impl_->delta_buffer);
    if (!impl_->delta_textures.empty()) {
      glDeleteTextures(GLsizei(impl_->delta_textures.size()), impl_->delta_textures.data());
    }
    if (!impl_->lightmap_textures.empty()) {
      glDeleteTextures(GLsizei(impl_->lightmap_textures.size()), impl_->lightmap_textures.data());
    }
  }
}

Expected<std::unique_ptr<Runtime>> Runtime::create(const Scene& scene, const BakeData& bake, const std::string& bake_dir,
                                                   const RuntimeSettings& settings) {
  if (Expected<GlContextInfo> context = checkGlContext(); !context.ok()) return context.status();
  if (Status s = checkSettings(settings); !s.ok()) return s;
  const uint64_t level_hash = hashLevel(scene);
  if (level_hash != bake.level_hash) {
    return Status(StatusCode::kInvalidInput, "svit runtime: the bake in " + bake_dir + " is of another level than " +
                                                 scene.source_path + " (level hash differs); bake it again");
  }
  auto impl = std::make_unique<Impl>();
  impl->scene = scene;
  impl->bake = bake;
  impl->bake_dir = bake_dir;
  impl->settings = settings;
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok()) return Status(surfaces.status().code(), bake_dir + ": " + surfaces.status().message());
  impl->surfaces = std::move(surfaces).value();
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(bake, bake_dir);
  if (!pages.ok()) return pages.status();
  impl->pages = std::move(pages).value();
  impl->bake_emitter_scale.assign(bake.emitters.size(), 1.0f);

  bool dynamic_content = false;
  for (const Instance& instance : scene.instances) dynamic_content |= instance.dynamic;
  for (const Light& light : scene.lights) dynamic_content |= light.dynamic;
  if (dynamic_content && !bake.has_runtime_sections) {
    return Status(StatusCode::kInvalidInput, bake_dir + ": the bake has no runtime sections but the level has dynamic "
                                                        "objects or lights; bake it again with this svit");
  }
  Impl& r = *impl;
  if (bake.has_runtime_sections) {
    // Runtime patches: about settings.target_patches over the static surfaces.
    double area = 0;
    for (size_t t = 0; t < r.surfaces.triangleCount(); ++t) area += r.surfaces.area(t) * (r.surfaces.doubleSided(t) ? 2 : 1);
    const double max_area = area / double(settings.target_patches);
    Expected<rt::RuntimePatches> patches = rt::buildRuntimePatches(scene, bake, r.surfaces, r.pages, max_area,
                                                                   area / double(settings.target_shooters));
    if (!patches.ok()) return Status(patches.status().code(), bake_dir + ": " + patches.status().message());
    r.patches = std::move(patches).value();
    r.receivers = r.patches.receivers;
    r.static_receivers = uint32_t(r.receivers.size());
    r.static_groups = uint32_t(r.patches.shooter_members.size());
    r.group_emitter.assign(r.static_groups, kInvalidId);
    r.delta_total.assign(r.receivers.size(), glm::dvec3(0.0));
    r.runtime_direct.assign(r.receivers.size(), glm::dvec3(0.0));
    r.display.assign(r.receivers.size(), Rgb{});
    r.static_map = rt::inRunOrder(settings.use_proxies ? rt::proxyMapTriangles(bake, r.patches, max_area)
                                                       : r.patches.triangles);
    r.static_block_bounds.assign(r.static_receivers / rt::kShareBlockReceivers, Aabb{});
    for (uint32_t p = 0; p < r.static_block_bounds.size() * rt::kShareBlockReceivers; ++p) {
      rt::grow(r.static_block_bounds[p / rt::kShareBlockReceivers], r.patches.bounds[p]);
    }
    r.patch_map_triangles.assign(r.static_receivers, {});
    for (uint32_t t = 0; t < r.static_map.triangleCount(); ++t) {
      if (r.static_map.front_receiver[t] != rt::kNoReceiver) r.patch_map_triangles[r.static_map.front_receiver[t]].push_back(t);
    }
  }
  const Aabb& b = r.surfaces.bounds();
  const glm::vec3 lo = toGlm(b.min), hi = toGlm(b.max);
  r.window.centre = fromGlm(0.5f * (lo + hi));
  r.window.radius_m = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  // Samples sit this far off their surface so the map's near plane clears it.
  r.sample_offset_m = 1e-4f * r.window.radius_m + 1e-6f * glm::length(toGlm(r.window.centre));

  std::unique_ptr<Runtime> runtime(new Runtime(std::move(impl)));
  // The level's own dynamic content.
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    if (!instance.dynamic) continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    rt::DynamicObject object;
    object.name = scene.nodes[size_t(instance.node)].name;
    object.instance = int(i);
    object.world_from_object = instance.world_from_object;
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      for (int k = 0; k < 3; ++k) object.object_positions.push_back(mesh.positions[mesh.indices[t * 3 + size_t(k)]]);
      object.albedo.push_back(mesh.triangle_albedo[t]);
      object.emission.push_back(mesh.triangle_emission[t]);
      object.double_sided |= scene.materials[mesh.triangle_material[t]].double_sided;
    }
    runtime->impl_->addObjectInternal(std::move(object));
  }
  runtime->impl_->scene_light_to_light.assign(scene.lights.size(), -1);
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    if (!scene.lights[i].dynamic) continue;
    if (Status s = checkLight(scene.lights[i], "light '" + scene.lights[i].name + "'"); !s.ok()) return s;
    Expected<LightId> id = runtime->addLight(scene.lights[i]);
    if (!id.ok()) return id.status();
    runtime->impl_->scene_light_to_light[i] = int(*id);
  }
  return runtime;
}

uint32_t Runtime::Impl::addObjectInternal(rt::DynamicObject object) {
  object.first_receiver = uint32_t(receivers.size());
  object.lit = false;
  object.shown_revision = shares_revisions;
  rt::binObjectTriangles(object);
  rt::placeObject(object);
  receivers.resize(receivers.size() + object.albedo.size());
  rt::updateObjectReceivers(object, receivers);
  group_emitter.resize(group_emitter.size() + kObjectShooters, kInvalidId);
  delta_total.resize(receivers.size(), glm::dvec3(0.0));
  runtime_direct.resize(receivers.size(), glm::dvec3(0.0));
  display.resize(receivers.size(), Rgb{});
  if (!object.bounds.empty()) moved_boxes.push_back(object.bounds);
  objects.push_back(std::move(object));
  dynamic_geometry_changed = true;
  have_content = true;
  return uint32_t(objects.size() - 1);
}

ObjectId Runtime::objectForNode(int node) const {
  for (size_t i = 0; i < impl_->objects.size(); ++i) {
    const rt::DynamicObject& o = impl_->objects[i];
    if (!o.removed && o.instance >= 0 && impl_->scene.instances[size_t(o.instance)].node == node) return ObjectId(i);
  }
  return kInvalidId;
}

Expected<ObjectId> Runtime::addObject(const DynamicMesh& mesh, const Mat4& world_from_object) {
  if (Status s = checkMesh(mesh); !s.ok()) return s;
  if (!finite(world_from_object)) return Status(StatusCode::kInvalidInput, "svit runtime: object '" + mesh.name + "': transform is not finite");
  if (!impl_->bake.has_runtime_sections) {
    return Status(StatusCode::kUnsupported, "svit runtime: the bake in " + impl_->bake_dir +
                                                " has no runtime sections (the level had no dynamic content when baked)");
  }
  return impl_->addObjectInternal(objectFromMesh(mesh, world_from_object));
}

namespace {
Status unknownObject(ObjectId id) {
  return Status(StatusCode::kNotFound, "svit runtime: no object " + std::to_string(id));
}
}  // namespace

Status Runtime::setObjectTransform(ObjectId id, const Mat4& world_from_object) {
  if (id >= impl_->objects.size() || impl_->objects[id].removed) return unknownObject(id);
  if (!finite(world_from_object)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: object " + std::to_string(id) + ": transform is not finite");
  }
  rt::DynamicObject& o = impl_->objects[id];
  if (o.world_from_object.m == world_from_object.m) return Status();
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  o.world_from_object = world_from_object;
  rt::placeObject(o);
  rt::updateObjectReceivers(o, impl_->receivers);
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  impl_->dynamic_geometry_changed = true;
  return Status();
}

Status Runtime::deformObject(ObjectId id, std::span<const Vec3> positions) {
  if (id >= impl_->objects.size() || impl_->objects[id].removed) return unknownObject(id);
  rt::DynamicObject& o = impl_->objects[id];
  if (positions.size() != o.object_positions.size()) {
    return Status(StatusCode::kInvalidInput, "svit runtime: object " + std::to_string(id) + ": " +
                                                 std::to_string(positions.size()) + " positions, it has " +
                                                 std::to_string(o.object_positions.size()) + " (3 per triangle)");
  }
  for (size_t i = 0; i < positions.size(); ++i) {
    if (!finite(positions[i])) {
      return Status(StatusCode::kInvalidInput, "svit runtime: object " + std::to_string(id) + ": position " + std::to_string(i) + " is not finite");
    }
  }
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  o.object_positions.assign(positions.begin(), positions.end());
  rt::binObjectTriangles(o);
  rt::placeObject(o);
  rt::updateObjectReceivers(o, impl_->receivers);
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  impl_->dynamic_geometry_changed = true;
  return Status();
}

Status Runtime::setObjectVisible(ObjectId id, bool visible) {
  if (id >= impl_->objects.size() || impl_->objects[id].removed) return unknownObject(id);
  rt::DynamicObject& o = impl_->objects[id];
  if (o.visible == visible) return Status();
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  o.visible = visible;
  o.lit = false;
  o.shown_revision = impl_->shares_revisions;
  rt::placeObject(o);
  rt::updateObjectReceivers(o, impl_->receivers);
  if (!o.bounds.empty()) impl_->moved_boxes.push_back(o.bounds);
  impl_->dynamic_geometry_changed = true;
  return Status();
}

Status Runtime::removeObject(ObjectId id) {
  if (Status s = setObjectVisible(id, false); !s.ok()) return s;
  impl_->objects[id].removed = true;
  return Status();
}

Expected<ObjectInfo> Runtime::objectInfo(ObjectId id) const {
  if (id >= impl_->objects.size() || impl_->objects[id].removed) return unknownObject(id);
  const rt::DynamicObject& o = impl_->objects[id];
  ObjectInfo info;
  info.name = o.name;
  info.instance = o.instance;
  info.world_from_object = o.world_from_object;
  info.first_patch = o.first_receiver;
  info.patch_count = uint32_t(o.albedo.size());
  info.visible = o.visible;
  info.world_positions = o.world_positions;
  info.triangle_albedo = o.albedo;
  info.triangle_emission = o.emission;
  return info;
}

std::vector<ObjectId> Runtime::objects() const {
  std::vector<ObjectId> ids;
  for (size_t i = 0; i < impl_->objects.size(); ++i) {
    if (!impl_->objects[i].removed) ids.push_back(ObjectId(i));
  }
  return ids;
}

LightId Runtime::lightForSceneLight(int index) const {
  if (index < 0 || size_t(index) >= impl_->scene_light_to_light.size()) return kInvalidId;
  const int id = impl_->scene_light_to_light[size_t(index)];
  return id < 0 ? kInvalidId : LightId(id);
}

Expected<LightId> Runtime::addLight(const Light& light) {
  if (Status s = checkLight(light, "svit runtime: light '" + light.name + "'"); !s.ok()) return s;
  if (!impl_->bake.has_runtime_sections) {
    return Status(StatusCode::kUnsupported, "svit runtime: the bake in " + impl_->bake_dir +
                                                " has no runtime sections (the level had no dynamic content when baked)");
  }
  RuntimeLightState state;
  state.light = normalisedLight(light);
  impl_->lights.push_back(state);
  impl_->have_content = true;
  impl_->lighting_changed = true;
  return LightId(impl_->lights.size() - 1);
}

namespace {
Status unknownLight(LightId id) { return Status(StatusCode::kNotFound, "svit runtime: no light " + std::to_string(id)); }
}  // namespace

Status Runtime::setLight(LightId id, const Light& value) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  if (Status s = checkLight(value, "svit runtime: light " + std::to_string(id)); !s.ok()) return s;
  RuntimeLightState& state = impl_->lights[id];
  const Light next = normalisedLight(value);
  const bool moved = next.type != state.light.type || next.position.x != state.light.position.x ||
                     next.position.y != state.light.position.y || next.position.z != state.light.position.z ||
                     next.direction.x != state.light.direction.x || next.direction.y != state.light.direction.y ||
                     next.direction.z != state.light.direction.z || next.inner_cone_rad != state.light.inner_cone_rad ||
                     next.outer_cone_rad != state.light.outer_cone_rad;
  state.light = next;
  if (moved && state.emitter != kInvalidId) {
    impl_->emitters[state.emitter].samples_stale = true;
    impl_->emitters[state.emitter].stale = true;
  }
  impl_->lighting_changed = true;
  return Status();
}

Status Runtime::setLightEnabled(LightId id, bool enabled) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  impl_->lights[id].enabled = enabled;
  impl_->lighting_changed = true;
  return Status();
}

Status Runtime::setLightDimmer(LightId id, float scale) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  if (!(scale >= 0) || !std::isfinite(scale)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: light " + std::to_string(id) + ": dimmer " + std::to_string(scale) + " must be finite and >= 0");
  }
  impl_->lights[id].dimmer = scale;
  impl_->lighting_changed = true;
  return Status();
}

Status Runtime::setBakedEmitterScale(uint32_t bake_emitter, float scale) {
  if (bake_emitter >= impl_->bake.emitters.size()) {
    return Status(StatusCode::kNotFound, "svit runtime: no baked emitter " + std::to_string(bake_emitter) + " (the bake has " +
                                             std::to_string(impl_->bake.emitters.size()) + ")");
  }
  if (!(scale >= 0) || !std::isfinite(scale)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: baked emitter scale " + std::to_string(scale) + " must be finite and >= 0");
  }
  if (impl_->bake_emitter_scale[bake_emitter] != scale) {
    impl_->bake_emitter_scale[bake_emitter] = scale;
    impl_->have_content = true;
    impl_->lighting_changed = true;
  }
  return Status();
}

std::vector<LightId> Runtime::lights() const {
  std::vector<LightId> ids;
  for (size_t i = 0; i < impl_->lights.size(); ++i) {
    if (!impl_->lights[i].removed) ids.push_back(LightId(i));
  }
  return ids;
}

Expected<RuntimeLightInfo> Runtime::lightInfo(LightId id) const {
  if (id >= impl_->lights.size()) return unknownLight(id);
  const RuntimeLightState& s = impl_->lights[id];
  return RuntimeLightInfo{s.light, s.enabled, s.dimmer};
}

FrameStats Runtime::update(double budget_ms) { return impl_->update(budget_ms); }

const char* refreshReasonName(RefreshReason reason) {
  switch (reason) {
    case RefreshReason::kImportant: return "important";
    case RefreshReason::kPromoted: return "promoted";
    case RefreshReason::kRoundRobin: return "round-robin";
    case RefreshReason::kLightChanged: return "light-changed";
    case RefreshReason::kBounce: return "bounce";
    case RefreshReason::kRefreshAll: return "refresh-all";
    case RefreshReason::kNoView: return "no-view";
  }
  return "unknown";
}

Status Runtime::setView(const RuntimeView& view) {
  const float values[] = {view.position.x, view.position.y, view.position.z, view.look_at.x, view.look_at.y,
                          view.look_at.z, view.up.x, view.up.y, view.up.z, view.yfov_rad, view.aspect, view.near_m};
  for (float v : values) {
    if (!std::isfinite(v)) return Status(StatusCode::kInvalidInput, "svit runtime: setView: the view is not finite");
  }
  const glm::vec3 forward = toGlm(view.look_at) - toGlm(view.position);
  if (!(glm::length(forward) > 0)) return Status(StatusCode::kInvalidInput, "svit runtime: setView: position equals look_at");
  if (!(glm::length(glm::cross(glm::normalize(forward), toGlm(view.up))) > 1e-6f)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: setView: up is zero or along the view direction");
  }
  if (!(view.yfov_rad > 0 && view.yfov_rad < 3.14159265f)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: setView: yfov_rad " + std::to_string(view.yfov_rad) + " is outside (0, pi)");
  }
  if (!(view.aspect > 0) || !(view.near_m > 0)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: setView: aspect and near_m must be positive");
  }
  impl_->view = view;
  impl_->has_view = true;
  return Status();
}

void Runtime::clearView() { impl_->has_view = false; }

Status Runtime::setSampleBudget(int max_samples_per_frame) {
  if (max_samples_per_frame < 0) return settingError("max_samples_per_frame", max_samples_per_frame, ">= 0");
  impl_->settings.max_samples_per_frame = max_samples_per_frame;
  return Status();
}

std::vector<EmitterState> Runtime::emitterStates() const {
  const Impl& m = *impl_;
  std::vector<EmitterState> states;
  states.reserve(m.emitters.size());
  for (const Emitter& e : m.emitters) {
    EmitterState s;
    s.type = EmitterType(uint32_t(e.kind));
    s.bake_emitter = e.bake_emitter;
    if (e.kind == EmitterKind::kRuntimeLight) s.light = e.index;
    s.importance = e.importance;
    s.interval = e.interval;
    s.out_of_date = m.outOfDate(e) && m.needsMaps(e);
    s.has_maps = e.has_current || e.has_baseline;
    s.refreshed_frame = e.refreshed_frame;
    s.samples = uint32_t(e.samples.empty() ? size_t(e.sample_count) : e.samples.size());
    states.push_back(s);
  }
  return states;
}

Rgb Runtime::irradianceAt(const Vec3& point, const Vec3& normal, float max_distance_m) const {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::optional<SurfaceHit> hit = impl_->surfaces.nearest(point, normal);
  if (!hit || hit->distance_m > max_distance_m) return {nan, nan, nan};
  Rgb e = impl_->pages[hit->page].sampleBilinear(hit->uv);
  // The delta as shading interpolates it: between the welded vertices of
  // the runtime patch sub-triangle under the point.
  const uint32_t element = hit->triangle * 2 + uint32_t(hit->side);
  float s1 = 0, s2 = 0;
  const uint32_t sub = impl_->patches.subTriangle(element, hit->w1, hit->w2, s1, s2);
  if (sub != rt::kNoReceiver) {
    if (hit->side == 1) std::swap(s1, s2);  // back-side sub-triangles are wound the other way
    const std::vector<glm::dvec3>& v = impl_->vertexDeltas();
    const uint32_t* corner = &impl_->patches.triangle_vertices[size_t(sub) * 3];
    auto at = [&](const std::vector<glm::dvec3>& values) {
      return values[corner[0]] * double(1 - s1 - s2) + values[corner[1]] * double(s1) + values[corner[2]] * double(s2);
    };
    const glm::dvec3 d = at(v);
    // The lightmap's factor (dimmed baked emitters), then the added light.
    const std::vector<glm::dvec3>& scales = impl_->vertex_scales;
    const double factor = 1.0 + (scales.empty() ? 0.0 : at(scales).x);
    // A delta never takes more light than there is (shading clamps the same way).
    e = {std::max(0.0f, float(e.r * factor + d.x)), std::max(0.0f, float(e.g * factor + d.y)),
         std::max(0.0f, float(e.b * factor + d.z))};
  }
  return e;
}

const std::vector<Rgb>& Runtime::patchDeltas() const { return impl_->display; }

uint32_t Runtime::staticPatchCount() const { return impl_->static_receivers; }

Expected<PatchInfo> Runtime::patchInfo(uint32_t patch) const {
  if (patch >= impl_->static_receivers) {
    return Status(StatusCode::kNotFound, "svit runtime: no static patch " + std::to_string(patch) + " (there are " +
                                             std::to_string(impl_->static_receivers) + ")");
  }
  const rt::RuntimePatches& p = impl_->patches;
  const rt::Receiver& r = p.receivers[patch];
  PatchInfo info;
  info.centroid = r.centroid;
  info.normal = r.normal;
  info.area_m2 = r.area_m2;
  info.albedo = r.albedo;
  info.baseline_exitance = {float(p.baseline[patch].x), float(p.baseline[patch].y), float(p.baseline[patch].z)};
  info.bake_patch = p.bake_patch[patch];
  for (size_t t = 0; t < p.triangles.triangleCount(); ++t) {
    if (p.triangles.front_receiver[t] != patch) continue;
    for (int k = 0; k < 3; ++k) info.triangles.push_back(p.triangles.positions[t * 3 + size_t(k)]);
  }
  return info;
}

Expected<Rgb> Runtime::objectPatchIrradiance(ObjectId id, uint32_t triangle) const {
  if (id >= impl_->objects.size() || impl_->objects[id].removed) return unknownObject(id);
  const rt::DynamicObject& o = impl_->objects[id];
  if (triangle >= o.albedo.size()) {
    return Status(StatusCode::kInvalidInput, "svit runtime: object " + std::to_string(id) + " has no triangle " + std::to_string(triangle));
  }
  const glm::dvec3& d = impl_->delta_total[o.first_receiver + triangle];
  return Rgb{float(d.x), float(d.y), float(d.z)};
}

ShadingResources Runtime::shadingResources() const {
  ShadingResources out;
  out.patch_delta_buffer = impl_->delta_buffer;
  out.patch_count = impl_->delta_buffer != 0 ? impl_->delta_buffer_receivers : 0;
  if (impl_->lightmap_textures.empty() && !impl_->pages.empty()) {
    impl_->lightmap_textures.resize(impl_->pages.size());
    glCreateTextures(GL_TEXTURE_2D, GLsizei(impl_->pages.size()), impl_->lightmap_textures.data());
    for (size_t i = 0; i < impl_->pages.size(); ++i) {
      const LightmapImage& page = impl_->pages[i];
      const GLuint texture = impl_->lightmap_textures[i];
      glTextureStorage2D(texture, 1, GL_RGB32F, page.width, page.height);
      glTextureSubImage2D(texture, 0, 0, 0, page.width, page.height, GL_RGB, GL_FLOAT, page.rgb.data());
      glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
  }
  out.lightmap_textures = impl_->lightmap_textures;
  out.delta_textures = impl_->delta_textures;
  out.delta_elements = impl_->delta_surface.elementBuffer();
  out.delta_slots = impl_->delta_surface.slotBuffer();
  out.vertex_deltas = impl_->delta_surface.vertexDeltaBuffer();
  return out;
}

const BakeData& Runtime::bake() const { return impl_->bake; }
const Scene& Runtime::scene() const { return impl_->scene; }

}  // namespace svit

// svit::Runtime: creation, and the object and light bookkeeping behind the
// API (validated by runtime_checks.cpp). The per-frame pipeline is in
// runtime_update.cpp, the queries in runtime_queries.cpp.

#include <algorithm>
#include <cmath>
#include <string>

#include "lighting/aabb_ops.h"
#include "runtime_checks.h"
#include "runtime_impl.h"
#include "scene/numeric.h"
#include "svit/gl_context.h"

namespace svit {
namespace {

Light normalisedLight(Light light) {
  const float length =
      std::sqrt(light.direction.x * light.direction.x + light.direction.y * light.direction.y +
                light.direction.z * light.direction.z);
  if (length > 0)
    light.direction = {light.direction.x / length, light.direction.y / length,
                       light.direction.z / length};
  light.dynamic = true;
  return light;
}

rt::DynamicObject objectFromMesh(const DynamicMesh& mesh, const Mat4& world_from_object) {
  rt::DynamicObject object;
  object.name = mesh.name;
  object.double_sided = mesh.double_sided;
  object.world_from_object = world_from_object;
  for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
    for (int k = 0; k < 3; ++k)
      object.object_positions.push_back(mesh.positions[mesh.indices[t * 3 + size_t(k)]]);
    object.albedo.push_back(mesh.albedo);
    object.emission.push_back(mesh.emission);
  }
  return object;
}

rt::DynamicObject objectFromInstance(const Scene& scene, size_t instance_index) {
  const Instance& instance = scene.instances[instance_index];
  const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
  rt::DynamicObject object;
  object.name = scene.nodes[size_t(instance.node)].name;
  object.instance = int(instance_index);
  object.world_from_object = instance.world_from_object;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k)
      object.object_positions.push_back(mesh.positions[mesh.indices[t * 3 + size_t(k)]]);
    object.albedo.push_back(mesh.triangle_albedo[t]);
    object.emission.push_back(mesh.triangle_emission[t]);
    object.double_sided |= scene.materials[mesh.triangle_material[t]].double_sided;
  }
  return object;
}

Status unknownObject(ObjectId id) {
  return Status(StatusCode::kNotFound, "svit runtime: no object " + std::to_string(id));
}
Status outOfObjectIds() {
  return Status(StatusCode::kUnsupported,
                "svit runtime: every object id has been given (ids are never reused)");
}
Status unknownLight(LightId id) {
  return Status(StatusCode::kNotFound, "svit runtime: no light " + std::to_string(id));
}

Status noRuntimeSections(const std::string& bake_dir) {
  return Status(StatusCode::kUnsupported,
                "svit runtime: the bake in " + bake_dir +
                    " has no runtime sections (the level had no dynamic content when baked)");
}

bool sameLobe(const Light& a, const Light& b) {
  return a.type == b.type && a.position.x == b.position.x && a.position.y == b.position.y &&
         a.position.z == b.position.z && a.direction.x == b.direction.x &&
         a.direction.y == b.direction.y && a.direction.z == b.direction.z &&
         a.inner_cone_rad == b.inner_cone_rad && a.outer_cone_rad == b.outer_cone_rad;
}

}  // namespace

Runtime::Runtime(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

// The GL objects are owned by the parts (gl_handle.h); the context that made
// them must be current here.
Runtime::~Runtime() = default;

void Runtime::Impl::initStaticReceivers() {
  receivers = level.patches.receivers;
  for (const Aabb& block : level.static_block_bounds) rt::grow(level_box, block);
  emitter_set.group_emitter.assign(level.static_groups, kInvalidId);
  outputs.resize(receivers.size());
  light_scale.reset(level.bake.emitters.size());
}

Status Runtime::Impl::addLevelContent(Runtime& runtime) {
  const Scene& scene = level.scene;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    if (scene.instances[i].dynamic) addObjectInternal(objectFromInstance(scene, i));
  }
  scene_light_to_light.assign(scene.lights.size(), -1);
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    if (!scene.lights[i].dynamic) continue;
    if (Status s = checkLight(scene.lights[i], "light '" + scene.lights[i].name + "'"); !s.ok())
      return s;
    Expected<LightId> id = runtime.addLight(scene.lights[i]);
    if (!id.ok()) return id.status();
    scene_light_to_light[i] = int(*id);
  }
  return Status();
}

Expected<std::unique_ptr<Runtime>> Runtime::create(const Scene& scene, const BakeData& bake,
                                                   const std::string& bake_dir,
                                                   const RuntimeSettings& settings) {
  if (Expected<GlContextInfo> context = checkGlContext(); !context.ok()) return context.status();
  if (Status s = checkSettings(settings); !s.ok()) return s;
  if (hashLevel(scene) != bake.level_hash) {
    return Status(StatusCode::kInvalidInput, "svit runtime: the bake in " + bake_dir +
                                                 " is of another level than " + scene.source_path +
                                                 " (level hash differs); bake it again");
  }
  Expected<rt::StaticLevel> level = rt::buildStaticLevel(scene, bake, bake_dir, settings);
  if (!level.ok()) return level.status();
  auto impl = std::make_unique<Impl>();
  impl->settings = settings;
  impl->level = std::move(level).value();
  impl->initStaticReceivers();
  std::unique_ptr<Runtime> runtime(new Runtime(std::move(impl)));
  if (Status s = runtime->impl_->addLevelContent(*runtime); !s.ok()) return s;
  return runtime;
}

void Runtime::Impl::releaseObject(uint32_t slot) {
  rt::DynamicObject& object = objects[slot];
  // Its receivers go back to the pool with no area, so nothing lights them
  // until an object takes them; it keeps no triangle, so no loop over the
  // objects' receivers reaches them through it.
  const uint32_t count = uint32_t(object.albedo.size());
  for (uint32_t t = 0; t < count; ++t) receivers[object.first_receiver + t] = {};
  if (count > 0) free_receivers.push_back({object.first_receiver, count});
  object = rt::DynamicObject{};
  object.visible = false;
  object.removed = true;
  // Its facings' light leaves the sums, then their records leave the set:
  // the slot's groups are free for the next object, which makes its own
  // emitters as a fresh runtime would.
  const uint32_t first_group = level.static_groups + slot * kObjectShooters;
  for (uint32_t bin = 0; bin < kObjectShooters; ++bin) {
    const uint32_t id = emitter_set.group_emitter[first_group + bin];
    if (id != kInvalidId) accumulator.retractCurrent(emitter_set.emitters[id]);
  }
  renumberEmitters(rt::eraseGroupEmitters(emitter_set, first_group, kObjectShooters));
}

void Runtime::Impl::renumberEmitters(const std::vector<uint32_t>& erased) {
  if (erased.empty()) return;
  for (RuntimeLightState& light : lights) {
    if (light.emitter != kInvalidId) light.emitter = rt::emitterIdAfterErase(light.emitter, erased);
  }
}

rt::DynamicObject* Runtime::Impl::liveObject(ObjectId id) {
  const uint32_t slot = object_slots.slotOf(id);
  return slot == rt::kNoSlot ? nullptr : &objects[slot];
}

const rt::DynamicObject* Runtime::Impl::liveObject(ObjectId id) const {
  const uint32_t slot = object_slots.slotOf(id);
  return slot == rt::kNoSlot ? nullptr : &objects[slot];
}

// The first range of `count` receivers a removed object gave back, or the
// end of the receivers (grown by `count`).
uint32_t Runtime::Impl::takeReceivers(uint32_t count) {
  for (size_t i = 0; i < free_receivers.size(); ++i) {
    auto& [first, free] = free_receivers[i];
    if (free < count) continue;
    const uint32_t taken = first;
    first += count;
    free -= count;
    if (free == 0) free_receivers.erase(free_receivers.begin() + std::ptrdiff_t(i));
    return taken;
  }
  const uint32_t end = uint32_t(receivers.size());
  receivers.resize(receivers.size() + count);
  return end;
}

ObjectId Runtime::Impl::addObjectInternal(rt::DynamicObject object) {
  const rt::ObjectSlots::Added added = object_slots.add();
  if (added.id == kInvalidId) return kInvalidId;
  object.first_receiver = takeReceivers(uint32_t(object.albedo.size()));
  object.lit = false;
  object.shown_revision = accumulator.revisions();
  rt::binObjectTriangles(object);
  rt::placeObject(object);
  rt::updateObjectReceivers(object, level_box, receivers);
  if (added.new_slot) {
    emitter_set.group_emitter.resize(emitter_set.group_emitter.size() + kObjectShooters,
                                     kInvalidId);
    objects.emplace_back();
  }
  outputs.resize(receivers.size());
  changes.noteBox(object.bounds);
  objects[added.slot] = std::move(object);
  changes.dynamic_geometry_changed = true;
  have_content = true;
  return added.id;
}

ObjectId Runtime::objectForNode(int node) const {
  for (uint32_t slot = 0; slot < impl_->objects.size(); ++slot) {
    const rt::DynamicObject& o = impl_->objects[slot];
    if (!o.removed && o.instance >= 0 &&
        impl_->level.scene.instances[size_t(o.instance)].node == node)
      return impl_->object_slots.idOf(slot);
  }
  return kInvalidId;
}

Expected<ObjectId> Runtime::addObject(const DynamicMesh& mesh, const Mat4& world_from_object) {
  if (Status s = checkMesh(mesh); !s.ok()) return s;
  if (Status s = checkPlacement(mesh.positions, world_from_object,
                                "svit runtime: object '" + mesh.name + "'");
      !s.ok())
    return s;
  if (!impl_->level.bake.has_runtime_sections) return noRuntimeSections(impl_->level.bake_dir);
  const ObjectId id = impl_->addObjectInternal(objectFromMesh(mesh, world_from_object));
  if (id == kInvalidId) return outOfObjectIds();
  return id;
}

Status Runtime::setObjectTransform(ObjectId id, const Mat4& world_from_object) {
  rt::DynamicObject* live = impl_->liveObject(id);
  if (live == nullptr) return unknownObject(id);
  rt::DynamicObject& o = *live;
  if (Status s = checkPlacement(o.object_positions, world_from_object,
                                "svit runtime: object " + std::to_string(id));
      !s.ok())
    return s;
  if (o.world_from_object.m == world_from_object.m) return Status();
  impl_->changeObject(
      o, [&](rt::DynamicObject& object) { object.world_from_object = world_from_object; });
  return Status();
}

Status Runtime::deformObject(ObjectId id, std::span<const Vec3> positions) {
  rt::DynamicObject* live = impl_->liveObject(id);
  if (live == nullptr) return unknownObject(id);
  rt::DynamicObject& o = *live;
  if (positions.size() != o.object_positions.size()) {
    return Status(StatusCode::kInvalidInput,
                  "svit runtime: object " + std::to_string(id) + ": " +
                      std::to_string(positions.size()) + " positions, it has " +
                      std::to_string(o.object_positions.size()) + " (3 per triangle)");
  }
  if (Status s = checkPlacement(positions, o.world_from_object,
                                "svit runtime: object " + std::to_string(id));
      !s.ok())
    return s;
  impl_->changeObject(o, [&](rt::DynamicObject& object) {
    object.object_positions.assign(positions.begin(), positions.end());
    rt::binObjectTriangles(object);
  });
  return Status();
}

Status Runtime::setObjectVisible(ObjectId id, bool visible) {
  rt::DynamicObject* live = impl_->liveObject(id);
  if (live == nullptr) return unknownObject(id);
  rt::DynamicObject& o = *live;
  if (o.visible == visible) return Status();
  impl_->changeObject(o, [&](rt::DynamicObject& object) {
    object.visible = visible;
    object.lit = false;
    object.shown_revision = impl_->accumulator.revisions();
  });
  return Status();
}

Status Runtime::removeObject(ObjectId id) {
  if (Status s = setObjectVisible(id, false); !s.ok()) return s;
  const uint32_t slot = impl_->object_slots.slotOf(id);
  impl_->objects[slot].removed = true;
  impl_->releaseObject(slot);
  impl_->object_slots.remove(id);  // the id stays refused; the slot goes to the next object
  return Status();
}

Expected<ObjectInfo> Runtime::objectInfo(ObjectId id) const {
  const rt::DynamicObject* live = impl_->liveObject(id);
  if (live == nullptr) return unknownObject(id);
  const rt::DynamicObject& o = *live;
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

std::vector<ObjectId> Runtime::objects() const { return impl_->object_slots.liveIds(); }

LightId Runtime::lightForSceneLight(int index) const {
  if (index < 0 || size_t(index) >= impl_->scene_light_to_light.size()) return kInvalidId;
  const int id = impl_->scene_light_to_light[size_t(index)];
  return id < 0 ? kInvalidId : LightId(id);
}

Expected<LightId> Runtime::addLight(const Light& light) {
  if (Status s = checkLight(light, "svit runtime: light '" + light.name + "'"); !s.ok()) return s;
  if (!impl_->level.bake.has_runtime_sections) return noRuntimeSections(impl_->level.bake_dir);
  RuntimeLightState state;
  state.light = normalisedLight(light);
  impl_->lights.push_back(state);
  impl_->have_content = true;
  impl_->changes.lighting_changed = true;
  return LightId(impl_->lights.size() - 1);
}

Status Runtime::setLight(LightId id, const Light& value) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  if (Status s = checkLight(value, "svit runtime: light " + std::to_string(id)); !s.ok()) return s;
  RuntimeLightState& state = impl_->lights[id];
  const Light next = normalisedLight(value);
  const bool moved = !sameLobe(next, state.light);
  state.light = next;
  if (moved && state.emitter != kInvalidId) {
    Emitter& e = impl_->emitter_set.emitters[state.emitter];
    e.samples_stale = true;
    e.markStale();
  }
  impl_->changes.lighting_changed = true;
  return Status();
}

Status Runtime::setLightEnabled(LightId id, bool enabled) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  impl_->lights[id].enabled = enabled;
  impl_->changes.lighting_changed = true;
  return Status();
}

Status Runtime::setLightDimmer(LightId id, float scale) {
  if (id >= impl_->lights.size()) return unknownLight(id);
  if (Status s = checkScale(scale, "svit runtime: light " + std::to_string(id) + ": dimmer");
      !s.ok())
    return s;
  impl_->lights[id].dimmer = scale;
  impl_->changes.lighting_changed = true;
  return Status();
}

Status Runtime::setBakedEmitterScale(uint32_t bake_emitter, float scale) {
  const size_t bake_emitters = impl_->level.bake.emitters.size();
  if (bake_emitter >= bake_emitters) {
    return Status(StatusCode::kNotFound, "svit runtime: no baked emitter " +
                                             std::to_string(bake_emitter) + " (the bake has " +
                                             std::to_string(bake_emitters) + ")");
  }
  if (Status s = checkScale(
          scale, "svit runtime: baked emitter " + std::to_string(bake_emitter) + ": scale");
      !s.ok())
    return s;
  if (impl_->light_scale.setEmitterScale(bake_emitter, scale)) {
    impl_->have_content = true;
    impl_->changes.lighting_changed = true;
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

FrameStats Runtime::update(double budget_ms) {
  // A bad budget is refused before anything happens: not even a frame counted.
  if (Status s = checkUpdateBudget(budget_ms); !s.ok()) {
    FrameStats stats;
    stats.error = s.message();
    return stats;
  }
  return impl_->update(budget_ms);
}

Status Runtime::setView(const RuntimeView& view) {
  if (Status s = checkView(view); !s.ok()) return s;
  impl_->ranking.view = view;
  impl_->ranking.has_view = true;
  return Status();
}

void Runtime::clearView() { impl_->ranking.has_view = false; }

Status Runtime::setSampleBudget(int max_samples_per_frame) {
  if (max_samples_per_frame < 0)
    return settingError("max_samples_per_frame", max_samples_per_frame, ">= 0");
  impl_->settings.max_samples_per_frame = max_samples_per_frame;
  return Status();
}

}  // namespace svit

// svit::Runtime's queries: emitter states, irradiance at a point as shading
// shows it, patch and object values, and the GL resources shading reads.

#include <algorithm>
#include <limits>
#include <optional>
#include <string>

#include "runtime_impl.h"

namespace svit {

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

std::vector<EmitterState> Runtime::emitterStates() const {
  const Impl& m = *impl_;
  std::vector<EmitterState> states;
  states.reserve(m.emitter_set.emitters.size());
  for (const Emitter& e : m.emitter_set.emitters) {
    EmitterState s;
    s.type = EmitterType(uint32_t(e.kind));
    s.bake_emitter = e.bake_emitter;
    if (e.kind == EmitterKind::kRuntimeLight) s.light = e.index;
    s.importance = e.queue.importance;
    s.interval = e.queue.interval;
    s.out_of_date = m.outOfDate(e) && m.needsMaps(e);
    s.has_maps = e.hasCurrent() || e.has_baseline;
    s.refreshed_frame = e.queue.refreshed_frame;
    s.samples = uint32_t(e.samples.empty() ? size_t(e.sample_count) : e.samples.size());
    states.push_back(s);
  }
  return states;
}

Rgb Runtime::irradianceAt(const Vec3& point, const Vec3& normal, float max_distance_m) const {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const rt::StaticLevel& level = impl_->level;
  const std::optional<SurfaceHit> hit = level.surfaces.nearest(point, normal);
  if (!hit || hit->distance_m > max_distance_m) return {nan, nan, nan};
  const Rgb e = samplePage(level.pages, hit->page, hit->uv);
  // Shaded per pixel beside the lightmap: the masked lights' direct light.
  const glm::dvec3 masked = level.masked.empty() ? glm::dvec3(0.0) : impl_->maskedDirectAt(*hit);
  // The delta as shading interpolates it: between the welded vertices of
  // the runtime patch sub-triangle under the point.
  const uint32_t element = hit->triangle * 2 + uint32_t(hit->side);
  float s1 = 0, s2 = 0;
  const uint32_t sub = level.patches.subTriangle(element, hit->w1, hit->w2, s1, s2);
  if (sub == rt::kNoReceiver)
    return {float(e.r + masked.x), float(e.g + masked.y), float(e.b + masked.z)};
  if (hit->side == 1) std::swap(s1, s2);  // back-side sub-triangles are wound the other way
  const uint32_t* corner = &level.patches.triangle_vertices[size_t(sub) * 3];
  auto at = [&](const std::vector<glm::dvec3>& values) {
    return values[corner[0]] * double(1 - s1 - s2) + values[corner[1]] * double(s1) +
           values[corner[2]] * double(s2);
  };
  const glm::dvec3 d = at(impl_->outputs.vertexDeltas(level.patches));
  // The lightmap's factor (dimmed baked emitters), then the added light.
  const std::vector<glm::dvec3>& scales = impl_->outputs.vertexScales();
  const double factor = 1.0 + (scales.empty() ? 0.0 : at(scales).x);
  // A delta never takes more light than there is (shading clamps the same way).
  return {std::max(0.0f, float(e.r * factor + d.x)) + float(masked.x),
          std::max(0.0f, float(e.g * factor + d.y)) + float(masked.y),
          std::max(0.0f, float(e.b * factor + d.z)) + float(masked.z)};
}

const std::vector<Rgb>& Runtime::patchDeltas() const { return impl_->outputs.display; }

uint32_t Runtime::staticPatchCount() const { return impl_->level.static_receivers; }

Expected<PatchInfo> Runtime::patchInfo(uint32_t patch) const {
  const uint32_t static_receivers = impl_->level.static_receivers;
  if (patch >= static_receivers) {
    return Status(StatusCode::kNotFound, "svit runtime: no static patch " + std::to_string(patch) +
                                             " (there are " + std::to_string(static_receivers) +
                                             ")");
  }
  const rt::RuntimePatches& p = impl_->level.patches;
  const rt::Receiver& r = p.receivers[patch];
  PatchInfo info;
  info.centroid = r.centroid;
  info.normal = r.normal;
  info.area_m2 = r.area_m2;
  info.albedo = r.albedo;
  info.baseline_exitance = {float(p.baseline[patch].x), float(p.baseline[patch].y),
                            float(p.baseline[patch].z)};
  info.bake_patch = p.bake_patch[patch];
  for (size_t t = 0; t < p.triangles.triangleCount(); ++t) {
    if (p.triangles.front_receiver[t] != patch) continue;
    for (int k = 0; k < 3; ++k) info.triangles.push_back(p.triangles.positions[t * 3 + size_t(k)]);
  }
  return info;
}

Expected<Rgb> Runtime::objectPatchIrradiance(ObjectId id, uint32_t triangle) const {
  const rt::DynamicObject* live = impl_->liveObject(id);
  if (live == nullptr) {
    return Status(StatusCode::kNotFound, "svit runtime: no object " + std::to_string(id));
  }
  const rt::DynamicObject& o = *live;
  if (triangle >= o.albedo.size()) {
    return Status(StatusCode::kInvalidInput, "svit runtime: object " + std::to_string(id) +
                                                 " has no triangle " + std::to_string(triangle));
  }
  const glm::dvec3& d = impl_->outputs.delta_total[o.first_receiver + triangle];
  return Rgb{float(d.x), float(d.y), float(d.z)};
}

ShadingResources Runtime::shadingResources() const {
  const rt::ShadingOutputs& outputs = impl_->outputs;
  ShadingResources out;
  out.patch_delta_buffer = outputs.deltaBuffer();
  out.patch_count = outputs.deltaBuffer() != 0 ? outputs.deltaBufferReceivers() : 0;
  out.lightmap_textures = outputs.lightmapTextures(impl_->level.pages);
  out.delta_textures = outputs.deltaTextures();
  out.delta_elements = outputs.deltaSurface().elementBuffer();
  out.delta_slots = outputs.deltaSurface().slotBuffer();
  out.vertex_deltas = outputs.deltaSurface().vertexDeltaBuffer();
  return out;
}

const BakeData& Runtime::bake() const { return impl_->level.bake; }
const Scene& Runtime::scene() const { return impl_->level.scene; }

}  // namespace svit

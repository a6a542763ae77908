// The runtime's frame (thesis 5.3): bring emitters' cached index-map shares
// up to date where something moved, within the budget; turn them into
// per-receiver flux deltas against the baked baseline (current minus
// baseline shares of every baked emitter, plus new emitters); bounce the
// deltas through the receivers' own cached shares; compensate what was not
// shot as ambient; publish the deltas for shading.

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "glm_interop.h"
#include "aabb_ops.h"
#include "delta_atlas.h"
#include "runtime_impl.h"

namespace svit {
namespace {

using rt::grow;
using rt::overlaps;

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }


int sampleCount(double flux, double max_flux, const RuntimeSettings& s) {
  if (!(max_flux > 0)) return s.min_samples_per_emitter;
  const int n = int(std::ceil(double(s.max_samples_per_emitter) * std::abs(flux) / max_flux));
  return std::clamp(n, s.min_samples_per_emitter, s.max_samples_per_emitter);
}

}  // namespace

Status Runtime::Impl::ensureRenderer() {
  if (renderer) return Status();
  rt::IndexMapSettings map_settings;
  map_settings.resolution = settings.map_resolution;
  map_settings.small_polygon_fallback = settings.small_polygon_fallback;
  map_settings.edge_taps = settings.edge_taps;
  map_settings.neighbour_ids = settings.neighbour_ids;
  map_settings.occlusion_culling = settings.occlusion_culling;
  Expected<std::unique_ptr<rt::IndexMapRenderer>> created = rt::IndexMapRenderer::create(map_settings);
  if (!created.ok()) return created.status();
  renderer = std::move(created).value();
  renderer->setStaticTriangles(static_map);
  renderer->setReceiverCount(uint32_t(receivers.size()));
  ++gl_objects_created;
  // The baked emitters and the bright patch groups (thesis 5.3 step 1):
  // every baked light, the sun, the sky, and the bake patches carrying
  // `secondary_emitter_share` of the reflected baseline flux.
  std::vector<double> group_flux(static_groups, 0.0);
  for (uint32_t r = 0; r < static_receivers; ++r) {
    group_flux[patches.shooter[r]] += std::max(0.0, lum(patches.baseline[r])) * double(receivers[r].area_m2);
  }
  std::vector<std::pair<double, uint32_t>> bright;
  double bright_total = 0, max_flux = 0;
  for (uint32_t g = 0; g < static_groups; ++g) {
    if (group_flux[g] > 0) bright.push_back({group_flux[g], g});
    bright_total += group_flux[g];
    max_flux = std::max(max_flux, group_flux[g]);
  }
  std::sort(bright.begin(), bright.end(), [](auto& a, auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    const BakeEmitter& be = bake.emitters[i];
    if (be.kind == BakeEmitter::Kind::kPatch) continue;
    Emitter e;
    e.kind = be.kind == BakeEmitter::Kind::kLight ? EmitterKind::kBakedLight
             : be.kind == BakeEmitter::Kind::kSun ? EmitterKind::kSun
                                                  : EmitterKind::kSky;
    e.index = i;
    e.bake_emitter = i;
    e.needs_baseline = true;
    e.flux = dvec(be.flux);  // until its samples give the exact lobe's flux
    initBakeShares(e);
    emitters.push_back(std::move(e));
  }
  double covered = 0;
  for (auto& [f, g] : bright) {
    if (covered >= settings.secondary_emitter_share * bright_total) break;
    covered += f;
    addGroupEmitter(g, true, f, max_flux);
  }
  // A lamp's emissive patch: its shooters can be dimmed as the baked emitter.
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    const BakeEmitter& be = bake.emitters[i];
    if (be.kind != BakeEmitter::Kind::kPatch) continue;
    for (uint32_t g = 0; g < static_groups; ++g) {
      if (patches.shooter_bake_patch[g] != be.index) continue;
      const uint32_t id = addGroupEmitter(g, true, group_flux[g], max_flux);
      emitters[id].bake_emitter = i;
      initBakeShares(emitters[id]);
    }
  }
  return Status();
}

uint32_t Runtime::Impl::addGroupEmitter(uint32_t group, bool bright, double wanted_flux, double max_flux) {
  if (group_emitter[group] != kInvalidId) {
    emitters[group_emitter[group]].needs_baseline |= bright && group < static_groups;
    return group_emitter[group];
  }
  Emitter e;
  e.kind = group < static_groups ? EmitterKind::kStaticPatch : EmitterKind::kDynamicObject;
  e.index = group < static_groups ? group : group - static_groups;
  e.needs_baseline = bright && group < static_groups;
  if (e.kind == EmitterKind::kStaticPatch) {
    for (uint32_t r : patches.shooter_members[group]) e.flux += patches.baseline[r] * double(receivers[r].area_m2);
  }
  if (e.kind == EmitterKind::kDynamicObject) e.flux = glm::dvec3(wanted_flux);
  e.sample_count = sampleCount(wanted_flux, max_flux, settings);
  emitters.push_back(std::move(e));
  group_emitter[group] = uint32_t(emitters.size() - 1);
  return group_emitter[group];
}

void Runtime::Impl::refreshSamples(Emitter& e) {
  const uint64_t seed = settings.seed;
  const bool jitter = settings.jitter_map_roll;
  const uint64_t stream = (uint64_t(e.kind) << 40) ^ e.index;
  switch (e.kind) {
    case EmitterKind::kBakedLight: {
      const Light& light = scene.lights[bake.emitters[e.index].index];
      e.flux = dvec(light.color) * double(light.intensity) * rt::lightLobeSolidAngle(light);
      e.samples = rt::lightSamples(light, e.sample_count, seed, stream, jitter);
      break;
    }
    case EmitterKind::kSun: {
      const double side = 2.0 * double(window.radius_m);
      e.flux = dvec(scene.sun.color) * double(scene.sun.illuminance_lux) * side * side;
      e.samples = rt::sunSamples(scene.sun, window, e.sample_count, seed, jitter);
      break;
    }
    case EmitterKind::kSky: {
      Rgb flux;
      e.samples = rt::skySamples(scene.sky, window, std::max(16, e.sample_count), seed, jitter, flux);
      e.flux = dvec(flux);
      break;
    }
    case EmitterKind::kStaticPatch: {
      // Samples where the group's baseline light is (thesis 5.4): density
      // by each member patch's baked exitance.
      std::vector<uint32_t> triangles;
      std::vector<double> density;
      bool any = false;
      for (uint32_t r : patches.shooter_members[e.index]) {
        const double b = std::max(0.0, lum(patches.baseline[r]));
        any |= b > 0;
        for (uint32_t t : patch_map_triangles[r]) {
          triangles.push_back(t);
          density.push_back(b);
        }
      }
      if (!any) density.clear();
      e.samples = rt::surfaceSamples(static_map, 0, triangles, density, e.sample_count, sample_offset_m, seed, stream, jitter);
      break;
    }
    case EmitterKind::kDynamicObject: {
      // One shooter per facing of the object (kObjectShooters bins of its
      // object-space normals): uniform samples over a flat-ish group need no
      // knowledge of where the light falls, so the result never depends on
      // the path the object took.
      const uint32_t o = e.index / kObjectShooters, bin = e.index % kObjectShooters;
      const rt::DynamicObject& object = objects[o];
      e.samples.clear();
      if (!object.visible || object.removed) break;
      rt::MapTriangles own;
      own.positions = object.world_positions;
      std::vector<uint32_t> triangles;
      for (uint32_t t = 0; t < object.albedo.size(); ++t) {
        if (object.shooter_bin[t] == bin) triangles.push_back(t);
      }
      own.front_receiver.resize(object.albedo.size(), rt::kNoReceiver);
      own.back_receiver.resize(object.albedo.size(), rt::kNoReceiver);
      e.samples = rt::surfaceSamples(own, uint32_t(static_map.triangleCount()) + object_map_base[o], triangles, {},
                                     e.sample_count, sample_offset_m, seed, stream, jitter);
      break;
    }
    case EmitterKind::kRuntimeLight: {
      const Light& light = lights[e.index].light;
      e.samples = rt::lightSamples(light, e.sample_count, seed, stream, jitter);
      break;
    }
  }
  e.samples_stale = false;
  e.lit_triangles.clear();  // what the old samples saw
}

void Runtime::Impl::invalidateMoved() {
  if (moved_boxes.empty()) return;
  // An emitter that cannot reach the box around every moved box (each
  // object's old and new place) reaches none of them: one test for most
  // emitters instead of one per box (8 boxes a frame on the sample house's
  // walk: 1.8 -> 0.9 ms a frame over the 8 x 8 house's 2,944 emitters).
  Aabb all;
  for (const Aabb& box : moved_boxes) grow(all, box);
  for (Emitter& e : emitters) {
    if (e.stale) continue;
    if (moved_boxes.size() > 1 && !reaches(e, all)) continue;
    for (const Aabb& box : moved_boxes) {
      if (reaches(e, box)) {
        e.stale = true;
        break;
      }
    }
  }
  moved_boxes.clear();
}

Status Runtime::Impl::gatherShares(std::vector<uint32_t> ids, bool baseline, FrameStats& stats) {
  if (ids.empty()) return Status();
  if (!baseline && settings.lit_set_culling) {
    // Static patches that shoot only deltas have no static-level maps of
    // their own; one first (same samples, once) gives them a lit set for
    // this and every later refresh, and a region that bounds their maps.
    std::vector<uint32_t> first_maps;
    for (uint32_t id : ids) {
      if (wantsLitSetMaps(emitters[id])) first_maps.push_back(id);
    }
    if (Status s = gatherShares(std::move(first_maps), true, stats); !s.ok()) return s;
  }
  const uint32_t receiver_count = uint32_t(receivers.size());
  renderer->setReceiverCount(receiver_count);
  // The baseline is the static level alone: hide dynamic triangles meanwhile.
  const bool hide_dynamic = baseline && dynamic_map.triangleCount() > 0;
  if (hide_dynamic) renderer->setDynamicTriangles(rt::MapTriangles{});
  // Slots x receivers floats come back per gather; bound that to ~64 MB.
  const size_t max_slots = std::max<size_t>(1, (size_t(16) << 20) / std::max<uint32_t>(receiver_count, 1));
  std::vector<float> shares;
  std::vector<uint32_t> seen;  // baseline gathers: per slot, the static triangles its maps showed
  const size_t seen_words = rt::triangleBitWords(static_map.triangleCount());
  Status status;
  for (size_t begin = 0; begin < ids.size() && status.ok(); begin += max_slots) {
    const size_t end = std::min(ids.size(), begin + max_slots);
    std::vector<rt::PointSample> samples;
    for (size_t i = begin; i < end; ++i) {
      Emitter& e = emitters[ids[i]];
      if (e.samples_stale || e.samples.empty()) refreshSamples(e);
      // With its baseline mapped, the emitter's region bounds everything it
      // lights and everything that can shadow it: the maps skip the rest.
      const bool bounded = !baseline && e.has_baseline && e.region.max.x < 1e38f;
      // Finer: the runs of static triangles its baseline maps showed (the
      // same samples; objects only hide static surfaces).
      const bool lit_set = !baseline && settings.lit_set_culling && !e.lit_triangles.empty();
      for (rt::PointSample s : e.samples) {
        s.slot = uint32_t(i - begin);
        if (bounded) s.reach = e.region;
        if (lit_set) s.static_triangles = &e.lit_triangles;
        samples.push_back(s);
      }
    }
    rt::GatherStats g;
    const auto t0 = Clock::now();
    status = renderer->gather(samples, uint32_t(end - begin), shares, &g, baseline ? &seen : nullptr);
    if (!status.ok()) break;
    const double ms = msSince(t0);
    if (!samples.empty()) ms_per_sample = 0.5 * ms_per_sample + 0.5 * ms / double(samples.size());
    stats.maps_ms += g.render_ms;
    stats.reduction_ms += g.reduce_ms + g.readback_ms;
    stats.samples_rendered += g.samples;
    stats.faces_rendered += g.faces_rendered;
    stats.triangles_drawn += g.triangles_drawn;
    stats.triangles_hidden += g.triangles_hidden;
    stats.texels_reduced += g.texels;
    stats.fallback_triangles += g.fallback_triangles;
    for (size_t i = begin; i < end; ++i) {
      Emitter& e = emitters[ids[i]];
      rt::SparseShares sparse;
      const float* row = shares.data() + (i - begin) * receiver_count;
      Aabb region, source;
      for (const rt::PointSample& s : e.samples) {
        if (s.lobe != rt::Lobe::kParallel) grow(source, s.position);
        if (s.lobe != rt::Lobe::kParallel) grow(region, s.position);
      }
      for (uint32_t r = 0; r < receiver_count; ++r) {
        if (!(row[r] > 0)) continue;
        sparse.receivers.push_back(r);
        sparse.shares.push_back(row[r]);
        if (r < static_receivers) {
          grow(region, patches.bounds[r]);
        } else {
          grow(region, receivers[r].centroid);
        }
      }
      sparse.indexBlocks();
      if (e.samples.empty() || e.samples.front().lobe == rt::Lobe::kParallel) {
        // Parallel light crosses the whole window: any change anywhere matters.
        region = Aabb{{-3e38f, -3e38f, -3e38f}, {3e38f, 3e38f, 3e38f}};
      }
      grow(e.source_box, source);
      e.region_known = true;
      e.reach_dirty = true;
      if (baseline) {
        e.baseline = std::move(sparse);
        e.has_baseline = true;
        const auto first = seen.begin() + ptrdiff_t((i - begin) * seen_words);
        e.lit_triangles.assign(first, first + ptrdiff_t(seen_words));
        grow(e.region, region);
      } else {
        setCurrent(e, std::move(sparse));
        e.stale = false;
        e.refreshed_frame = frame;
        e.region = region;
        if (e.has_baseline) {
          for (uint32_t r : e.baseline.receivers) grow(e.region, r < static_receivers ? patches.bounds[r] : Aabb{});
        }
        ++stats.emitters_refreshed;
      }
    }
  }
  if (hide_dynamic) renderer->setDynamicTriangles(dynamic_map);
  return status;
}

void Runtime::Impl::solve(FrameStats& stats, std::vector<std::pair<double, uint32_t>>& wanted) {
  const auto t0 = Clock::now();
  const size_t n = receivers.size();
  updateLightScale();
  sumEmitterDeltas();
  const std::vector<glm::dvec3>& first = first_flux;
  const std::vector<glm::dvec3>& direct = direct_flux;
  const std::vector<int32_t> group_of = receiverGroups();
  std::vector<const rt::SparseShares*> shooters(group_emitter.size(), nullptr);
  std::vector<uint64_t> revisions(group_emitter.size(), 0);
  for (size_t g = 0; g < group_emitter.size(); ++g) {
    const uint32_t id = group_emitter[g];
    if (id == kInvalidId || !emitters[id].has_current) continue;
    shooters[g] = &emitters[id].current;
    revisions[g] = emitters[id].current_revision;
  }
  rt::BounceSettings bounce;
  bounce.max_bounces = settings.max_bounces;
  bounce.stop_share = settings.bounce_stop_share;
  bounce.ambient = settings.ambient_compensation;
  const rt::BounceResult& result = bounce_solver.solve(receivers, first, group_of, shooters, revisions, bounce);
  stats.bounce_rounds = uint32_t(result.rounds);
  stats.unshot_share = result.unshot_share;
  for (size_t r = 0; r < n; ++r) {
    const double area = receivers[r].area_m2;
    delta_total[r] = area > 0 ? result.received[r] / area : glm::dvec3(0.0);
    runtime_direct[r] = area > 0 ? direct[r] / area : glm::dvec3(0.0);
  }
  // A flat face of an object made of several triangles shows one value:
  // average coplanar triangles (the per-triangle estimates come from few
  // samples each and would otherwise differ across a face's diagonal).
  // Linear in the triangles: the faces are known from binObjectTriangles.
  std::vector<glm::dvec3> face_sum;
  std::vector<double> face_area;
  for (const rt::DynamicObject& object : objects) {
    const size_t count = object.albedo.size();
    if (!object.visible || object.removed || object.flat_face.size() != count) continue;
    face_sum.assign(count, glm::dvec3(0.0));
    face_area.assign(count, 0.0);
    for (size_t t = 0; t < count; ++t) {
      const double area = receivers[object.first_receiver + t].area_m2;
      face_sum[object.flat_face[t]] += delta_total[object.first_receiver + t] * area;
      face_area[object.flat_face[t]] += area;
    }
    for (size_t t = 0; t < count; ++t) {
      const uint32_t f = object.flat_face[t];
      if (face_area[f] > 0) delta_total[object.first_receiver + t] = face_sum[f] / face_area[f];
    }
  }
  for (size_t g = 0; g < result.wanted.size(); ++g) {
    if (result.wanted[g] > 0) wanted.push_back({result.wanted[g], uint32_t(g)});
  }
  vertex_deltas_stale = true;
  std::sort(wanted.begin(), wanted.end(), [](auto& a, auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  stats.bounce_ms += msSince(t0);
}

// An object is lit once the emitters that carry light to it (a baked light,
// the sun, the sky, a lamp or bright patch: those with a baseline) and have
// rendered shares since it appeared carry all but kUnlitShare of its light,
// each weighed by flux over squared distance from its source to the object.
// A partial sum of its emitters would draw it darker than the probe grid
// does (black after the first update), so it keeps the probes until then;
// waiting for every last dim emitter would keep it there for as long as
// importance caching lets those wait. Once lit, later moves refresh its
// emitters one by one from values that are already nearly whole.
void Runtime::Impl::updateObjectsLit() {
  constexpr double kUnlitShare = 0.05;
  for (rt::DynamicObject& object : objects) {
    if (object.lit || !object.visible || object.removed || object.bounds.empty()) continue;
    const glm::dvec3 low(toGlm(object.bounds.min)), high(toGlm(object.bounds.max));
    const glm::dvec3 centre = 0.5 * (low + high);
    const double radius2 = 0.25 * glm::dot(high - low, high - low);
    double total = 0, missing = 0;
    for (const Emitter& e : emitters) {
      if (!e.needs_baseline || !reaches(e, object.bounds)) continue;
      // The sun's and sky's source is their window over the level, about as
      // far as it is wide: flux over squared distance is then about their
      // illuminance, as it is a lamp's irradiance.
      const glm::dvec3 source = e.source_box.empty() ? centre
                                                     : 0.5 * (glm::dvec3(toGlm(e.source_box.min)) +
                                                              glm::dvec3(toGlm(e.source_box.max)));
      const glm::dvec3 d = source - centre;
      const double weight = std::max(0.0, lum(e.flux)) / std::max(glm::dot(d, d), radius2);
      total += weight;
      if (!e.has_current || e.current_revision <= object.shown_revision) missing += weight;
    }
    object.lit = missing <= kUnlitShare * total;
  }
}

void Runtime::Impl::uploadDisplay(FrameStats& stats) {
  const auto t0 = Clock::now();
  const size_t n = receivers.size();
  const float blend = settings.temporal_blend;
  std::vector<float> packed(n * 4, 0.0f);
  for (size_t r = 0; r < n; ++r) {
    const glm::dvec3 target = delta_total[r] - runtime_direct[r];
    Rgb& d = display[r];
    d = {d.r + blend * (float(target.x) - d.r), d.g + blend * (float(target.y) - d.g), d.b + blend * (float(target.z) - d.b)};
    packed[r * 4] = d.r;
    packed[r * 4 + 1] = d.g;
    packed[r * 4 + 2] = d.b;
    packed[r * 4 + 3] = r < static_receivers ? float(lightScaleOf(uint32_t(r)) - 1.0) : 0.0f;
  }
  // A dynamic receiver's w says whether its object is lit: shading keeps
  // the probes' light for one that is not (Impl::updateObjectsLit).
  for (const rt::DynamicObject& object : objects) {
    const size_t end = std::min(n, size_t(object.first_receiver) + object.albedo.size());
    for (size_t r = object.first_receiver; r < end; ++r) packed[r * 4 + 3] = object.lit ? 1.0f : 0.0f;
  }
  if (delta_buffer_receivers < n) {
    // Grows only when objects are added; a steady scene never allocates.
    if (delta_buffer != 0) glDeleteBuffers(1, &delta_buffer);
    glCreateBuffers(1, &delta_buffer);
    glNamedBufferStorage(delta_buffer, GLsizeiptr(n * 4 * sizeof(float)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    delta_buffer_receivers = uint32_t(n);
    ++gl_objects_created;
  }
  glNamedBufferSubData(delta_buffer, 0, GLsizeiptr(n * 4 * sizeof(float)), packed.data());
  // The static deltas and light scales at the welded vertices of the
  // runtime patches, as shading interpolates them per pixel.
  std::vector<glm::dvec3> shown(static_receivers), scale(static_receivers);
  for (uint32_t r = 0; r < static_receivers; ++r) {
    shown[r] = dvec(display[r]);
    scale[r] = glm::dvec3(lightScaleOf(r) - 1.0);
  }
  const std::vector<glm::dvec3> shown_at_vertices = rt::vertexValues(patches, shown);
  // Empty while every baked emitter is as baked (a factor of 1 everywhere).
  vertex_scales = light_scale.empty() ? std::vector<glm::dvec3>{} : rt::vertexValues(patches, scale);
  const std::vector<glm::dvec3>& scale_at_vertices = vertex_scales;
  if (!delta_surface.allocated()) {
    delta_surface = rt::DeltaSurfaceBuffers::create(patches);
    gl_objects_created += 3;
  }
  delta_surface.upload(shown_at_vertices, scale_at_vertices);
  if (!settings.delta_textures) {
    stats.upload_ms += msSince(t0);
    return;
  }
  // The same deltas in lightmap space.
  std::vector<std::pair<int, int>> sizes;
  for (const LightmapImage& page : pages) sizes.push_back({page.width, page.height});
  const std::vector<rt::DeltaPage> atlas = rt::rasteriseDeltas(patches, shown_at_vertices, scale_at_vertices, sizes);
  if (delta_textures.empty()) {
    delta_textures.resize(atlas.size());
    glCreateTextures(GL_TEXTURE_2D, GLsizei(atlas.size()), delta_textures.data());
    for (size_t p = 0; p < atlas.size(); ++p) {
      glTextureStorage2D(delta_textures[p], 1, GL_RGBA32F, atlas[p].width, atlas[p].height);
      glTextureParameteri(delta_textures[p], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTextureParameteri(delta_textures[p], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTextureParameteri(delta_textures[p], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTextureParameteri(delta_textures[p], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    gl_objects_created += uint32_t(atlas.size());
  }
  for (size_t p = 0; p < atlas.size(); ++p) {
    glTextureSubImage2D(delta_textures[p], 0, 0, 0, atlas[p].width, atlas[p].height, GL_RGBA, GL_FLOAT,
                        atlas[p].rgba.data());
  }
  stats.upload_ms += msSince(t0);
}

FrameStats Runtime::Impl::update(double budget_ms) {
  const auto start = Clock::now();
  FrameStats stats;
  ++frame;
  gl_objects_created = 0;
  const bool anything_due = std::any_of(emitters.begin(), emitters.end(), [&](const Emitter& e) {
    return settings.refresh_all ? needsMaps(e) : (outOfDate(e) && needsMaps(e)) || (e.stale && e.needs_baseline);
  });
  if (!have_content || (!dynamic_geometry_changed && !lighting_changed && !anything_due && !pending_wanted)) {
    stats.idle = true;
    stats.total_ms = msSince(start);
    return stats;
  }
  if (Status s = ensureRenderer(); !s.ok()) {
    stats.error = s.message();
    stats.total_ms = msSince(start);
    return stats;
  }
  if (dynamic_geometry_changed) {
    dynamic_map = rt::dynamicMapTriangles(objects);
    object_map_base.assign(objects.size(), 0);
    uint32_t base = 0;
    for (size_t o = 0; o < objects.size(); ++o) {
      object_map_base[o] = base;
      if (objects[o].visible && !objects[o].removed) base += uint32_t(objects[o].albedo.size());
    }
    renderer->setDynamicTriangles(dynamic_map);
    renderer->setReceiverCount(uint32_t(receivers.size()));
    // Every dynamic emitter's samples follow its triangle (and its place in the map set).
    for (Emitter& e : emitters) {
      if (e.kind == EmitterKind::kDynamicObject) e.samples_stale = true;
    }
    // Emissive objects are primary emitters.
    double max_flux = 0;
    for (const Emitter& e : emitters) max_flux = std::max(max_flux, lum(e.flux));
    for (size_t o = 0; o < objects.size(); ++o) {
      const rt::DynamicObject& object = objects[o];
      double flux = 0;
      for (size_t t = 0; t < object.emission.size(); ++t) {
        flux += 3.14159265358979 * luminance(object.emission[t]) * receivers[object.first_receiver + t].area_m2;
      }
      for (uint32_t bin = 0; flux > 0 && bin < kObjectShooters; ++bin) {
        const uint32_t g = static_groups + uint32_t(o) * kObjectShooters + bin;
        if (group_emitter[g] == kInvalidId) addGroupEmitter(g, false, flux, std::max(max_flux, flux));
      }
    }
    dynamic_geometry_changed = false;
  }
  for (size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].emitter != kInvalidId || lights[i].removed) continue;
    Emitter e;
    e.kind = EmitterKind::kRuntimeLight;
    e.index = uint32_t(i);
    e.sample_count = settings.min_samples_per_emitter;
    emitters.push_back(std::move(e));
    lights[i].emitter = uint32_t(emitters.size() - 1);
  }
  invalidateMoved();
  updateReach();
  lighting_changed = false;
  if (settings.refresh_all) {
    for (Emitter& e : emitters) {
      if (needsMaps(e)) e.stale = true;
    }
  }
  // A baked emitter with nothing dynamic in its reach and its baked scale
  // adds exactly nothing: it settles to its baseline without a map.
  for (Emitter& e : emitters) {
    if (!e.needs_baseline || !e.stale || needsMaps(e)) continue;
    if (e.has_baseline) {
      setCurrent(e, e.baseline);
    } else {
      retractCurrent(e);
      e.has_current = false;
      e.current = {};
    }
    e.stale = false;
    e.waiting = false;
  }

  // Which emitters refresh: by importance for the view (thesis 5.10), or
  // brightest first without one.
  const bool by_view = has_view && settings.importance_caching && !settings.refresh_all;
  if (by_view) {
    rankForView(stats);
  } else {
    top_importance = 0;
    for (Emitter& e : emitters) {
      e.importance = std::max(0.0, lum(e.flux)) * std::max(1.0, emitterScale(e));
      e.interval = 1;
    }
  }
  const std::vector<rt::RefreshCandidate> candidates = refreshCandidates();
  double budget = std::numeric_limits<double>::infinity();
  if (!settings.refresh_all) {
    if (budget_ms > 0) budget = std::max(0.0, budget_ms - msSince(start)) / ms_per_sample;
    if (settings.max_samples_per_frame > 0) budget = std::min(budget, double(settings.max_samples_per_frame));
  }
  const std::vector<rt::RefreshDecision> decisions = rt::scheduleRefreshes(
      candidates, frame, by_view ? top_importance : 0.0, by_view ? uint32_t(settings.max_refresh_interval) : 1u, budget);
  Status status;
  // Baselines first (the static level's shares, once per emitter); an
  // emitter nothing dynamic reaches then needs no second map.
  std::vector<uint32_t> baseline_ids, current_ids;
  for (const rt::RefreshDecision& d : decisions) {
    Emitter& e = emitters[d.emitter];
    if (e.needs_baseline && !e.has_baseline) baseline_ids.push_back(d.emitter);
    RefreshReason reason = d.reason;
    if (!by_view && reason != RefreshReason::kLightChanged) reason = RefreshReason::kNoView;
    if (settings.refresh_all) reason = RefreshReason::kRefreshAll;
    stats.refreshes.push_back({d.emitter, reason, d.importance});
  }
  status = gatherShares(baseline_ids, true, stats);
  for (uint32_t id : baseline_ids) {
    Emitter& e = emitters[id];
    e.touched = reachesAnyObject(e);  // its reach is known now
    if (!e.touched) {
      setCurrent(e, e.baseline);
      e.stale = false;
      e.refreshed_frame = frame;
      ++stats.emitters_refreshed;
    } else {
      e.stale = true;
    }
  }
  for (const rt::RefreshDecision& d : decisions) {
    Emitter& e = emitters[d.emitter];
    if (e.stale || !e.has_current) current_ids.push_back(d.emitter);
  }
  if (status.ok()) status = gatherShares(current_ids, false, stats);
  for (const rt::RefreshDecision& d : decisions) {
    Emitter& e = emitters[d.emitter];
    if (!outOfDate(e)) e.waiting = false;
    e.region_known = e.region_known || e.has_current;
  }
  if (by_view) settleImportance(decisions);
  // Bounce; receivers whose reflected delta had no shares to go through get
  // emitters (fewer samples as energy falls), budget permitting, and the
  // bounce is solved again with them.
  std::vector<std::pair<double, uint32_t>> wanted;
  solve(stats, wanted);
  for (int pass = 0; status.ok() && pass < 2 && !wanted.empty() && msSince(start) < (budget_ms > 0 ? budget_ms : 1e300); ++pass) {
    double total = 0, covered = 0;
    for (auto& [w, r] : wanted) total += w;
    std::vector<uint32_t> fresh;
    for (auto& [w, r] : wanted) {
      if (covered >= (1.0 - settings.bounce_stop_share) * total) break;
      covered += w;
      const uint32_t id = addGroupEmitter(r, false, w, wanted.front().first);
      emitters[id].bounce_requested = true;
      if (!emitters[id].has_current) fresh.push_back(id);
    }
    // Within what is left of the budget, most wanted first (the order of `wanted`).
    std::vector<rt::RefreshCandidate> bounce_candidates;
    for (uint32_t id : fresh) {
      rt::RefreshCandidate c;
      c.emitter = id;
      c.importance = double(fresh.size() - bounce_candidates.size());
      c.cost = double(std::max(emitters[id].sample_count, 1));
      bounce_candidates.push_back(c);
    }
    double left = budget;
    for (const EmitterRefresh& r : stats.refreshes) left -= double(std::max<size_t>(emitters[r.emitter].samples.size(), 1));
    // No budget left: the wanted shooters wait for the scheduler (by
    // importance) instead of one each pass and a solve again for it.
    if (!stats.refreshes.empty() && left <= 0) break;
    const std::vector<rt::RefreshDecision> chosen =
        rt::scheduleRefreshes(bounce_candidates, frame, 0.0, 1, stats.refreshes.empty() ? budget : left);
    if (chosen.empty()) break;
    std::vector<uint32_t> ids;
    for (const rt::RefreshDecision& d : chosen) {
      ids.push_back(d.emitter);
      stats.refreshes.push_back({d.emitter, RefreshReason::kBounce, emitters[d.emitter].importance});
    }
    status = gatherShares(ids, false, stats);
    for (uint32_t id : ids) emitters[id].region_known = true;
    wanted.clear();
    solve(stats, wanted);
  }
  pending_wanted = false;
  for (auto& [w, r] : wanted) {
    if (group_emitter[r] == kInvalidId || !emitters[group_emitter[r]].has_current) pending_wanted = true;
  }
  if (!status.ok()) stats.error = status.message();
  for (const Emitter& e : emitters) {
    if (outOfDate(e) && needsMaps(e)) ++stats.emitters_pending;
  }
  updateObjectsLit();
  uploadDisplay(stats);
  stats.gl_objects_created = gl_objects_created;
  stats.total_ms = msSince(start);
  return stats;
}

}  // namespace svit

// An emitter's shares, brought up to date: which emitters the moved boxes
// invalidate, their point samples (thesis 5.4), and the index-map gathers
// that turn samples into shares per receiver (thesis 5.2).

#include <algorithm>
#include <chrono>

#include "lighting/aabb_ops.h"
#include "runtime_impl.h"
#include "scene/numeric.h"

namespace svit {
namespace {

using rt::grow;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

void addGatherStats(FrameStats& stats, const rt::GatherStats& g) {
  stats.maps_ms += g.render_ms;
  stats.reduction_ms += g.reduce_ms + g.readback_ms;
  stats.samples_rendered += g.samples;
  stats.faces_rendered += g.faces_rendered;
  stats.triangles_drawn += g.triangles_drawn;
  stats.triangles_hidden += g.triangles_hidden;
  stats.texels_reduced += g.texels;
  stats.fallback_triangles += g.fallback_triangles;
}

/// Samples where a static group's baseline light is (thesis 5.4): density
/// by each member patch's baked exitance.
std::vector<rt::PointSample> staticPatchSamples(const rt::StaticLevel& level, const Emitter& e,
                                                uint64_t seed, uint64_t stream, bool jitter) {
  std::vector<uint32_t> triangles;
  std::vector<double> density;
  bool any = false;
  for (uint32_t r : level.patches.shooter_members[e.index]) {
    const double b = std::max(0.0, luminanceOf(level.patches.baseline[r]));
    any |= b > 0;
    for (uint32_t t : level.patch_map_triangles[r]) {
      triangles.push_back(t);
      density.push_back(b);
    }
  }
  if (!any) density.clear();
  return rt::surfaceSamples(level.static_map, 0, triangles, density, e.sample_count,
                            level.sample_offset_m, seed, stream, jitter);
}

}  // namespace

void Runtime::Impl::invalidateMoved() {
  std::vector<Aabb>& moved = changes.moved_boxes;
  if (moved.empty()) return;
  // An emitter that cannot reach the box around every moved box (each
  // object's old and new place) reaches none of them: one test for most
  // emitters instead of one per box.
  Aabb all;
  for (const Aabb& box : moved) grow(all, box);
  for (Emitter& e : emitter_set.emitters) {
    if (e.isStale()) continue;
    if (moved.size() > 1 && !reaches(e, all)) continue;
    for (const Aabb& box : moved) {
      if (reaches(e, box)) {
        e.markStale();
        break;
      }
    }
  }
  moved.clear();
}

/// One shooter per facing of the object (kObjectShooters bins of its
/// object-space normals): uniform samples over a flat-ish group need no
/// knowledge of where the light falls, so the result never depends on the
/// path the object took.
std::vector<rt::PointSample> Runtime::Impl::objectFacingSamples(const Emitter& e, uint64_t seed,
                                                                uint64_t stream,
                                                                bool jitter) const {
  const uint32_t o = e.index / kObjectShooters, bin = e.index % kObjectShooters;
  const rt::DynamicObject& object = objects[o];
  if (!object.visible || object.removed) return {};
  rt::MapTriangles own;
  own.positions = object.world_positions;
  std::vector<uint32_t> triangles;
  for (uint32_t t = 0; t < object.albedo.size(); ++t) {
    if (object.shooter_bin[t] == bin) triangles.push_back(t);
  }
  own.front_receiver.resize(object.albedo.size(), rt::kNoReceiver);
  own.back_receiver.resize(object.albedo.size(), rt::kNoReceiver);
  return rt::surfaceSamples(own, uint32_t(level.static_map.triangleCount()) + object_map_base[o],
                            triangles, {}, e.sample_count, level.sample_offset_m, seed, stream,
                            jitter);
}

void Runtime::Impl::refreshSamples(Emitter& e) {
  const uint64_t seed = settings.seed;
  const bool jitter = settings.jitter_map_roll;
  const uint64_t stream = (uint64_t(e.kind) << 40) ^ e.index;
  const Scene& scene = level.scene;
  switch (e.kind) {
    case EmitterKind::kBakedLight: {
      const Light& light = scene.lights[level.bake.emitters[e.index].index];
      e.flux = dvec(light.color) * double(light.intensity) * rt::lightLobeSolidAngle(light);
      e.samples = rt::lightSamples(light, e.sample_count, seed, stream, jitter);
      break;
    }
    case EmitterKind::kSun: {
      const double side = 2.0 * double(level.window.radius_m);
      e.flux = dvec(scene.sun.color) * double(scene.sun.illuminance_lux) * side * side;
      e.samples = rt::sunSamples(scene.sun, level.window, e.sample_count, seed, jitter);
      break;
    }
    case EmitterKind::kSky: {
      Rgb flux;
      e.samples =
          rt::skySamples(scene.sky, level.window, std::max(16, e.sample_count), seed, jitter, flux);
      e.flux = dvec(flux);
      break;
    }
    case EmitterKind::kStaticPatch:
      e.samples = staticPatchSamples(level, e, seed, stream, jitter);
      break;
    case EmitterKind::kDynamicObject:
      e.samples = objectFacingSamples(e, seed, stream, jitter);
      break;
    case EmitterKind::kRuntimeLight:
      e.samples = rt::lightSamples(lights[e.index].light, e.sample_count, seed, stream, jitter);
      break;
  }
  e.samples_stale = false;
  e.lit_triangles.clear();  // what the old samples saw
}

/// The samples of emitters [begin, end) of `ids`, each in its slot, with
/// the culling its cached maps allow.
std::vector<rt::PointSample> Runtime::Impl::batchSamples(const std::vector<uint32_t>& ids,
                                                         size_t begin, size_t end, bool baseline) {
  std::vector<rt::PointSample> samples;
  for (size_t i = begin; i < end; ++i) {
    Emitter& e = emitter_set.emitters[ids[i]];
    if (e.samples_stale || e.samples.empty()) refreshSamples(e);
    // With its baseline mapped, the emitter's region bounds everything it
    // lights and everything that can shadow it: the maps skip the rest.
    const bool bounded = !baseline && e.has_baseline && !e.reach.region.isEverything();
    // Finer: the runs of static triangles its baseline maps showed (the
    // same samples; objects only hide static surfaces).
    const bool lit_set = !baseline && settings.lit_set_culling && !e.lit_triangles.empty();
    for (rt::PointSample s : e.samples) {
      s.slot = uint32_t(i - begin);
      if (bounded) s.reach = e.reach.region;
      if (lit_set) s.static_triangles = &e.lit_triangles;
      samples.push_back(s);
    }
  }
  return samples;
}

/// One slot's row of shares as sparse shares, and the box of its samples
/// and of everything they lit.
rt::SparseShares Runtime::Impl::sparseRow(const Emitter& e, const float* row, Aabb& region,
                                          Aabb& source) const {
  const uint32_t receiver_count = uint32_t(receivers.size());
  for (const rt::PointSample& s : e.samples) {
    if (s.lobe != rt::Lobe::kParallel) grow(source, s.position);
    if (s.lobe != rt::Lobe::kParallel) grow(region, s.position);
  }
  rt::SparseShares sparse;
  for (uint32_t k = 0; k < receiver_count; ++k) {
    if (!(row[k] > 0)) continue;
    sparse.receivers.push_back(k);
    sparse.shares.push_back(row[k]);
    if (k < level.static_receivers) {
      grow(region, level.patches.bounds[k]);
    } else {
      grow(region, receivers[k].centroid);
    }
  }
  sparse.indexBlocks();
  if (e.samples.empty() || e.samples.front().lobe == rt::Lobe::kParallel) {
    // Parallel light crosses the whole window: any change anywhere matters.
    region = Aabb::everything();
  }
  return sparse;
}

/// Stores a gathered row as the emitter's baseline (with the static
/// triangles its maps saw) or as its current shares.
void Runtime::Impl::storeShares(Emitter& e, const float* row, const uint32_t* seen,
                                size_t seen_words, bool baseline, FrameStats& stats) {
  Aabb region, source;
  rt::SparseShares sparse = sparseRow(e, row, region, source);
  grow(e.reach.source_box, source);
  e.reach.region_known = true;
  e.reach.touched_dirty = true;
  if (baseline) {
    e.baseline = std::move(sparse);
    e.has_baseline = true;
    e.lit_triangles.assign(seen, seen + seen_words);
    grow(e.reach.region, region);
    return;
  }
  accumulator.setCurrent(e, std::move(sparse));
  e.queue.refreshed_frame = changes.frame;
  e.reach.region = region;
  if (e.has_baseline) {
    for (uint32_t k : e.baseline.receivers) {
      grow(e.reach.region, k < level.static_receivers ? level.patches.bounds[k] : Aabb{});
    }
  }
  ++stats.emitters_refreshed;
}

Status Runtime::Impl::gatherShares(std::vector<uint32_t> ids, bool baseline, FrameStats& stats) {
  if (ids.empty()) return Status();
  if (!baseline && settings.lit_set_culling) {
    // Static patches that shoot only deltas have no static-level maps of
    // their own; one first (same samples, once) gives them a lit set for
    // this and every later refresh, and a region that bounds their maps.
    std::vector<uint32_t> first_maps;
    for (uint32_t id : ids) {
      if (wantsLitSetMaps(emitter_set.emitters[id])) first_maps.push_back(id);
    }
    if (Status s = gatherShares(std::move(first_maps), true, stats); !s.ok()) return s;
  }
  const uint32_t receiver_count = uint32_t(receivers.size());
  renderer->setReceiverCount(receiver_count);
  // The baseline is the static level alone: hide dynamic triangles meanwhile.
  const bool hide_dynamic = baseline && dynamic_map.triangleCount() > 0;
  if (hide_dynamic) renderer->setDynamicTriangles(rt::MapTriangles{});
  // Slots x receivers floats come back per gather; bound that to ~64 MB.
  const size_t max_slots =
      std::max<size_t>(1, (size_t(16) << 20) / std::max<uint32_t>(receiver_count, 1));
  std::vector<float> shares;
  std::vector<uint32_t> seen;  // baseline gathers: per slot, the static triangles its maps showed
  const size_t seen_words = rt::triangleBitWords(level.static_map.triangleCount());
  Status status;
  for (size_t begin = 0; begin < ids.size() && status.ok(); begin += max_slots) {
    const size_t end = std::min(ids.size(), begin + max_slots);
    const std::vector<rt::PointSample> samples = batchSamples(ids, begin, end, baseline);
    rt::GatherStats g;
    const auto t0 = Clock::now();
    status =
        renderer->gather(samples, uint32_t(end - begin), shares, &g, baseline ? &seen : nullptr);
    if (!status.ok()) break;
    const double ms = msSince(t0);
    if (!samples.empty()) ms_per_sample = 0.5 * ms_per_sample + 0.5 * ms / double(samples.size());
    addGatherStats(stats, g);
    for (size_t i = begin; i < end; ++i) {
      const float* row = shares.data() + (i - begin) * receiver_count;
      const uint32_t* slot_seen = baseline ? seen.data() + (i - begin) * seen_words : nullptr;
      storeShares(emitter_set.emitters[ids[i]], row, slot_seen, seen_words, baseline, stats);
    }
  }
  if (hide_dynamic) renderer->setDynamicTriangles(dynamic_map);
  return status;
}

}  // namespace svit

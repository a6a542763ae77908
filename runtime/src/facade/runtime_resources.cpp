// Runtime::resources(): what the runtime holds, measured, and why; or what
// it left out, and why (the "pay for what is used" audit).

#include <string>
#include <vector>

#include "gl/gl_memory.h"
#include "runtime_impl.h"

namespace svit {
namespace {

template <typename T>
uint64_t vectorBytes(const std::vector<T>& v) {
  return uint64_t(v.capacity()) * sizeof(T);
}

template <typename T>
uint64_t nestedBytes(const std::vector<std::vector<T>>& v) {
  uint64_t bytes = vectorBytes(v);
  for (const std::vector<T>& inner : v) bytes += vectorBytes(inner);
  return bytes;
}

uint64_t mapTriangleBytes(const rt::MapTriangles& m) {
  return vectorBytes(m.positions) + vectorBytes(m.front_receiver) + vectorBytes(m.back_receiver);
}

uint64_t patchBytes(const rt::RuntimePatches& p) {
  return vectorBytes(p.receivers) + vectorBytes(p.baseline) + vectorBytes(p.emission) +
         vectorBytes(p.bake_patch) + vectorBytes(p.shooter) + vectorBytes(p.bounds) +
         nestedBytes(p.bake_members) + nestedBytes(p.shooter_members) +
         vectorBytes(p.shooter_bake_patch) + mapTriangleBytes(p.triangles) +
         vectorBytes(p.triangle_vertices) + vectorBytes(p.triangle_page) +
         vectorBytes(p.triangle_uvs) + vectorBytes(p.element_n) +
         vectorBytes(p.element_first_slot) + vectorBytes(p.slots);
}

const std::string kNoContent = "the level has no dynamic objects and no runtime lights";

ResourceUse pagesUse(const rt::StaticLevel& level) {
  ResourceUse pages;
  pages.name = "lightmap pages (host copy)";
  pages.allocated = !level.pages.empty();
  for (const LightmapImage& page : level.pages) pages.cpu_bytes += vectorBytes(page.rgb);
  pages.reason = "irradianceAt() and the lightmap textures read the baked irradiance from here";
  return pages;
}

ResourceUse lightmapTexturesUse(const rt::ShadingOutputs& outputs) {
  ResourceUse lightmaps = rt::measuredUse("lightmap textures", outputs.lightmapObjects());
  lightmaps.reason =
      lightmaps.allocated
          ? "shadingResources() asked for them (SceneRenderer borrows these: one copy)"
          : "shadingResources() not called: a host with its own copy pays nothing here";
  return lightmaps;
}

ResourceUse patchesUse(const rt::StaticLevel& level, const rt::ShadingOutputs& outputs,
                       const RuntimeSettings& settings) {
  ResourceUse patches;
  patches.name = "runtime patches (receivers, sub-triangles, map triangles)";
  patches.allocated = level.bake.has_runtime_sections;
  if (!patches.allocated) {
    patches.reason =
        "the bake has no runtime sections (" + kNoContent + " when baked): static level";
    return patches;
  }
  patches.cpu_bytes = patchBytes(level.patches) + mapTriangleBytes(level.static_map) +
                      nestedBytes(level.patch_map_triangles) + outputs.hostBytes() +
                      vectorBytes(level.static_block_bounds);
  patches.reason =
      std::to_string(level.static_receivers) + " patches, " +
      std::to_string(level.static_map.triangleCount()) +
      (settings.use_proxies ? " proxy" : " full-geometry") +
      " map triangles: the bake has runtime sections, so objects and lights may come at any time";
  return patches;
}

ResourceUse objectsUse(const std::vector<rt::DynamicObject>& objects, const rt::ObjectSlots& slots,
                       const rt::MapTriangles& dynamic_map) {
  ResourceUse use;
  use.name = "dynamic objects (triangles, receivers)";
  use.allocated = !objects.empty();
  for (const rt::DynamicObject& o : objects) {
    use.cpu_bytes += vectorBytes(o.object_positions) + vectorBytes(o.albedo) +
                     vectorBytes(o.emission) + vectorBytes(o.shooter_bin) +
                     vectorBytes(o.world_positions);
  }
  use.cpu_bytes += mapTriangleBytes(dynamic_map);
  // The records themselves: one per slot, as many as were ever alive at
  // once (a removed object's slot goes to the next one added).
  use.cpu_bytes += vectorBytes(objects) + slots.bytes();
  const uint32_t live = slots.liveCount();
  use.reason = use.allocated ? std::to_string(live) + " objects in " +
                                   std::to_string(objects.size()) + " slots"
                             : "no dynamic objects";
  return use;
}

ResourceUse cachesUse(const std::vector<Emitter>& emitters, const rt::BounceSolver& bounce_solver,
                      bool have_content) {
  ResourceUse caches;
  caches.name = "emitter caches (point samples, form factors)";
  caches.allocated = !emitters.empty();
  uint32_t cached = 0;
  for (const Emitter& e : emitters) {
    caches.cpu_bytes +=
        vectorBytes(e.samples) + e.current.bytes() + e.baseline.bytes() + e.bake_shares.bytes();
    cached += e.hasCurrent() ? 1u : 0u;
  }
  caches.cpu_bytes += vectorBytes(emitters);  // the records (a removed object's leave)
  // the last frame's bounce rounds and the shares they went through
  caches.cpu_bytes += bounce_solver.bytes();
  caches.reason = caches.allocated ? std::to_string(emitters.size()) + " emitters, " +
                                         std::to_string(cached) + " with maps cached"
                                   : (have_content ? "no update() yet" : kNoContent);
  return caches;
}

ResourceUse mapsUse(const rt::IndexMapRenderer* renderer, const RuntimeSettings& settings,
                    bool have_content) {
  ResourceUse maps =
      rt::measuredUse("index maps, geometry and reduction buffers",
                      renderer ? renderer->mapObjects() : std::vector<rt::GlObject>{});
  if (renderer) maps.cpu_bytes = renderer->hostBytes();
  maps.reason = maps.allocated
                    ? std::to_string(settings.map_resolution) +
                          "^2 maps, made on the first update with "
                          "dynamic content"
                    : (have_content ? "no update() yet" : kNoContent + ": no emitter needs a map");
  return maps;
}

ResourceUse viewUse(const rt::IndexMapRenderer* renderer, const RuntimeSettings& settings) {
  ResourceUse view =
      rt::measuredUse("camera id pass (importance)",
                      renderer ? renderer->viewObjects() : std::vector<rt::GlObject>{});
  view.reason = view.allocated ? "setView() gave a camera: visible patches rank the emitters"
                               : (!settings.importance_caching
                                      ? "importance caching is off"
                                      : "no camera: setView() not called, or no maps needed");
  return view;
}

/// The patch delta buffer, the delta surface and the delta textures.
void deltaUses(const rt::StaticLevel& level, const rt::ShadingOutputs& outputs,
               const RuntimeSettings& settings, bool have_content, std::vector<ResourceUse>& out) {
  ResourceUse deltas =
      rt::measuredUse("patch delta buffer", {rt::glBufferObject(outputs.deltaBuffer())});
  deltas.reason =
      deltas.allocated
          ? std::to_string(outputs.deltaBufferReceivers()) + " patches: what shading adds"
          : (have_content ? "no update() yet" : kNoContent + ": nothing to add to the lightmaps");
  out.push_back(deltas);

  ResourceUse surface = rt::measuredUse("delta surface buffers (per-pixel lookup)",
                                        outputs.deltaSurface().glObjects());
  surface.reason = surface.allocated
                       ? std::to_string(level.patches.vertex_count) +
                             " welded vertices of the runtime patches: svit_runtime_delta.frag"
                       : deltas.reason;
  out.push_back(surface);

  ResourceUse delta_pages =
      rt::measuredUse("delta textures (half-resolution pages)", outputs.deltaTextureObjects());
  delta_pages.reason =
      delta_pages.allocated ? "lightmap(uv) + delta(uv) shading (RuntimeSettings::delta_textures)"
      : !settings.delta_textures
          ? "RuntimeSettings::delta_textures off: the host looks deltas up per pixel"
          : deltas.reason;
  out.push_back(delta_pages);
}

}  // namespace

std::vector<ResourceUse> Runtime::resources() const {
  const Impl& r = *impl_;
  std::vector<ResourceUse> out;
  out.push_back(pagesUse(r.level));
  out.push_back(lightmapTexturesUse(r.outputs));
  out.push_back(patchesUse(r.level, r.outputs, r.settings));
  out.push_back(objectsUse(r.objects, r.object_slots, r.dynamic_map));
  out.push_back(cachesUse(r.emitter_set.emitters, r.bounce_solver, r.have_content));
  out.push_back(mapsUse(r.renderer.get(), r.settings, r.have_content));
  out.push_back(viewUse(r.renderer.get(), r.settings));
  deltaUses(r.level, r.outputs, r.settings, r.have_content, out);
  return out;
}

}  // namespace svit

// Runtime::resources(): what the runtime holds, measured, and why; or what
// it left out, and why (the "pay for what is used" audit).

#include <string>
#include <vector>

#include "gl_memory.h"
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
  return vectorBytes(p.receivers) + vectorBytes(p.baseline) + vectorBytes(p.emission) + vectorBytes(p.bake_patch) +
         vectorBytes(p.shooter) + vectorBytes(p.bounds) + nestedBytes(p.bake_members) +
         nestedBytes(p.shooter_members) + vectorBytes(p.shooter_bake_patch) + mapTriangleBytes(p.triangles) +
         vectorBytes(p.triangle_vertices) + vectorBytes(p.triangle_page) + vectorBytes(p.triangle_uvs) +
         vectorBytes(p.element_n) + vectorBytes(p.element_first_slot) + vectorBytes(p.slots);
}

}  // namespace

std::vector<ResourceUse> Runtime::resources() const {
  const Impl& r = *impl_;
  const bool runtime_sections = r.bake.has_runtime_sections;
  const std::string no_content = "the level has no dynamic objects and no runtime lights";
  std::vector<ResourceUse> out;

  ResourceUse pages;
  pages.name = "lightmap pages (host copy)";
  pages.allocated = !r.pages.empty();
  for (const LightmapImage& page : r.pages) pages.cpu_bytes += vectorBytes(page.rgb);
  pages.reason = "irradianceAt() and the lightmap textures read the baked irradiance from here";
  out.push_back(pages);

  std::vector<rt::GlObject> lightmap_objects;
  for (uint32_t t : r.lightmap_textures) lightmap_objects.push_back(rt::glTextureObject(t));
  ResourceUse lightmaps = rt::measuredUse("lightmap textures", lightmap_objects);
  lightmaps.reason = lightmaps.allocated ? "shadingResources() asked for them (SceneRenderer borrows these: one copy)"
                                         : "shadingResources() not called: a host with its own copy pays nothing here";
  out.push_back(lightmaps);

  ResourceUse patches;
  patches.name = "runtime patches (receivers, sub-triangles, map triangles)";
  patches.allocated = runtime_sections;
  if (runtime_sections) {
    patches.cpu_bytes = patchBytes(r.patches) + mapTriangleBytes(r.static_map) + nestedBytes(r.patch_map_triangles) +
                        vectorBytes(r.delta_total) + vectorBytes(r.runtime_direct) + vectorBytes(r.display) +
                        vectorBytes(r.vertex_deltas) + vectorBytes(r.static_block_bounds);
    patches.reason = std::to_string(r.static_receivers) + " patches, " + std::to_string(r.static_map.triangleCount()) +
                     (r.settings.use_proxies ? " proxy" : " full-geometry") +
                     " map triangles: the bake has runtime sections, so objects and lights may come at any time";
  } else {
    patches.reason = "the bake has no runtime sections (" + no_content + " when baked): static level";
  }
  out.push_back(patches);

  ResourceUse objects;
  objects.name = "dynamic objects (triangles, receivers)";
  objects.allocated = !r.objects.empty();
  for (const rt::DynamicObject& o : r.objects) {
    objects.cpu_bytes += vectorBytes(o.object_positions) + vectorBytes(o.albedo) + vectorBytes(o.emission) +
                         vectorBytes(o.shooter_bin) + vectorBytes(o.world_positions);
  }
  objects.cpu_bytes += mapTriangleBytes(r.dynamic_map);
  objects.reason = objects.allocated ? std::to_string(r.objects.size()) + " objects" : "no dynamic objects";
  out.push_back(objects);

  ResourceUse caches;
  caches.name = "emitter caches (point samples, form factors)";
  caches.allocated = !r.emitters.empty();
  uint32_t cached = 0;
  for (const Emitter& e : r.emitters) {
    caches.cpu_bytes += vectorBytes(e.samples) + e.current.bytes() + e.baseline.bytes() + e.bake_shares.bytes();
    cached += e.has_current ? 1u : 0u;
  }
  caches.cpu_bytes += r.bounce_solver.bytes();  // the last frame's bounce rounds and the shares they went through
  caches.reason = caches.allocated ? std::to_string(r.emitters.size()) + " emitters, " + std::to_string(cached) +
                                         " with maps cached"
                                   : (r.have_content ? "no update() yet" : no_content);
  out.push_back(caches);

  ResourceUse maps = rt::measuredUse("index maps, geometry and reduction buffers",
                            r.renderer ? r.renderer->mapObjects() : std::vector<rt::GlObject>{});
  if (r.renderer) maps.cpu_bytes = r.renderer->hostBytes();
  maps.reason = maps.allocated ? std::to_string(r.settings.map_resolution) + "^2 maps, made on the first update with "
                                                                             "dynamic content"
                               : (r.have_content ? "no update() yet" : no_content + ": no emitter needs a map");
  out.push_back(maps);

  ResourceUse view = rt::measuredUse("camera id pass (importance)",
                                     r.renderer ? r.renderer->viewObjects() : std::vector<rt::GlObject>{});
  view.reason = view.allocated ? "setView() gave a camera: visible patches rank the emitters"
                               : (!r.settings.importance_caching ? "importance caching is off"
                                                                 : "no camera: setView() not called, or no maps needed");
  out.push_back(view);

  ResourceUse deltas = rt::measuredUse("patch delta buffer", {rt::glBufferObject(r.delta_buffer)});
  deltas.reason = deltas.allocated ? std::to_string(r.delta_buffer_receivers) + " patches: what shading adds"
                                   : (r.have_content ? "no update() yet" : no_content + ": nothing to add to the lightmaps");
  out.push_back(deltas);

  ResourceUse surface = rt::measuredUse("delta surface buffers (per-pixel lookup)", r.delta_surface.glObjects());
  surface.reason = surface.allocated ? std::to_string(r.patches.vertex_count) +
                                           " welded vertices of the runtime patches: svit_runtime_delta.frag"
                                     : deltas.reason;
  out.push_back(surface);

  std::vector<rt::GlObject> delta_objects;
  for (uint32_t t : r.delta_textures) delta_objects.push_back(rt::glTextureObject(t));
  ResourceUse delta_pages = rt::measuredUse("delta textures (half-resolution pages)", delta_objects);
  delta_pages.reason = delta_pages.allocated ? "lightmap(uv) + delta(uv) shading (RuntimeSettings::delta_textures)"
                      : !r.settings.delta_textures
                          ? "RuntimeSettings::delta_textures off: the host looks deltas up per pixel"
                          : deltas.reason;
  out.push_back(delta_pages);
  return out;
}

}  // namespace svit

#include "static_level.h"

#include <algorithm>

#include "aabb_ops.h"
#include "bounce_solver.h"
#include "scene/glm_interop.h"

namespace svit::gl {
namespace {

bool hasDynamicContent(const Scene& scene) {
  bool dynamic_content = false;
  for (const Instance& instance : scene.instances) dynamic_content |= instance.dynamic;
  for (const Light& light : scene.lights) dynamic_content |= light.dynamic;
  return dynamic_content;
}

/// The runtime patches, about settings.target_patches over the static
/// surfaces (both sides of double-sided ones), and the tables derived from
/// them.
Status buildPatches(StaticLevel& level, const RuntimeSettings& settings) {
  double area = 0;
  for (size_t t = 0; t < level.surfaces.triangleCount(); ++t) {
    area += level.surfaces.area(t) * (level.surfaces.doubleSided(t) ? 2 : 1);
  }
  const double max_area = area / double(settings.target_patches);
  Expected<RuntimePatches> patches =
      buildRuntimePatches(level.scene, level.bake, level.surfaces, level.pages, level.masked,
                          max_area, area / double(settings.target_shooters));
  if (!patches.ok())
    return Status(patches.status().code(), level.bake_dir + ": " + patches.status().message());
  level.patches = std::move(patches).value();
  level.static_receivers = uint32_t(level.patches.receivers.size());
  level.static_groups = uint32_t(level.patches.shooter_members.size());
  level.static_map =
      inRunOrder(settings.use_proxies ? proxyMapTriangles(level.bake, level.patches, max_area)
                                      : level.patches.triangles);
  level.static_block_bounds.assign(level.static_receivers / kShareBlockReceivers, Aabb{});
  for (uint32_t p = 0; p < level.static_block_bounds.size() * kShareBlockReceivers; ++p) {
    grow(level.static_block_bounds[p / kShareBlockReceivers], level.patches.bounds[p]);
  }
  level.patch_map_triangles.assign(level.static_receivers, {});
  for (uint32_t t = 0; t < level.static_map.triangleCount(); ++t) {
    const uint32_t front = level.static_map.front_receiver[t];
    if (front != kNoReceiver) level.patch_map_triangles[front].push_back(t);
  }
  return Status();
}

void placeWindow(StaticLevel& level) {
  const Aabb& b = level.surfaces.bounds();
  const glm::vec3 lo = toGlm(b.min), hi = toGlm(b.max);
  level.window.centre = fromGlm(0.5f * (lo + hi));
  level.window.radius_m = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  level.sample_offset_m =
      1e-4f * level.window.radius_m + 1e-6f * glm::length(toGlm(level.window.centre));
}

}  // namespace

Expected<StaticLevel> buildStaticLevel(const Scene& scene, const BakeData& bake,
                                       const std::string& bake_dir,
                                       const RuntimeSettings& settings) {
  StaticLevel level;
  level.scene = scene;
  level.bake = bake;
  level.bake_dir = bake_dir;
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok())
    return Status(surfaces.status().code(), bake_dir + ": " + surfaces.status().message());
  level.surfaces = std::move(surfaces).value();
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(bake, bake_dir);
  if (!pages.ok()) return pages.status();
  level.pages = std::move(pages).value();
  Expected<MaskedLightField> masked = MaskedLightField::create(scene, bake, level.surfaces);
  if (!masked.ok())
    return Status(masked.status().code(), bake_dir + "/" + masked.status().message());
  level.masked = std::move(masked).value();
  level.bake.masks.pages.clear();  // the field holds them; not twice
  if (hasDynamicContent(scene) && !bake.has_runtime_sections) {
    return Status(StatusCode::kInvalidInput,
                  bake_dir +
                      ": the bake has no runtime sections but the level has dynamic "
                      "objects or lights; bake it again with this svit");
  }
  if (bake.has_runtime_sections) {
    if (Status s = buildPatches(level, settings); !s.ok()) return s;
  }
  placeWindow(level);
  return level;
}

}  // namespace svit::gl

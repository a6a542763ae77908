// Static geometry for the SceneRenderer: the bake's triangles with lightmap
// UVs, batched by material, page and emitter; each corner names its bake
// elements, where the runtime's per-patch delta is looked up per pixel.

#include "scene_renderer_static_mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include <glm/glm.hpp>

#include "scene/glm_interop.h"
#include "svit/baked_surfaces.h"

namespace svit::gl {
namespace {

glm::mat3 normalMatrix(const Mat4& world_from_object) {
  return glm::transpose(glm::inverse(glm::mat3(toGlm(world_from_object))));
}

}  // namespace

size_t countBakeableStaticTriangles(const Scene& scene) {
  size_t count = 0;
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic || instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size())
      continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const glm::mat4 world = toGlm(instance.world_from_object);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec3(
            transformPoint(world, toGlm(mesh.positions[mesh.indices[t * 3 + size_t(k)]])));
      }
      // The baker's test (bake_geometry.cpp): height/edge below float
      // resolution counts as zero area.
      const double area = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      const double longest2 =
          std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                    glm::dot(p[0] - p[2], p[0] - p[2])});
      if (2.0 * area > 1e-7 * longest2 && std::isfinite(area)) ++count;
    }
  }
  return count;
}

namespace {

// The bake and the level agree on the static triangles and their pages.
Status checkBakeTriangles(const Scene& scene, const BakeData& bake) {
  const size_t triangle_count = bake.triangle_uvs.size();
  const size_t level_count = countBakeableStaticTriangles(scene);
  if (level_count != triangle_count) {
    return Status(StatusCode::kInvalidInput,
                  "bake lists " + std::to_string(triangle_count) + " static triangles, the level " +
                      scene.source_path + " has " + std::to_string(level_count) +
                      ": bake the level again");
  }
  return Status();
}

Status checkPages(const BakeData& bake) {
  for (size_t t = 0; t < bake.triangle_uvs.size(); ++t) {
    if (bake.triangle_uvs[t].page >= bake.pages.size()) {
      return Status(StatusCode::kInvalidInput,
                    "bake triangle " + std::to_string(t) + ": lightmap page " +
                        std::to_string(bake.triangle_uvs[t].page) + " >= page count " +
                        std::to_string(bake.pages.size()));
    }
  }
  return Status();
}

// Per bake triangle: its material, and the front-side shading normal of
// each corner (into corner_normal, 3 per triangle).
std::vector<uint32_t> triangleMaterials(const Scene& scene, const BakeData& bake,
                                        const BakedSurfaces& surfaces,
                                        std::vector<glm::vec3>& corner_normal) {
  const size_t triangle_count = bake.triangle_uvs.size();
  std::vector<uint32_t> material(triangle_count);
  corner_normal.assign(triangle_count * 3, glm::vec3(0.0f));
  int cached_instance = -1;
  glm::mat3 normal_from_object(1.0f);
  for (size_t t = 0; t < triangle_count; ++t) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const Instance& instance = scene.instances[uv.instance];
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    material[t] = mesh.triangle_material[uv.mesh_triangle];
    if (int(uv.instance) != cached_instance) {
      cached_instance = int(uv.instance);
      normal_from_object = normalMatrix(instance.world_from_object);
    }
    const glm::vec3 face = toGlm(surfaces.normal(t));
    for (int k = 0; k < 3; ++k) {
      glm::vec3 n = face;
      if (!mesh.normals.empty()) {
        const glm::vec3 m =
            normal_from_object *
            toGlm(mesh.normals[mesh.indices[size_t(uv.mesh_triangle) * 3 + size_t(k)]]);
        const float length = glm::length(m);
        // A mirroring transform keeps the front counter-clockwise in world
        // space (as the baker lights it): the shading normal follows.
        if (length > 0 && std::isfinite(length))
          n = glm::dot(m, face) < 0 ? -m / length : m / length;
      }
      corner_normal[t * 3 + size_t(k)] = n;
    }
  }
  return material;
}

// The kPatch bake emitter of each emissive triangle side (element t * 2 +
// side), so a dimmed lamp can be drawn dimmed: its own batches. Error: a
// patch element out of range.
Expected<std::vector<uint32_t>> elementEmitters(const Scene& scene, const BakeData& bake,
                                                const std::vector<uint32_t>& material) {
  const size_t triangle_count = bake.triangle_uvs.size();
  std::vector<uint32_t> emitter(triangle_count * 2, kNoBakeEmitter);
  std::vector<uint32_t> patch_emitter(bake.patches.size(), kNoBakeEmitter);
  for (uint32_t e = 0; e < bake.emitters.size(); ++e) {
    const BakeEmitter& be = bake.emitters[e];
    if (be.kind == BakeEmitter::Kind::kPatch && be.index < patch_emitter.size())
      patch_emitter[be.index] = e;
  }
  for (uint32_t p = 0; p < bake.patches.size(); ++p) {
    if (patch_emitter[p] == kNoBakeEmitter) continue;
    const BakePatch& patch = bake.patches[p];
    for (uint32_t i = patch.first_element; i < patch.first_element + patch.element_count; ++i) {
      const uint32_t element = i < bake.patch_elements.size() ? bake.patch_elements[i] : UINT32_MAX;
      if (element / 2 >= triangle_count) {
        return Status(StatusCode::kInvalidInput, "bake patch " + std::to_string(p) + ": element " +
                                                     std::to_string(i) + " out of range");
      }
      const Material& m = scene.materials[material[element / 2]];
      const bool emits =
          m.emissive_luminance.r > 0 || m.emissive_luminance.g > 0 || m.emissive_luminance.b > 0;
      if (emits) emitter[element] = patch_emitter[p];
    }
  }
  return emitter;
}

// One draw of a triangle: the sides it shows, with that lightmap and emitter.
struct DrawnTriangle {
  uint32_t triangle = 0;
  DrawnSides sides = DrawnSides::kBoth;
  uint32_t page = 0;
  const Vec2* uv = nullptr;  ///< 3 lightmap corners
  uint32_t emitter = kNoBakeEmitter;
};

// Each triangle once (both sides), or twice where its back has a lightmap
// of its own; drawn both sides, the front side's emitter wins over the back's.
std::vector<DrawnTriangle> drawnTriangles(const BakeData& bake,
                                          const std::vector<uint32_t>& element_emitter) {
  std::vector<DrawnTriangle> drawn;
  drawn.reserve(bake.triangle_uvs.size() + bake.back_uvs.size());
  for (uint32_t t = 0; t < bake.triangle_uvs.size(); ++t) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const uint32_t front = element_emitter[t * 2], back = element_emitter[t * 2 + 1];
    const BakeBackUv* back_uv = findBackUv(bake, t);
    if (!back_uv) {
      drawn.push_back(
          {t, DrawnSides::kBoth, uv.page, uv.uv, front != kNoBakeEmitter ? front : back});
      continue;
    }
    drawn.push_back({t, DrawnSides::kFront, uv.page, uv.uv, front});
    drawn.push_back({t, DrawnSides::kBack, back_uv->page, back_uv->uv, back});
  }
  return drawn;
}

// Batches: draws ordered by (sides, material, page, emitter), bake order
// within; their vertices appended to out.
void appendBatches(const Scene& scene, const BakeData& bake, const BakedSurfaces& surfaces,
                   const std::vector<uint32_t>& material,
                   const std::vector<uint32_t>& element_emitter,
                   const std::vector<glm::vec3>& corner_normal, StaticMesh& out) {
  std::vector<DrawnTriangle> drawn = drawnTriangles(bake, element_emitter);
  std::stable_sort(drawn.begin(), drawn.end(), [&](const DrawnTriangle& x, const DrawnTriangle& y) {
    return std::tie(x.sides, material[x.triangle], x.page, x.emitter) <
           std::tie(y.sides, material[y.triangle], y.page, y.emitter);
  });
  out.vertices.reserve(drawn.size() * 3);
  for (const DrawnTriangle& d : drawn) {
    const uint32_t t = d.triangle;
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const StaticBatch* last = out.batches.empty() ? nullptr : &out.batches.back();
    if (!last || last->sides != d.sides || last->material != material[t] || last->page != d.page ||
        last->emitter != d.emitter) {
      out.batches.push_back(
          {d.sides, material[t], d.page, d.emitter, uint32_t(out.vertices.size()), 0});
    }
    const Mesh& mesh = scene.meshes[size_t(scene.instances[uv.instance].mesh)];
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = mesh.indices[size_t(uv.mesh_triangle) * 3 + size_t(k)];
      StaticVertex v{};
      const Vec3& p = surfaces.corner(t, k);
      const glm::vec3& n = corner_normal[size_t(t) * 3 + size_t(k)];
      v.position[0] = p.x, v.position[1] = p.y, v.position[2] = p.z;
      v.normal[0] = n.x, v.normal[1] = n.y, v.normal[2] = n.z;
      if (!mesh.uv0.empty()) v.uv0[0] = mesh.uv0[index].x, v.uv0[1] = mesh.uv0[index].y;
      if (!mesh.uv1.empty()) v.uv1[0] = mesh.uv1[index].x, v.uv1[1] = mesh.uv1[index].y;
      v.uv_lightmap[0] = d.uv[k].x, v.uv_lightmap[1] = d.uv[k].y;
      v.delta_element[0] = t * 2;
      v.delta_element[1] = t * 2 + 1;
      out.vertices.push_back(v);
    }
    out.batches.back().vertex_count += 3;
  }
}

}  // namespace

Expected<StaticMesh> buildStaticMesh(const Scene& scene, const BakeData& bake) {
  if (Status s = checkBakeTriangles(scene, bake); !s.ok()) return s;
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok()) return surfaces.status();
  if (Status s = checkPages(bake); !s.ok()) return s;
  StaticMesh out;
  out.bounds = surfaces->bounds();
  std::vector<glm::vec3> corner_normal;
  const std::vector<uint32_t> material = triangleMaterials(scene, bake, *surfaces, corner_normal);
  Expected<std::vector<uint32_t>> emitter = elementEmitters(scene, bake, material);
  if (!emitter.ok()) return emitter.status();
  appendBatches(scene, bake, *surfaces, material, *emitter, corner_normal, out);
  return out;
}

}  // namespace svit::gl

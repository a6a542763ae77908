// Static geometry for the SceneRenderer: the bake's triangles with lightmap
// UVs, and the welded vertices the per-patch deltas are interpolated at
// (DESIGN.md "Patches"), by the vertex rule of thesis ch. 4 that DESIGN.md
// "T-vertices" restates: a vertex takes the area-weighted mean of the
// elements around it, and hard edges stay hard (vertices weld only across
// equal shading normals).

#include "scene_renderer_static_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>

#include <glm/glm.hpp>

#include "glm_interop.h"
#include "svit/baked_surfaces.h"

namespace svit::gl {
namespace {

constexpr uint32_t kNoPatch = std::numeric_limits<uint32_t>::max();

// Position and normal of a triangle side's corner, quantised for welding.
struct WeldKey {
  int64_t p[3];
  int32_t n[3];
  auto tie() const { return std::tie(p[0], p[1], p[2], n[0], n[1], n[2]); }
  bool operator<(const WeldKey& o) const { return tie() < o.tie(); }
  bool operator==(const WeldKey& o) const { return tie() == o.tie(); }
};

glm::mat3 normalMatrix(const Mat4& world_from_object) {
  return glm::transpose(glm::inverse(glm::mat3(toGlm(world_from_object))));
}

}  // namespace

size_t countBakeableStaticTriangles(const Scene& scene) {
  size_t count = 0;
  for (const Instance& instance : scene.instances) {
    if (instance.dynamic || instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const glm::mat4 world = toGlm(instance.world_from_object);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec3(transformPoint(world, toGlm(mesh.positions[mesh.indices[t * 3 + size_t(k)]])));
      }
      // The baker's test (bake_geometry.cpp): height/edge below float
      // resolution counts as zero area.
      const double area = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      const double longest2 = std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                                        glm::dot(p[0] - p[2], p[0] - p[2])});
      if (2.0 * area > 1e-7 * longest2 && std::isfinite(area)) ++count;
    }
  }
  return count;
}

Expected<StaticMesh> buildStaticMesh(const Scene& scene, const BakeData& bake) {
  const size_t triangle_count = bake.triangle_uvs.size();
  const size_t level_count = countBakeableStaticTriangles(scene);
  if (level_count != triangle_count) {
    return Status(StatusCode::kInvalidInput, "bake lists " + std::to_string(triangle_count) +
                                                 " static triangles, the level " + scene.source_path + " has " +
                                                 std::to_string(level_count) + ": bake the level again");
  }
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(scene, bake);
  if (!surfaces.ok()) return surfaces.status();
  for (size_t t = 0; t < triangle_count; ++t) {
    if (bake.triangle_uvs[t].page >= bake.pages.size()) {
      return Status(StatusCode::kInvalidInput, "bake triangle " + std::to_string(t) + ": lightmap page " +
                                                   std::to_string(bake.triangle_uvs[t].page) + " >= page count " +
                                                   std::to_string(bake.pages.size()));
    }
  }

  StaticMesh out;
  out.bounds = surfaces->bounds();

  // Per triangle: material and the front-side shading normal of each corner.
  std::vector<uint32_t> material(triangle_count);
  std::vector<glm::vec3> corner_normal(triangle_count * 3);
  {
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
      const glm::vec3 face = toGlm(surfaces->normal(t));
      for (int k = 0; k < 3; ++k) {
        glm::vec3 n = face;
        if (!mesh.normals.empty()) {
          const glm::vec3 m = normal_from_object * toGlm(mesh.normals[mesh.indices[size_t(uv.mesh_triangle) * 3 + size_t(k)]]);
          const float length = glm::length(m);
          // A mirroring transform keeps the front counter-clockwise in world
          // space (as the baker lights it): the shading normal follows.
          if (length > 0 && std::isfinite(length)) n = glm::dot(m, face) < 0 ? -m / length : m / length;
        }
        corner_normal[t * 3 + size_t(k)] = n;
      }
    }
  }

  // Welded vertices and their patches, only when there are patches.
  std::vector<uint32_t> welded(triangle_count * 6, 0);  // (t * 2 + side) * 3 + k
  if (!bake.patches.empty()) {
    std::vector<uint32_t> element_patch(triangle_count * 2, kNoPatch);
    for (uint32_t p = 0; p < bake.patches.size(); ++p) {
      const BakePatch& patch = bake.patches[p];
      for (uint32_t i = patch.first_element; i < patch.first_element + patch.element_count; ++i) {
        if (i >= bake.patch_elements.size() || bake.patch_elements[i] >= element_patch.size()) {
          return Status(StatusCode::kInvalidInput, "bake patch " + std::to_string(p) + ": element " +
                                                       std::to_string(i) + " out of range");
        }
        element_patch[bake.patch_elements[i]] = p;
      }
    }
    const Aabb& b = out.bounds;
    const double extent = std::max({double(b.max.x) - b.min.x, double(b.max.y) - b.min.y, double(b.max.z) - b.min.z});
    const double position_quantum = std::max(extent * 1e-6, 1e-9);  // metres
    const double normal_quantum = 0.01;  // unit vector components: ~0.6 degree
    std::vector<std::pair<WeldKey, uint32_t>> keys;  // key, corner slot
    keys.reserve(triangle_count * 3);
    for (size_t t = 0; t < triangle_count; ++t) {
      const int sides = surfaces->doubleSided(t) ? 2 : 1;
      for (int side = 0; side < sides; ++side) {
        for (int k = 0; k < 3; ++k) {
          const Vec3& p = surfaces->corner(t, k);
          const glm::vec3 n = corner_normal[t * 3 + size_t(k)] * (side == 0 ? 1.0f : -1.0f);
          WeldKey key;
          key.p[0] = std::llround((double(p.x) - b.min.x) / position_quantum);
          key.p[1] = std::llround((double(p.y) - b.min.y) / position_quantum);
          key.p[2] = std::llround((double(p.z) - b.min.z) / position_quantum);
          for (int c = 0; c < 3; ++c) key.n[c] = int32_t(std::lround(n[c] / normal_quantum));
          keys.push_back({key, uint32_t((t * 2 + size_t(side)) * 3 + size_t(k))});
        }
      }
    }
    std::sort(keys.begin(), keys.end(), [](const auto& x, const auto& y) {
      return x.first < y.first || (x.first == y.first && x.second < y.second);
    });
    uint32_t vertex_count = 0;
    for (size_t i = 0; i < keys.size(); ++i) {
      if (i > 0 && !(keys[i].first == keys[i - 1].first)) ++vertex_count;
      welded[keys[i].second] = vertex_count;
    }
    vertex_count = keys.empty() ? 0 : vertex_count + 1;
    // Single-sided backs are black: they point at the front's vertex, unused.
    for (size_t t = 0; t < triangle_count; ++t) {
      if (!surfaces->doubleSided(t)) {
        for (int k = 0; k < 3; ++k) welded[(t * 2 + 1) * 3 + size_t(k)] = welded[t * 2 * 3 + size_t(k)];
      }
    }
    // (vertex, patch, area) triples, merged per (vertex, patch).
    struct Entry {
      uint32_t vertex, patch;
      double weight;
    };
    std::vector<Entry> entries;
    entries.reserve(keys.size());
    for (const auto& [key, slot] : keys) {
      const size_t element = slot / 3, t = element / 2;
      const uint32_t patch = element_patch[element];
      if (patch == kNoPatch) continue;
      entries.push_back({welded[slot], patch, double(surfaces->area(t))});
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
      return std::tie(x.vertex, x.patch) < std::tie(y.vertex, y.patch);
    });
    DeltaInterpolation& d = out.deltas;
    d.vertex_count = vertex_count;
    d.offsets.assign(size_t(vertex_count) + 1, 0);
    size_t i = 0;
    for (uint32_t v = 0; v < vertex_count; ++v) {
      d.offsets[v] = uint32_t(d.patches.size());
      const size_t first = d.patches.size();
      double total = 0;
      for (; i < entries.size() && entries[i].vertex == v; ++i) {
        if (d.patches.size() > first && d.patches.back() == entries[i].patch) {
          d.weights.back() += float(entries[i].weight);
        } else {
          d.patches.push_back(entries[i].patch);
          d.weights.push_back(float(entries[i].weight));
        }
        total += entries[i].weight;
      }
      for (size_t j = first; j < d.patches.size(); ++j) d.weights[j] = total > 0 ? float(d.weights[j] / total) : 0.0f;
    }
    d.offsets[vertex_count] = uint32_t(d.patches.size());
  }

  // The kPatch bake emitter of each emissive triangle, so a dimmed lamp can
  // be drawn dimmed: its own batches.
  std::vector<uint32_t> emitter(triangle_count, kNoBakeEmitter);
  {
    std::vector<uint32_t> patch_emitter(bake.patches.size(), kNoBakeEmitter);
    for (uint32_t e = 0; e < bake.emitters.size(); ++e) {
      const BakeEmitter& be = bake.emitters[e];
      if (be.kind == BakeEmitter::Kind::kPatch && be.index < patch_emitter.size()) patch_emitter[be.index] = e;
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
        const bool emits = m.emissive_luminance.r > 0 || m.emissive_luminance.g > 0 || m.emissive_luminance.b > 0;
        // The front side's emitter wins over the back's.
        if (emits && (element % 2 == 0 || emitter[element / 2] == kNoBakeEmitter)) emitter[element / 2] = patch_emitter[p];
      }
    }
  }

  // Batches: triangles ordered by (material, page, emitter), bake order within.
  std::vector<uint32_t> order(triangle_count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
    return std::tie(material[x], bake.triangle_uvs[x].page, emitter[x]) <
           std::tie(material[y], bake.triangle_uvs[y].page, emitter[y]);
  });
  out.vertices.reserve(triangle_count * 3);
  for (uint32_t t : order) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    if (out.batches.empty() || out.batches.back().material != material[t] || out.batches.back().page != uv.page ||
        out.batches.back().emitter != emitter[t]) {
      out.batches.push_back({material[t], uv.page, emitter[t], uint32_t(out.vertices.size()), 0});
    }
    const Mesh& mesh = scene.meshes[size_t(scene.instances[uv.instance].mesh)];
    for (int k = 0; k < 3; ++k) {
      const uint32_t index = mesh.indices[size_t(uv.mesh_triangle) * 3 + size_t(k)];
      StaticVertex v{};
      const Vec3& p = surfaces->corner(t, k);
      const glm::vec3& n = corner_normal[size_t(t) * 3 + size_t(k)];
      v.position[0] = p.x, v.position[1] = p.y, v.position[2] = p.z;
      v.normal[0] = n.x, v.normal[1] = n.y, v.normal[2] = n.z;
      if (!mesh.uv0.empty()) v.uv0[0] = mesh.uv0[index].x, v.uv0[1] = mesh.uv0[index].y;
      if (!mesh.uv1.empty()) v.uv1[0] = mesh.uv1[index].x, v.uv1[1] = mesh.uv1[index].y;
      v.uv_lightmap[0] = uv.uv[k].x, v.uv_lightmap[1] = uv.uv[k].y;
      v.delta_vertex[0] = welded[size_t(t) * 6 + size_t(k)];
      v.delta_vertex[1] = welded[size_t(t) * 6 + 3 + size_t(k)];
      out.vertices.push_back(v);
    }
    out.batches.back().vertex_count += 3;
  }
  return out;
}

}  // namespace svit::gl

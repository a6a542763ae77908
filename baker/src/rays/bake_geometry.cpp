#include "svit/baker/bake_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/glm.hpp>

#include "scene/glm_interop.h"

namespace svit::baker {
namespace {

std::string vecText(const glm::dvec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%g, %g, %g)", p.x, p.y, p.z);
  return text;
}

// "file: node 'Name' mesh 'Mesh' triangle 3" for messages.
std::string triangleLabel(const Scene& scene, const Instance& instance, const Mesh& mesh,
                          size_t t) {
  std::string label = scene.source_path + ": ";
  if (instance.node >= 0 && size_t(instance.node) < scene.nodes.size()) {
    label += "node '" + scene.nodes[size_t(instance.node)].name + "' ";
  }
  label += "mesh '" + mesh.name + "'";
  if (t < mesh.triangle_source.size()) {
    label += " primitive " + std::to_string(mesh.triangle_source[t].primitive) + " triangle " +
             std::to_string(mesh.triangle_source[t].triangle);
  } else {
    label += " triangle " + std::to_string(t);
  }
  return label;
}

}  // namespace

Expected<BakeGeometry> flattenStaticGeometry(const Scene& scene, size_t* skipped_degenerate) {
  BakeGeometry geometry;
  size_t skipped = 0;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    if (instance.dynamic) continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const glm::mat4 world = toGlm(instance.world_from_object);
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec3(
            transformPoint(world, toGlm(mesh.positions[mesh.indices[t * 3 + size_t(k)]])));
        // Finite data under a finite transform can still overflow float
        // (a 3e38 m corner scaled by 2): an error, not a degenerate triangle.
        if (!std::isfinite(p[k].x) || !std::isfinite(p[k].y) || !std::isfinite(p[k].z)) {
          return Status(StatusCode::kInvalidInput,
                        triangleLabel(scene, instance, mesh, t) + ": corner " + std::to_string(k) +
                            " is " + vecText(p[k]) + " in world space, not a finite float");
        }
      }
      // A mirroring transform (negative determinant) keeps glTF's rule that
      // the front face is counter-clockwise in world space, so the normal is
      // taken from the transformed corners, not the mesh normals.
      const glm::dvec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
      const double area = 0.5 * glm::length(cross);
      // Same relative test as import (height/edge below float resolution),
      // for instances that squash a triangle flat.
      const double longest2 =
          std::max({glm::dot(p[1] - p[0], p[1] - p[0]), glm::dot(p[2] - p[1], p[2] - p[1]),
                    glm::dot(p[0] - p[2], p[0] - p[2])});
      if (!(area <= double(std::numeric_limits<float>::max()))) {
        return Status(StatusCode::kInvalidInput, triangleLabel(scene, instance, mesh, t) +
                                                     ": world-space area " + std::to_string(area) +
                                                     " m2 is beyond float range");
      }
      if (!(2.0 * area > 1e-7 * longest2)) {
        ++skipped;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        geometry.positions.push_back(fromGlm(glm::vec3(p[k])));
        const Vec3& q = geometry.positions.back();
        geometry.bounds.min = {std::min(geometry.bounds.min.x, q.x),
                               std::min(geometry.bounds.min.y, q.y),
                               std::min(geometry.bounds.min.z, q.z)};
        geometry.bounds.max = {std::max(geometry.bounds.max.x, q.x),
                               std::max(geometry.bounds.max.y, q.y),
                               std::max(geometry.bounds.max.z, q.z)};
      }
      geometry.normals.push_back(fromGlm(glm::vec3(cross / (2.0 * area))));
      geometry.areas_m2.push_back(float(area));
      geometry.albedo.push_back(mesh.triangle_albedo[t]);
      geometry.emission.push_back(mesh.triangle_emission[t]);
      geometry.double_sided.push_back(scene.materials[mesh.triangle_material[t]].double_sided ? 1
                                                                                              : 0);
      geometry.instance.push_back(uint32_t(i));
      geometry.mesh_triangle.push_back(uint32_t(t));
    }
  }
  if (skipped_degenerate) *skipped_degenerate = skipped;
  if (geometry.triangleCount() == 0) {
    return Status(StatusCode::kInvalidInput, scene.source_path + ": no static triangles to bake");
  }
  return geometry;
}

}  // namespace svit::baker

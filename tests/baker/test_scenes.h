#pragma once
// Scenes built in code for the baker's analytic tests: quads, boxes, disks,
// lights, each object its own static instance.

#include <cmath>
#include <string>
#include <vector>

#include "svit/scene.h"

namespace svit::test {

class SceneBuilder {
 public:
  /// A diffuse material; `emission` is luminance in cd/m2.
  int material(Rgb albedo, Rgb emission = {0, 0, 0}, bool double_sided = false) {
    Material m;
    m.name = "material " + std::to_string(scene_.materials.size());
    m.base_color = albedo;
    m.emissive_luminance = emission;
    m.double_sided = double_sided;
    scene_.materials.push_back(m);
    return int(scene_.materials.size() - 1);
  }

  /// Triangles with unshared corners; front faces counter-clockwise.
  int addMesh(const std::string& name, const std::vector<Vec3>& corners, int material) {
    Mesh mesh;
    mesh.name = name;
    for (size_t t = 0; t + 2 < corners.size(); t += 3) {
      const Vec3 a = corners[t], b = corners[t + 1], c = corners[t + 2];
      const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
      const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
      double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
      nx /= length;
      ny /= length;
      nz /= length;
      for (const Vec3& p : {a, b, c}) {
        mesh.indices.push_back(uint32_t(mesh.positions.size()));
        mesh.positions.push_back(p);
        mesh.normals.push_back({float(nx), float(ny), float(nz)});
      }
      const Material& m = scene_.materials[size_t(material)];
      mesh.triangle_material.push_back(uint32_t(material));
      mesh.triangle_albedo.push_back(m.base_color);
      mesh.triangle_emission.push_back(m.emissive_luminance);
      mesh.triangle_source.push_back({0, uint32_t(t / 3)});
    }
    scene_.meshes.push_back(mesh);
    Node node;
    node.name = name;
    node.mesh = int(scene_.meshes.size() - 1);
    scene_.nodes.push_back(node);
    Instance instance;
    instance.node = int(scene_.nodes.size() - 1);
    instance.mesh = node.mesh;
    scene_.instances.push_back(instance);
    return node.mesh;
  }

  /// Quad a-b-c-d, counter-clockwise seen from its front, as two triangles.
  int addQuad(const std::string& name, Vec3 a, Vec3 b, Vec3 c, Vec3 d, int material) {
    return addMesh(name, {a, b, c, a, c, d}, material);
  }

  /// Axis-aligned box [lo, hi] with faces pointing inwards (a closed room).
  void addRoom(const std::string& name, Vec3 lo, Vec3 hi, int material) {
    const float x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
    addQuad(name + " floor", {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0}, material);
    addQuad(name + " ceiling", {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}, material);
    addQuad(name + " -x", {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}, material);
    addQuad(name + " +x", {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}, material);
    addQuad(name + " -z", {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, material);
    addQuad(name + " +z", {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}, material);
  }

  /// Horizontal disk of `segments` triangles at height y, facing up or down.
  void addDisk(const std::string& name, Vec3 centre, float radius, int segments, bool facing_up,
               int material) {
    std::vector<Vec3> corners;
    for (int i = 0; i < segments; ++i) {
      const double a0 = 2.0 * 3.14159265358979323846 * i / segments;
      // The last segment closes on angle 0 exactly (sin(2 pi) is not 0 in
      // floating point, which would leave a seam of unwelded vertices).
      const double a1 = 2.0 * 3.14159265358979323846 * ((i + 1) % segments) / segments;
      const Vec3 p0{centre.x + radius * float(std::cos(a0)), centre.y,
                    centre.z + radius * float(std::sin(a0))};
      const Vec3 p1{centre.x + radius * float(std::cos(a1)), centre.y,
                    centre.z + radius * float(std::sin(a1))};
      // Counter-clockwise seen from +y is (centre, p1, p0) for increasing angle in x-z.
      if (facing_up) {
        corners.insert(corners.end(), {centre, p1, p0});
      } else {
        corners.insert(corners.end(), {centre, p0, p1});
      }
    }
    addMesh(name, corners, material);
  }

  void addPointLight(Vec3 position, float intensity_cd, Rgb color = {1, 1, 1}) {
    Light light;
    light.name = "point " + std::to_string(scene_.lights.size());
    light.type = LightType::kPoint;
    light.position = position;
    light.intensity = intensity_cd;
    light.color = color;
    scene_.lights.push_back(light);
  }

  Scene& scene() { return scene_; }

 private:
  Scene scene_;
};

/// Sum over triangles of (front irradiance x area): flux received, lm (luminance).
inline double receivedFlux(const std::vector<Rgb>& irradiance, const std::vector<float>& areas,
                           size_t begin = 0, size_t end = ~size_t(0)) {
  double sum = 0;
  for (size_t t = begin; t < irradiance.size() && t < end; ++t)
    sum += double(luminance(irradiance[t])) * areas[t];
  return sum;
}

}  // namespace svit::test

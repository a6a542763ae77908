#include "svit/baked_surfaces.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/glm.hpp>

#include "glm_interop.h"

namespace svit {
namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision
// Detection 5.1.5), returned as barycentrics (weights of b and c).
glm::dvec2 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {0, 0};
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {d1 / (d1 - d3), 0};
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {0, d2 / (d2 - d6)};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {1 - w, w};
  }
  const double denominator = 1.0 / (va + vb + vc);
  return {vb * denominator, vc * denominator};
}

glm::dvec3 dvec(const Vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

Expected<BakedSurfaces> BakedSurfaces::build(const Scene& scene, const BakeData& bake) {
  BakedSurfaces s;
  const size_t n = bake.triangle_uvs.size();
  s.positions_.reserve(n * 3);
  for (size_t t = 0; t < n; ++t) {
    const BakeTriangleUv& uv = bake.triangle_uvs[t];
    const std::string where = "bake triangle " + std::to_string(t);
    if (uv.instance >= scene.instances.size()) {
      return Status(StatusCode::kInvalidInput,
                    where + ": instance " + std::to_string(uv.instance) + " is not in the level");
    }
    const Instance& instance = scene.instances[uv.instance];
    if (instance.dynamic) {
      return Status(StatusCode::kInvalidInput, where + ": instance " + std::to_string(uv.instance) +
                                                   " is dynamic in the level");
    }
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    if (uv.mesh_triangle >= mesh.triangleCount()) {
      return Status(StatusCode::kInvalidInput,
                    where + ": mesh triangle " + std::to_string(uv.mesh_triangle) +
                        " >= triangle count " + std::to_string(mesh.triangleCount()));
    }
    const glm::mat4 world = toGlm(instance.world_from_object);
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = glm::dvec3(transformPoint(
          world, toGlm(mesh.positions[mesh.indices[size_t(uv.mesh_triangle) * 3 + size_t(k)]])));
      s.positions_.push_back(fromGlm(glm::vec3(p[k])));
      const Vec3& q = s.positions_.back();
      s.bounds_.min = {std::min(s.bounds_.min.x, q.x), std::min(s.bounds_.min.y, q.y),
                       std::min(s.bounds_.min.z, q.z)};
      s.bounds_.max = {std::max(s.bounds_.max.x, q.x), std::max(s.bounds_.max.y, q.y),
                       std::max(s.bounds_.max.z, q.z)};
    }
    // Normal from the transformed corners, as the baker takes it (mirroring
    // transforms keep counter-clockwise fronts in world space).
    const glm::dvec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double length = glm::length(cross);
    s.normals_.push_back(length > 0 ? fromGlm(glm::vec3(cross / length)) : Vec3{0, 1, 0});
    s.areas_m2_.push_back(float(0.5 * length));
    s.double_sided_.push_back(
        scene.materials[mesh.triangle_material[uv.mesh_triangle]].double_sided ? 1 : 0);
    // A back without texels of its own reads its front's.
    const BakeBackUv* back = findBackUv(bake, uint32_t(t));
    if (back && !s.double_sided_.back()) {
      return Status(StatusCode::kInvalidInput,
                    where + ": has a back lightmap (section BUVS) but is one-sided in the level");
    }
    s.page_.push_back(uv.page);
    s.page_.push_back(back ? back->page : uv.page);
    for (const Vec2& c : uv.uv) s.uvs_.push_back(c);
    for (const Vec2& c : back ? back->uv : uv.uv) s.uvs_.push_back(c);
  }
  return s;
}

std::optional<SurfaceHit> BakedSurfaces::nearest(const Vec3& point, const Vec3& normal,
                                                 double cos_limit) const {
  const glm::dvec3 p = dvec(point);
  const double length = glm::length(dvec(normal));
  if (!(length > 0)) return std::nullopt;
  const glm::dvec3 n = dvec(normal) / length;
  std::optional<SurfaceHit> best;
  for (uint32_t t = 0; t < triangleCount(); ++t) {
    const double facing = glm::dot(dvec(normals_[t]), n);
    int side = 0;
    if (facing < cos_limit) {
      if (!double_sided_[t] || -facing < cos_limit) continue;
      side = 1;
    }
    const glm::dvec3 a = dvec(corner(t, 0)), b = dvec(corner(t, 1)), c = dvec(corner(t, 2));
    const glm::dvec2 w = closestOnTriangle(p, a, b, c);
    const glm::dvec3 q = a + w.x * (b - a) + w.y * (c - a);
    const double d = glm::length(q - p);
    if (best && d >= best->distance_m) continue;
    SurfaceHit hit;
    hit.triangle = t;
    hit.side = side;
    hit.point = fromGlm(glm::vec3(q));
    hit.w1 = float(w.x);
    hit.w2 = float(w.y);
    hit.distance_m = d;
    hit.page = page_[size_t(t) * 2 + size_t(side)];
    const Vec2* uv = &uvs_[(size_t(t) * 2 + size_t(side)) * 3];
    hit.uv = {float((1 - w.x - w.y) * uv[0].x + w.x * uv[1].x + w.y * uv[2].x),
              float((1 - w.x - w.y) * uv[0].y + w.x * uv[1].y + w.y * uv[2].y)};
    best = hit;
  }
  return best;
}

Expected<std::vector<ProbePoint>> readProbePoints(const std::string& path) {
  std::ifstream file(path);
  if (!file) return Status(StatusCode::kNotFound, path + ": cannot open");
  std::vector<ProbePoint> points;
  std::string line;
  for (size_t number = 1; std::getline(file, line); ++number) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string token; in >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    double v[6];
    bool numbers = tokens.size() == 6;
    for (size_t i = 0; numbers && i < 6; ++i) {
      char* end = nullptr;
      v[i] = std::strtod(tokens[i].c_str(), &end);
      numbers = end != tokens[i].c_str() && *end == '\0';
    }
    if (!numbers) {
      return Status(StatusCode::kInvalidInput,
                    path + ":" + std::to_string(number) + ": expected 6 numbers 'x y z nx ny nz'");
    }
    for (double x : v) {
      if (!std::isfinite(x))
        return Status(StatusCode::kInvalidInput,
                      path + ":" + std::to_string(number) + ": not finite");
    }
    if (v[3] == 0 && v[4] == 0 && v[5] == 0) {
      return Status(StatusCode::kInvalidInput,
                    path + ":" + std::to_string(number) + ": the normal is zero");
    }
    points.push_back(
        {{float(v[0]), float(v[1]), float(v[2])}, {float(v[3]), float(v[4]), float(v[5])}});
  }
  return points;
}

Expected<std::vector<LightmapImage>> readLightmapPages(const BakeData& bake,
                                                       const std::string& bake_dir) {
  std::vector<LightmapImage> pages;
  for (const BakeLightmapPage& page : bake.pages) {
    Expected<LightmapImage> image =
        readLightmapExr((std::filesystem::path(bake_dir) / page.file).string());
    if (!image.ok()) return image.status();
    pages.push_back(std::move(image).value());
  }
  return pages;
}

}  // namespace svit

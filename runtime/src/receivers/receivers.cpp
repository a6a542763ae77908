#include "receivers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <glm/glm.hpp>

#include "scene/glm_interop.h"

namespace svit::gl {
namespace {

void grow(Aabb& box, const Vec3& p) {
  box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
  box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
}

// Per triangle: the first triangle with exactly the same corners, rotated
// so the smallest corner leads (a rotation keeps the winding).
std::vector<uint32_t> repeatedTriangles(const std::vector<Vec3>& positions) {
  using Corner = std::array<float, 3>;
  std::map<std::array<Corner, 3>, uint32_t> first;
  std::vector<uint32_t> same_as(positions.size() / 3);
  for (size_t t = 0; t < same_as.size(); ++t) {
    std::array<Corner, 3> corners;
    for (size_t k = 0; k < 3; ++k) {
      const Vec3& p = positions[t * 3 + k];
      corners[k] = {p.x, p.y, p.z};
    }
    const size_t lead = size_t(std::min_element(corners.begin(), corners.end()) - corners.begin());
    std::rotate(corners.begin(), corners.begin() + std::ptrdiff_t(lead), corners.end());
    same_as[t] = first.emplace(corners, uint32_t(t)).first->second;
  }
  return same_as;
}

}  // namespace

void binObjectTriangles(DynamicObject& object) {
  object.shooter_bin.resize(object.albedo.size());
  for (size_t t = 0; t < object.albedo.size(); ++t) {
    const glm::vec3 a = toGlm(object.object_positions[t * 3]),
                    b = toGlm(object.object_positions[t * 3 + 1]),
                    c = toGlm(object.object_positions[t * 3 + 2]);
    const glm::vec3 n = glm::cross(b - a, c - a), m = glm::abs(n);
    const int axis = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
    object.shooter_bin[t] = uint8_t(axis * 2 + (n[axis] < 0 ? 1 : 0));
  }
  // Flat faces, in object space (an affine placement keeps coplanar
  // triangles coplanar): same normal within 0.8 degrees, same plane offset
  // within 1e-4 of it.
  const size_t count = object.albedo.size();
  object.same_as = repeatedTriangles(object.object_positions);
  object.flat_face.resize(count);
  std::vector<glm::dvec4> planes(count);
  for (size_t t = 0; t < count; ++t) {
    const glm::dvec3 a(toGlm(object.object_positions[t * 3])),
        b(toGlm(object.object_positions[t * 3 + 1])), c(toGlm(object.object_positions[t * 3 + 2]));
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double length = glm::length(cross);
    const glm::dvec3 n = length > 0 ? cross / length : glm::dvec3(0.0);
    planes[t] = glm::dvec4(n, glm::dot(n, (a + b + c) / 3.0));
    object.flat_face[t] = uint32_t(t);
    if (object.same_as[t] != t) {
      object.flat_face[t] = object.flat_face[object.same_as[t]];
      continue;
    }
    if (count > kMaxFlatFaceTriangles || length == 0) continue;
    for (size_t u = 0; u < t; ++u) {
      const glm::dvec4& p = planes[u];
      if (glm::dot(glm::dvec3(p), n) < 0.9999 ||
          std::abs(p.w - planes[t].w) > 1e-4 * (1.0 + std::abs(p.w)))
        continue;
      object.flat_face[t] = object.flat_face[u];
      break;
    }
  }
}

void placeObject(DynamicObject& object) {
  const glm::mat4 world = toGlm(object.world_from_object);
  object.world_positions.resize(object.object_positions.size());
  object.bounds = Aabb{};
  for (size_t i = 0; i < object.object_positions.size(); ++i) {
    object.world_positions[i] = fromGlm(transformPoint(world, toGlm(object.object_positions[i])));
    if (object.visible && !object.removed) grow(object.bounds, object.world_positions[i]);
  }
}

MapTriangles dynamicMapTriangles(const std::vector<DynamicObject>& objects) {
  MapTriangles out;
  for (const DynamicObject& object : objects) {
    if (!object.visible || object.removed) continue;
    const uint32_t triangles = uint32_t(object.albedo.size());
    if (triangles > 0) out.part_starts.push_back(uint32_t(out.triangleCount()));
    for (uint32_t t = 0; t < triangles; ++t) {
      for (int k = 0; k < 3; ++k)
        out.positions.push_back(object.world_positions[size_t(t) * 3 + size_t(k)]);
      const uint32_t receiver = object.first_receiver + object.same_as[t];
      out.front_receiver.push_back(receiver);
      out.back_receiver.push_back(object.double_sided ? receiver : kNoReceiver);
    }
  }
  return out;
}

void updateObjectReceivers(const DynamicObject& object, const Aabb& level_box,
                           std::vector<Receiver>& receivers) {
  const size_t triangles = object.albedo.size();
  const Aabb& box = object.bounds;
  const bool inside = !box.empty() && box.min.x <= level_box.max.x &&
                      box.max.x >= level_box.min.x && box.min.y <= level_box.max.y &&
                      box.max.y >= level_box.min.y && box.min.z <= level_box.max.z &&
                      box.max.z >= level_box.min.z;
  for (size_t t = 0; t < triangles; ++t) {
    const glm::vec3 a = toGlm(object.world_positions[t * 3]);
    const glm::vec3 b = toGlm(object.world_positions[t * 3 + 1]);
    const glm::vec3 c = toGlm(object.world_positions[t * 3 + 2]);
    const glm::vec3 cross = glm::cross(b - a, c - a);
    const float length = glm::length(cross);
    Receiver& r = receivers[object.first_receiver + t];
    // A hidden object keeps its slot with zero area: it receives and emits
    // nothing; so does a repeated face (its first copy does).
    const bool repeated = t < object.same_as.size() && object.same_as[t] != t;
    r.area_m2 = (object.visible && !object.removed && !repeated) ? 0.5f * length : 0.0f;
    r.albedo = object.albedo[t];
    r.centroid = fromGlm((a + b + c) / 3.0f);
    r.normal = length > 0 ? fromGlm(cross / length) : Vec3{0, 1, 0};
    r.shares_ambient = inside;
  }
}

}  // namespace svit::gl

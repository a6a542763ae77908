#include "receivers.h"

#include <algorithm>
#include <string>

#include <glm/glm.hpp>

#include "glm_interop.h"

namespace svit::gl {
namespace {

void grow(Aabb& box, const Vec3& p) {
  box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
  box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
}

}  // namespace

Expected<MapTriangles> staticMapTriangles(const BakeData& bake, const BakedSurfaces& surfaces, bool use_proxies) {
  const uint32_t patch_count = uint32_t(bake.patches.size());
  MapTriangles out;
  if (use_proxies) {
    const BakeProxyMesh& proxy = bake.proxy;
    const size_t faces = proxy.indices.size() / 3;
    for (size_t f = 0; f < faces; ++f) {
      const uint32_t patch = proxy.face_patch[f];
      if (patch >= patch_count) {
        return Status(StatusCode::kInvalidInput, "bake proxy face " + std::to_string(f) + ": patch " +
                                                     std::to_string(patch) + " >= patch count " + std::to_string(patch_count));
      }
      for (int k = 0; k < 3; ++k) out.positions.push_back(proxy.positions[proxy.indices[f * 3 + size_t(k)]]);
      // A proxy face stands for the side of the original surface facing it.
      out.front_receiver.push_back(patch);
      out.back_receiver.push_back(kNoReceiver);
    }
    return out;
  }
  const size_t triangles = surfaces.triangleCount();
  out.front_receiver.assign(triangles, kNoReceiver);
  out.back_receiver.assign(triangles, kNoReceiver);
  for (uint32_t p = 0; p < patch_count; ++p) {
    const BakePatch& patch = bake.patches[p];
    for (uint32_t i = 0; i < patch.element_count; ++i) {
      const uint32_t element = bake.patch_elements[patch.first_element + i];
      const uint32_t t = element / 2;
      if (t >= triangles) {
        return Status(StatusCode::kInvalidInput, "bake patch " + std::to_string(p) + ": element " +
                                                     std::to_string(element) + " names triangle " + std::to_string(t) +
                                                     " of " + std::to_string(triangles));
      }
      (element % 2 == 0 ? out.front_receiver : out.back_receiver)[t] = p;
    }
  }
  out.positions.reserve(triangles * 3);
  for (size_t t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) out.positions.push_back(surfaces.corner(t, k));
  }
  return out;
}

std::vector<Receiver> staticReceivers(const BakeData& bake) {
  std::vector<Receiver> receivers;
  receivers.reserve(bake.patches.size());
  for (const BakePatch& patch : bake.patches) {
    receivers.push_back({patch.area_m2, patch.albedo, patch.centroid, patch.normal});
  }
  return receivers;
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
    for (uint32_t t = 0; t < triangles; ++t) {
      for (int k = 0; k < 3; ++k) out.positions.push_back(object.world_positions[size_t(t) * 3 + size_t(k)]);
      out.front_receiver.push_back(object.first_receiver + t);
      out.back_receiver.push_back(object.double_sided ? object.first_receiver + t : kNoReceiver);
    }
  }
  return out;
}

void updateObjectReceivers(const DynamicObject& object, std::vector<Receiver>& receivers) {
  const size_t triangles = object.albedo.size();
  for (size_t t = 0; t < triangles; ++t) {
    const glm::vec3 a = toGlm(object.world_positions[t * 3]);
    const glm::vec3 b = toGlm(object.world_positions[t * 3 + 1]);
    const glm::vec3 c = toGlm(object.world_positions[t * 3 + 2]);
    const glm::vec3 cross = glm::cross(b - a, c - a);
    const float length = glm::length(cross);
    Receiver& r = receivers[object.first_receiver + t];
    // A hidden object keeps its slot with zero area: it receives and emits nothing.
    r.area_m2 = (object.visible && !object.removed) ? 0.5f * length : 0.0f;
    r.albedo = object.albedo[t];
    r.centroid = fromGlm((a + b + c) / 3.0f);
    r.normal = length > 0 ? fromGlm(cross / length) : Vec3{0, 1, 0};
  }
}

}  // namespace svit::gl

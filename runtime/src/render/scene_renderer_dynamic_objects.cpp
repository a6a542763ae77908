#include "scene_renderer_dynamic_objects.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include <glm/glm.hpp>

#include "scene/glm_interop.h"
#include "svit/bake_file.h"

namespace svit::gl {
namespace {

// Appends one object's triangles. `world` holds 3 world positions per
// triangle. Shading normals come from the level's mesh when the object is
// one of its instances with the same triangles (the runtime keeps mesh
// order), else from the faces. `mesh`/`materials` may be null.
void appendObject(const std::vector<Vec3>& world, const Mat4& world_from_object, const Mesh* mesh,
                  const std::vector<Material>* materials, const std::vector<Rgb>& albedo,
                  const std::vector<Rgb>& emission, uint32_t first_patch, uint32_t patch_count,
                  std::vector<DynamicVertex>& out, Aabb& bounds) {
  const size_t triangles = world.size() / 3;
  const bool mesh_normals =
      mesh != nullptr && mesh->triangleCount() == triangles && !mesh->normals.empty();
  const glm::mat3 normal_from_object =
      glm::transpose(glm::inverse(glm::mat3(toGlm(world_from_object))));
  for (size_t t = 0; t < triangles; ++t) {
    const glm::vec3 p[3] = {toGlm(world[t * 3]), toGlm(world[t * 3 + 1]), toGlm(world[t * 3 + 2])};
    const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
    const float length = glm::length(cross);
    if (!(length > 0) || !std::isfinite(length)) continue;  // squashed flat: nothing to see
    const glm::vec3 face = cross / length;
    const glm::vec3 centroid = (p[0] + p[1] + p[2]) / 3.0f;
    const Rgb a = t < albedo.size() ? albedo[t] : Rgb{0.5f, 0.5f, 0.5f};
    const Rgb e = t < emission.size() ? emission[t] : Rgb{};
    // Unknown sidedness (objects the game added) is lit on both sides.
    bool double_sided = true;
    if (mesh != nullptr && materials != nullptr && t < mesh->triangle_material.size()) {
      double_sided = (*materials)[mesh->triangle_material[t]].double_sided;
    }
    for (int k = 0; k < 3; ++k) {
      glm::vec3 n = face;
      if (mesh_normals) {
        const glm::vec3 m =
            normal_from_object * toGlm(mesh->normals[mesh->indices[t * 3 + size_t(k)]]);
        const float m_length = glm::length(m);
        if (m_length > 0 && std::isfinite(m_length))
          n = glm::dot(m, face) < 0 ? -m / m_length : m / m_length;
      }
      DynamicVertex v{};
      v.position[0] = p[k].x, v.position[1] = p[k].y, v.position[2] = p[k].z;
      v.normal[0] = n.x, v.normal[1] = n.y, v.normal[2] = n.z;
      v.albedo[0] = a.r, v.albedo[1] = a.g, v.albedo[2] = a.b;
      v.emission[0] = e.r, v.emission[1] = e.g, v.emission[2] = e.b;
      v.centroid[0] = centroid.x, v.centroid[1] = centroid.y, v.centroid[2] = centroid.z;
      v.face_normal[0] = face.x, v.face_normal[1] = face.y, v.face_normal[2] = face.z;
      v.patch = t < patch_count ? first_patch + uint32_t(t) : kNoDynamicPatch;
      v.double_sided = double_sided ? 1u : 0u;
      out.push_back(v);
      bounds.min = {std::min(bounds.min.x, p[k].x), std::min(bounds.min.y, p[k].y),
                    std::min(bounds.min.z, p[k].z)};
      bounds.max = {std::max(bounds.max.x, p[k].x), std::max(bounds.max.y, p[k].y),
                    std::max(bounds.max.z, p[k].z)};
    }
  }
}

}  // namespace

DynamicObjectMeshes::DynamicObjectMeshes(DynamicObjectMeshes&& other) noexcept {
  *this = std::move(other);
}

DynamicObjectMeshes& DynamicObjectMeshes::operator=(DynamicObjectMeshes&& other) noexcept {
  if (this != &other) {
    release();
    vertices_ = std::move(other.vertices_);
    objects_ = std::move(other.objects_);
    moved_boxes_ = std::move(other.moved_boxes_);
    hash_ = other.hash_;
    uploaded_ = other.uploaded_;
    bounds_ = other.bounds_;
    vao_ = std::move(other.vao_);
    buffer_ = std::move(other.buffer_);
    capacity_ = std::exchange(other.capacity_, 0);
  }
  return *this;
}

DynamicObjectMeshes::~DynamicObjectMeshes() { release(); }

void DynamicObjectMeshes::release() {
  buffer_.reset();
  vao_.reset();
  capacity_ = 0;
}

std::vector<DynamicObjectMeshes::ObjectSpan> DynamicObjectMeshes::gatherVertices(
    const Scene& scene, const Runtime* runtime) {
  vertices_.clear();
  bounds_ = Aabb{};
  std::vector<ObjectSpan> objects;
  // Closes the object whose vertices start at `first`: its hash and box.
  auto endObject = [&](size_t first) {
    ObjectSpan span;
    span.hash =
        fnv1a64(vertices_.data() + first, (vertices_.size() - first) * sizeof(DynamicVertex));
    for (size_t v = first; v < vertices_.size(); ++v) {
      const float* p = vertices_[v].position;
      span.bounds.min = {std::min(span.bounds.min.x, p[0]), std::min(span.bounds.min.y, p[1]),
                         std::min(span.bounds.min.z, p[2])};
      span.bounds.max = {std::max(span.bounds.max.x, p[0]), std::max(span.bounds.max.y, p[1]),
                         std::max(span.bounds.max.z, p[2])};
    }
    objects.push_back(span);
  };
  if (runtime != nullptr) {
    for (ObjectId id : runtime->objects()) {
      Expected<ObjectInfo> info = runtime->objectInfo(id);
      if (!info.ok() || !info->visible) continue;
      const Mesh* mesh = nullptr;
      if (info->instance >= 0 && size_t(info->instance) < scene.instances.size()) {
        const int m = scene.instances[size_t(info->instance)].mesh;
        if (m >= 0 && size_t(m) < scene.meshes.size()) mesh = &scene.meshes[size_t(m)];
      }
      const size_t first = vertices_.size();
      appendObject(info->world_positions, info->world_from_object, mesh, &scene.materials,
                   info->triangle_albedo, info->triangle_emission, info->first_patch,
                   info->patch_count, vertices_, bounds_);
      endObject(first);
    }
  } else {
    std::vector<Vec3> world;
    for (const Instance& instance : scene.instances) {
      if (!instance.dynamic || instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size())
        continue;
      const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
      const glm::mat4 m = toGlm(instance.world_from_object);
      world.clear();
      for (uint32_t index : mesh.indices)
        world.push_back(fromGlm(transformPoint(m, toGlm(mesh.positions[index]))));
      const size_t first = vertices_.size();
      appendObject(world, instance.world_from_object, &mesh, &scene.materials, mesh.triangle_albedo,
                   mesh.triangle_emission, 0, 0, vertices_, bounds_);
      endObject(first);
    }
  }
  return objects;
}

void DynamicObjectMeshes::findMovedBoxes(const std::vector<ObjectSpan>& objects) {
  moved_boxes_.clear();
  const bool same_objects = objects.size() == objects_.size();
  for (size_t o = 0; o < std::max(objects.size(), objects_.size()); ++o) {
    const bool had = o < objects_.size(), has = o < objects.size();
    if (same_objects && objects[o].hash == objects_[o].hash) continue;
    if (had && !objects_[o].bounds.empty()) moved_boxes_.push_back(objects_[o].bounds);
    if (has && !objects[o].bounds.empty()) moved_boxes_.push_back(objects[o].bounds);
  }
}

void DynamicObjectMeshes::upload() {
  if (vertices_.size() > capacity_) {
    buffer_.reset();
    capacity_ = std::max(vertices_.size(), capacity_ * 2);
    buffer_ = createGlBuffer();
    glNamedBufferStorage(buffer_.id(), GLsizeiptr(capacity_ * sizeof(DynamicVertex)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    if (!vao_) {
      vao_ = createGlVertexArray();
      const GLuint vao = vao_.id();
      const GLuint offsets[6] = {
          offsetof(DynamicVertex, position), offsetof(DynamicVertex, normal),
          offsetof(DynamicVertex, albedo),   offsetof(DynamicVertex, emission),
          offsetof(DynamicVertex, centroid), offsetof(DynamicVertex, face_normal)};
      for (GLuint a = 0; a < 6; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, offsets[a]);
        glVertexArrayAttribBinding(vao, a, 0);
      }
      glEnableVertexArrayAttrib(vao, 6);
      glVertexArrayAttribIFormat(vao, 6, 2, GL_UNSIGNED_INT, offsetof(DynamicVertex, patch));
      glVertexArrayAttribBinding(vao, 6, 0);
    }
    glVertexArrayVertexBuffer(vao_.id(), 0, buffer_.id(), 0, sizeof(DynamicVertex));
  }
  glNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(vertices_.size() * sizeof(DynamicVertex)),
                       vertices_.data());
}

bool DynamicObjectMeshes::update(const Scene& scene, const Runtime* runtime) {
  std::vector<ObjectSpan> objects = gatherVertices(scene, runtime);
  const uint64_t hash = fnv1a64(vertices_.data(), vertices_.size() * sizeof(DynamicVertex));
  const bool changed = !uploaded_ || hash != hash_;
  findMovedBoxes(objects);
  objects_ = std::move(objects);
  hash_ = hash;
  uploaded_ = true;
  if (changed && !vertices_.empty()) upload();
  return changed;
}

void DynamicObjectMeshes::draw() const {
  if (vertices_.empty() || !vao_) return;
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices_.size()));
}

}  // namespace svit::gl

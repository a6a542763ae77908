// glTF mesh primitives -> one svit::Mesh: triangle lists, strips and fans
// converted (glTF 2.0 section 3.7.2.1), points and lines skipped, every index
// and value validated, zero-area triangles dropped, missing normals
// generated flat (as the glTF spec requires), per-triangle mean albedo and
// emission for the radiosity solver.

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

#include "accessor_reader.h"
#include "glm_interop.h"
#include "gltf_import_context.h"
#include "texture_sampling.h"

namespace svit::gltf {
namespace {

// A triangle whose height over its longest edge is below float32's relative
// resolution (2^-24 ~ 6e-8, rounded up to 1e-7) has an orientation made of
// rounding noise: treat it as zero-area. Slivers of aspect 1e5 (height/edge
// 1e-5) stay.
constexpr double kZeroAreaRelative = 1e-7;
// Warnings listed one by one per mesh before they are only counted.
constexpr size_t kListedWarningsPerMesh = 3;

std::string formatVec(const float* v, int n) {
  std::string s = "(";
  for (int i = 0; i < n; ++i) {
    s += std::to_string(v[i]);
    if (i + 1 < n) s += ", ";
  }
  return s + ")";
}

Status readAttribute(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                     const std::string& name, int components, const std::string& what,
                     size_t vertex_count, std::vector<float>& out, bool& present) {
  auto it = primitive.attributes.find(name);
  present = it != primitive.attributes.end();
  if (!present) return Status();
  const std::string where = what + " attribute " + name;
  if (Status s = readFloats(model, it->second, components, where, out); !s.ok()) return s;
  if (vertex_count != size_t(-1) && out.size() / size_t(components) != vertex_count) {
    return Status(StatusCode::kInvalidInput,
                  where + ": " + std::to_string(out.size() / size_t(components)) +
                      " elements, but POSITION has " + std::to_string(vertex_count));
  }
  for (size_t v = 0; v < out.size() / size_t(components); ++v) {
    for (int c = 0; c < components; ++c) {
      if (!std::isfinite(out[v * size_t(components) + size_t(c)])) {
        return Status(StatusCode::kInvalidInput,
                      where + " vertex " + std::to_string(v) + ": " +
                          formatVec(&out[v * size_t(components)], components) +
                          " is not finite");
      }
    }
  }
  return Status();
}

// Triangle index triples of one primitive, per its mode.
std::vector<uint32_t> triangulate(const std::vector<uint32_t>& indices, int mode) {
  std::vector<uint32_t> triangles;
  const size_t n = indices.size();
  if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < n; ++i) {
      // glTF: p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}} keeps the winding.
      triangles.insert(triangles.end(),
                       {indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]});
    }
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 1; i + 1 < n; ++i) {
      triangles.insert(triangles.end(), {indices[i], indices[i + 1], indices[0]});
    }
  } else {
    triangles.assign(indices.begin(), indices.begin() + long(n - n % 3));
  }
  return triangles;
}

glm::dvec3 dvec(const std::vector<float>& p, uint32_t i) {
  return {p[size_t(i) * 3], p[size_t(i) * 3 + 1], p[size_t(i) * 3 + 2]};
}

Rgb textureMean(const Scene& scene, const TextureRef& ref, const Mesh& mesh, size_t triangle,
                bool& missing_uvs) {
  if (ref.texture < 0) return {1, 1, 1};
  const std::vector<Vec2>& uvs = ref.texcoord == 1 ? mesh.uv1 : mesh.uv0;
  if (uvs.empty()) {
    missing_uvs = true;
    return {1, 1, 1};
  }
  const uint32_t* t = &mesh.indices[triangle * 3];
  return meanOverTriangle(scene.textures[size_t(ref.texture)], transformUv(ref, uvs[t[0]]),
                          transformUv(ref, uvs[t[1]]), transformUv(ref, uvs[t[2]]), true);
}

}  // namespace

Status importMesh(ImportContext& context, int mesh_index, Mesh& mesh) {
  const tinygltf::Model& model = context.model;
  const tinygltf::Mesh& source = model.meshes[size_t(mesh_index)];
  Scene& scene = context.scene;
  const std::string label = context.path + ": " + meshLabel(model, mesh_index);
  mesh.name = source.name.empty() ? "mesh " + std::to_string(mesh_index) : source.name;

  bool any_uv0 = false, any_uv1 = false;
  for (const tinygltf::Primitive& p : source.primitives) {
    any_uv0 = any_uv0 || p.attributes.count("TEXCOORD_0");
    any_uv1 = any_uv1 || p.attributes.count("TEXCOORD_1");
  }
  size_t zero_area = 0;
  bool generated_normals = false;
  for (size_t p = 0; p < source.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = source.primitives[p];
    const std::string what = label + " primitive " + std::to_string(p);
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE ||
        mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP) {
      scene.warnings.push_back(what + ": " + (mode == TINYGLTF_MODE_POINTS ? "points" : "lines") +
                               " skipped (svit lights triangles only)");
      ++scene.counters.skipped_point_line_primitives;
      continue;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      return Status(StatusCode::kInvalidInput, what + ": mode " + std::to_string(mode) +
                                                   " is not a glTF primitive mode");
    }
    if (!primitive.attributes.count("POSITION")) {
      return Status(StatusCode::kInvalidInput, what + ": has no POSITION attribute");
    }
    std::vector<float> positions, normals, uv0, uv1;
    bool has_positions = false, has_normals = false, has_uv0 = false, has_uv1 = false;
    if (Status s = readAttribute(model, primitive, "POSITION", 3, what, size_t(-1), positions,
                                 has_positions);
        !s.ok()) {
      return s;
    }
    const size_t vertex_count = positions.size() / 3;
    if (Status s = readAttribute(model, primitive, "NORMAL", 3, what, vertex_count, normals, has_normals);
        !s.ok()) {
      return s;
    }
    if (Status s = readAttribute(model, primitive, "TEXCOORD_0", 2, what, vertex_count, uv0, has_uv0);
        !s.ok()) {
      return s;
    }
    if (Status s = readAttribute(model, primitive, "TEXCOORD_1", 2, what, vertex_count, uv1, has_uv1);
        !s.ok()) {
      return s;
    }
    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
      if (Status s = readIndices(model, primitive.indices, what + " indices", indices); !s.ok()) {
        return s;
      }
    } else {
      indices.resize(vertex_count);
      for (size_t i = 0; i < vertex_count; ++i) indices[i] = uint32_t(i);
    }
    const std::vector<uint32_t> triangles = triangulate(indices, mode);
    uint32_t material = 0;
    if (primitive.material >= 0) {
      if (size_t(primitive.material) >= model.materials.size()) {
        return Status(StatusCode::kInvalidInput,
                      what + ": material " + std::to_string(primitive.material) +
                          " does not exist (file has " + std::to_string(model.materials.size()) + ")");
      }
      material = uint32_t(primitive.material);
    } else {
      if (context.default_material < 0) {
        context.default_material = int(scene.materials.size());
        Material fallback;
        fallback.name = "glTF default material";
        scene.materials.push_back(fallback);
      }
      material = uint32_t(context.default_material);
    }

    // Normals: the file's (renormalized; zero-length ones repaired from the
    // faces around the vertex), or flat per triangle when absent.
    std::vector<glm::dvec3> repaired;
    std::vector<bool> needs_repair;
    if (has_normals) {
      needs_repair.assign(vertex_count, false);
      for (size_t v = 0; v < vertex_count; ++v) {
        const glm::dvec3 n = dvec(normals, uint32_t(v));
        // Below 1e-6 a stored normal is noise, not a direction.
        if (glm::length(n) < 1e-6) needs_repair[v] = true;
      }
      repaired.assign(vertex_count, glm::dvec3(0.0));
    }
    const uint32_t base = uint32_t(mesh.positions.size());
    if (has_normals) {
      for (size_t v = 0; v < vertex_count; ++v) {
        mesh.positions.push_back({positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]});
        mesh.normals.push_back({normals[v * 3], normals[v * 3 + 1], normals[v * 3 + 2]});
        if (any_uv0) mesh.uv0.push_back(has_uv0 ? Vec2{uv0[v * 2], uv0[v * 2 + 1]} : Vec2{0, 0});
        if (any_uv1) mesh.uv1.push_back(has_uv1 ? Vec2{uv1[v * 2], uv1[v * 2 + 1]} : Vec2{0, 0});
      }
    } else {
      generated_normals = true;
    }
    for (size_t t = 0; t * 3 < triangles.size(); ++t) {
      const uint32_t* tri = &triangles[t * 3];
      for (int k = 0; k < 3; ++k) {
        if (tri[k] >= vertex_count) {
          return Status(StatusCode::kInvalidInput,
                        what + " triangle " + std::to_string(t) + ": index " +
                            std::to_string(tri[k]) + " >= vertex count " +
                            std::to_string(vertex_count));
        }
      }
      const glm::dvec3 a = dvec(positions, tri[0]), b = dvec(positions, tri[1]),
                       c = dvec(positions, tri[2]);
      const glm::dvec3 cross = glm::cross(b - a, c - a);
      const double longest2 =
          std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
      if (!(glm::length(cross) > kZeroAreaRelative * longest2)) {
        if (zero_area < kListedWarningsPerMesh) {
          scene.warnings.push_back(what + " triangle " + std::to_string(t) +
                                   ": zero area, skipped");
        }
        ++zero_area;
        continue;
      }
      const glm::dvec3 face_normal = glm::normalize(cross);
      if (has_normals) {
        for (int k = 0; k < 3; ++k) {
          mesh.indices.push_back(base + tri[k]);
          if (needs_repair[tri[k]]) repaired[tri[k]] += cross;  // area-weighted
        }
      } else {
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = tri[k];
          mesh.indices.push_back(uint32_t(mesh.positions.size()));
          mesh.positions.push_back({positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]});
          mesh.normals.push_back(fromGlm(glm::vec3(face_normal)));
          if (any_uv0) mesh.uv0.push_back(has_uv0 ? Vec2{uv0[v * 2], uv0[v * 2 + 1]} : Vec2{0, 0});
          if (any_uv1) mesh.uv1.push_back(has_uv1 ? Vec2{uv1[v * 2], uv1[v * 2 + 1]} : Vec2{0, 0});
        }
      }
      mesh.triangle_material.push_back(material);
      mesh.triangle_source.push_back({uint32_t(p), uint32_t(t)});
    }
    if (has_normals) {
      for (size_t v = 0; v < vertex_count; ++v) {
        Vec3& n = mesh.normals[base + v];
        if (needs_repair[v]) {
          if (glm::length(repaired[v]) > 0.0) {
            n = fromGlm(glm::vec3(glm::normalize(repaired[v])));
            ++scene.counters.repaired_normals;
          } else {
            n = {0, 1, 0};  // used by no kept triangle
          }
        } else {
          // In double: a float |n|^2 overflows for |n| > ~1.8e19 and would
          // normalise to zero (found by fuzz_glb).
          n = fromGlm(glm::vec3(glm::normalize(dvec(normals, uint32_t(v)))));
        }
      }
    }
  }
  if (zero_area > 0) {
    scene.counters.zero_area_triangles += zero_area;
    if (zero_area > kListedWarningsPerMesh) {
      scene.warnings.push_back(label + ": " + std::to_string(zero_area) +
                               " zero-area triangles skipped in all");
    }
  }
  if (generated_normals) ++scene.counters.meshes_with_generated_normals;

  // Per-triangle means for the solver.
  const size_t triangle_count = mesh.triangleCount();
  mesh.triangle_albedo.resize(triangle_count);
  mesh.triangle_emission.resize(triangle_count);
  bool missing_uvs = false;
  for (size_t t = 0; t < triangle_count; ++t) {
    const Material& material = scene.materials[mesh.triangle_material[t]];
    const Rgb albedo_texture = textureMean(scene, material.base_color_texture, mesh, t, missing_uvs);
    mesh.triangle_albedo[t] = {material.base_color.r * albedo_texture.r,
                               material.base_color.g * albedo_texture.g,
                               material.base_color.b * albedo_texture.b};
    const Rgb& e = material.emissive_luminance;
    if (e.r > 0 || e.g > 0 || e.b > 0) {
      const Rgb emission_texture = textureMean(scene, material.emissive_texture, mesh, t, missing_uvs);
      mesh.triangle_emission[t] = {e.r * emission_texture.r, e.g * emission_texture.g,
                                   e.b * emission_texture.b};
    }
  }
  if (missing_uvs) {
    scene.warnings.push_back(label + ": a material's texture needs texture coordinates the mesh "
                                     "lacks; its factor is used alone");
  }
  return Status();
}

}  // namespace svit::gltf

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
                          formatVec(&out[v * size_t(components)], components) + " is not finite");
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

// What the primitives of one mesh share while they are appended to it.
struct MeshImport {
  ImportContext& context;
  const std::string label;  // "<path>: mesh 'Crate'", prefix of the mesh's messages
  Mesh& mesh;
  bool any_uv0 = false, any_uv1 = false;  // some primitive has TEXCOORD_0 / _1
  size_t zero_area = 0;
  bool generated_normals = false;
};

// The attributes and triangles of one primitive as the file gives them.
struct PrimitiveData {
  std::vector<float> positions, normals, uv0, uv1;
  bool has_positions = false, has_normals = false, has_uv0 = false, has_uv1 = false;
  size_t vertex_count = 0;
  std::vector<uint32_t> triangles;  // index triples into this primitive's vertices
  uint32_t material = 0;
};

void findTexcoords(const tinygltf::Mesh& source, MeshImport& importing) {
  for (const tinygltf::Primitive& p : source.primitives) {
    importing.any_uv0 = importing.any_uv0 || p.attributes.count("TEXCOORD_0");
    importing.any_uv1 = importing.any_uv1 || p.attributes.count("TEXCOORD_1");
  }
}

bool isPointOrLineMode(int mode) {
  return mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE ||
         mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP;
}

Status checkTriangleMode(int mode, const tinygltf::Primitive& primitive, const std::string& what) {
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    return Status(StatusCode::kInvalidInput,
                  what + ": mode " + std::to_string(mode) + " is not a glTF primitive mode");
  }
  if (!primitive.attributes.count("POSITION")) {
    return Status(StatusCode::kInvalidInput, what + ": has no POSITION attribute");
  }
  return Status();
}

Status readVertexAttributes(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                            const std::string& what, PrimitiveData& data) {
  if (Status s = readAttribute(model, primitive, "POSITION", 3, what, size_t(-1), data.positions,
                               data.has_positions);
      !s.ok()) {
    return s;
  }
  data.vertex_count = data.positions.size() / 3;
  if (Status s = readAttribute(model, primitive, "NORMAL", 3, what, data.vertex_count, data.normals,
                               data.has_normals);
      !s.ok()) {
    return s;
  }
  if (Status s = readAttribute(model, primitive, "TEXCOORD_0", 2, what, data.vertex_count, data.uv0,
                               data.has_uv0);
      !s.ok()) {
    return s;
  }
  return readAttribute(model, primitive, "TEXCOORD_1", 2, what, data.vertex_count, data.uv1,
                       data.has_uv1);
}

// The index list (or 0..n-1 for a non-indexed primitive), as triangles.
Status readTriangles(const tinygltf::Model& model, const tinygltf::Primitive& primitive, int mode,
                     const std::string& what, PrimitiveData& data) {
  std::vector<uint32_t> indices;
  if (primitive.indices >= 0) {
    if (Status s = readIndices(model, primitive.indices, what + " indices", indices); !s.ok()) {
      return s;
    }
  } else {
    indices.resize(data.vertex_count);
    for (size_t i = 0; i < data.vertex_count; ++i) indices[i] = uint32_t(i);
  }
  data.triangles = triangulate(indices, mode);
  return Status();
}

// The primitive's material, or glTF's default material (created on first use).
Status resolveMaterial(ImportContext& context, const tinygltf::Primitive& primitive,
                       const std::string& what, PrimitiveData& data) {
  const tinygltf::Model& model = context.model;
  if (primitive.material >= 0) {
    if (size_t(primitive.material) >= model.materials.size()) {
      return Status(StatusCode::kInvalidInput, what + ": material " +
                                                   std::to_string(primitive.material) +
                                                   " does not exist (file has " +
                                                   std::to_string(model.materials.size()) + ")");
    }
    data.material = uint32_t(primitive.material);
    return Status();
  }
  if (context.default_material < 0) {
    context.default_material = int(context.scene.materials.size());
    Material fallback;
    fallback.name = "glTF default material";
    context.scene.materials.push_back(fallback);
  }
  data.material = uint32_t(context.default_material);
  return Status();
}

// Normals: the file's (renormalized; zero-length ones repaired from the
// faces around the vertex), or flat per triangle when absent.
struct NormalRepair {
  std::vector<glm::dvec3> repaired;  // area-weighted sum of the faces around each vertex
  std::vector<bool> needs_repair;
};

NormalRepair findNormalsToRepair(const PrimitiveData& data) {
  NormalRepair repair;
  if (!data.has_normals) return repair;
  repair.needs_repair.assign(data.vertex_count, false);
  for (size_t v = 0; v < data.vertex_count; ++v) {
    const glm::dvec3 n = dvec(data.normals, uint32_t(v));
    // Below 1e-6 a stored normal is noise, not a direction.
    if (glm::length(n) < 1e-6) repair.needs_repair[v] = true;
  }
  repair.repaired.assign(data.vertex_count, glm::dvec3(0.0));
  return repair;
}

void appendVertex(MeshImport& importing, const PrimitiveData& data, size_t v, const Vec3& normal) {
  Mesh& mesh = importing.mesh;
  mesh.positions.push_back(
      {data.positions[v * 3], data.positions[v * 3 + 1], data.positions[v * 3 + 2]});
  mesh.normals.push_back(normal);
  if (importing.any_uv0) {
    mesh.uv0.push_back(data.has_uv0 ? Vec2{data.uv0[v * 2], data.uv0[v * 2 + 1]} : Vec2{0, 0});
  }
  if (importing.any_uv1) {
    mesh.uv1.push_back(data.has_uv1 ? Vec2{data.uv1[v * 2], data.uv1[v * 2 + 1]} : Vec2{0, 0});
  }
}

// With file normals every vertex is shared by the triangles that use it.
void appendSharedVertices(MeshImport& importing, const PrimitiveData& data) {
  if (!data.has_normals) {
    importing.generated_normals = true;
    return;
  }
  for (size_t v = 0; v < data.vertex_count; ++v) {
    appendVertex(importing, data, v,
                 {data.normals[v * 3], data.normals[v * 3 + 1], data.normals[v * 3 + 2]});
  }
}

Status checkTriangleIndices(const uint32_t* tri, size_t t, const PrimitiveData& data,
                            const std::string& what) {
  for (int k = 0; k < 3; ++k) {
    if (tri[k] >= data.vertex_count) {
      return Status(StatusCode::kInvalidInput,
                    what + " triangle " + std::to_string(t) + ": index " + std::to_string(tri[k]) +
                        " >= vertex count " + std::to_string(data.vertex_count));
    }
  }
  return Status();
}

// Appends the triangles of positive area; flat-shaded ones get vertices of their own.
Status appendTriangles(MeshImport& importing, size_t p, uint32_t base, const PrimitiveData& data,
                       NormalRepair& repair, const std::string& what) {
  Mesh& mesh = importing.mesh;
  for (size_t t = 0; t * 3 < data.triangles.size(); ++t) {
    const uint32_t* tri = &data.triangles[t * 3];
    if (Status s = checkTriangleIndices(tri, t, data, what); !s.ok()) return s;
    const glm::dvec3 a = dvec(data.positions, tri[0]), b = dvec(data.positions, tri[1]),
                     c = dvec(data.positions, tri[2]);
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double longest2 =
        std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    if (!(glm::length(cross) > kZeroAreaRelative * longest2)) {
      if (importing.zero_area < kListedWarningsPerMesh) {
        importing.context.scene.warnings.push_back(what + " triangle " + std::to_string(t) +
                                                   ": zero area, skipped");
      }
      ++importing.zero_area;
      continue;
    }
    const glm::dvec3 face_normal = glm::normalize(cross);
    if (data.has_normals) {
      for (int k = 0; k < 3; ++k) {
        mesh.indices.push_back(base + tri[k]);
        if (repair.needs_repair[tri[k]]) repair.repaired[tri[k]] += cross;  // area-weighted
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        mesh.indices.push_back(uint32_t(mesh.positions.size()));
        appendVertex(importing, data, tri[k], fromGlm(glm::vec3(face_normal)));
      }
    }
    mesh.triangle_material.push_back(data.material);
    mesh.triangle_source.push_back({uint32_t(p), uint32_t(t)});
  }
  return Status();
}

void finishSharedNormals(MeshImport& importing, uint32_t base, const PrimitiveData& data,
                         const NormalRepair& repair) {
  if (!data.has_normals) return;
  for (size_t v = 0; v < data.vertex_count; ++v) {
    Vec3& n = importing.mesh.normals[base + v];
    if (repair.needs_repair[v]) {
      if (glm::length(repair.repaired[v]) > 0.0) {
        n = fromGlm(glm::vec3(glm::normalize(repair.repaired[v])));
        ++importing.context.scene.counters.repaired_normals;
      } else {
        n = {0, 1, 0};  // used by no kept triangle
      }
    } else {
      // In double: a float |n|^2 overflows for |n| > ~1.8e19 and would
      // normalise to zero (found by fuzz_glb).
      n = fromGlm(glm::vec3(glm::normalize(dvec(data.normals, uint32_t(v)))));
    }
  }
}

Status importPrimitive(MeshImport& importing, const tinygltf::Primitive& primitive, size_t p) {
  ImportContext& context = importing.context;
  Scene& scene = context.scene;
  const std::string what = importing.label + " primitive " + std::to_string(p);
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (isPointOrLineMode(mode)) {
    scene.warnings.push_back(what + ": " + (mode == TINYGLTF_MODE_POINTS ? "points" : "lines") +
                             " skipped (svit lights triangles only)");
    ++scene.counters.skipped_point_line_primitives;
    return Status();
  }
  if (Status s = checkTriangleMode(mode, primitive, what); !s.ok()) return s;
  PrimitiveData data;
  if (Status s = readVertexAttributes(context.model, primitive, what, data); !s.ok()) return s;
  if (Status s = readTriangles(context.model, primitive, mode, what, data); !s.ok()) return s;
  if (Status s = resolveMaterial(context, primitive, what, data); !s.ok()) return s;
  NormalRepair repair = findNormalsToRepair(data);
  const uint32_t base = uint32_t(importing.mesh.positions.size());
  appendSharedVertices(importing, data);
  if (Status s = appendTriangles(importing, p, base, data, repair, what); !s.ok()) return s;
  finishSharedNormals(importing, base, data, repair);
  return Status();
}

void countMeshWarnings(const MeshImport& importing) {
  Scene& scene = importing.context.scene;
  if (importing.zero_area > 0) {
    scene.counters.zero_area_triangles += importing.zero_area;
    if (importing.zero_area > kListedWarningsPerMesh) {
      scene.warnings.push_back(importing.label + ": " + std::to_string(importing.zero_area) +
                               " zero-area triangles skipped in all");
    }
  }
  if (importing.generated_normals) ++scene.counters.meshes_with_generated_normals;
}

// Per-triangle means for the solver.
void computeTriangleMeans(Scene& scene, Mesh& mesh, const std::string& label) {
  const size_t triangle_count = mesh.triangleCount();
  mesh.triangle_albedo.resize(triangle_count);
  mesh.triangle_emission.resize(triangle_count);
  bool missing_uvs = false;
  for (size_t t = 0; t < triangle_count; ++t) {
    const Material& material = scene.materials[mesh.triangle_material[t]];
    const Rgb albedo_texture =
        textureMean(scene, material.base_color_texture, mesh, t, missing_uvs);
    mesh.triangle_albedo[t] = {material.base_color.r * albedo_texture.r,
                               material.base_color.g * albedo_texture.g,
                               material.base_color.b * albedo_texture.b};
    const Rgb& e = material.emissive_luminance;
    if (e.r > 0 || e.g > 0 || e.b > 0) {
      const Rgb emission_texture =
          textureMean(scene, material.emissive_texture, mesh, t, missing_uvs);
      mesh.triangle_emission[t] = {e.r * emission_texture.r, e.g * emission_texture.g,
                                   e.b * emission_texture.b};
    }
  }
  if (missing_uvs) {
    scene.warnings.push_back(label +
                             ": a material's texture needs texture coordinates the mesh "
                             "lacks; its factor is used alone");
  }
}

}  // namespace

Status importMesh(ImportContext& context, int mesh_index, Mesh& mesh) {
  const tinygltf::Mesh& source = context.model.meshes[size_t(mesh_index)];
  MeshImport importing{context, context.path + ": " + meshLabel(context.model, mesh_index), mesh};
  mesh.name = source.name.empty() ? "mesh " + std::to_string(mesh_index) : source.name;
  findTexcoords(source, importing);
  for (size_t p = 0; p < source.primitives.size(); ++p) {
    if (Status s = importPrimitive(importing, source.primitives[p], p); !s.ok()) return s;
  }
  countMeshWarnings(importing);
  computeTriangleMeans(context.scene, mesh, importing.label);
  return Status();
}

}  // namespace svit::gltf

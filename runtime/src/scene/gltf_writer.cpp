// Writes a Scene back as glTF 2.0 with tinygltf's writer: used by tools that
// generate levels and by the round-trip test of the importer.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

#include <tiny_gltf.h>

#include "numeric.h"
#include "svit/level.h"

namespace svit {
namespace {

// Appends raw bytes to the buffer (4-byte aligned) and returns a buffer view.
int addView(tinygltf::Model& model, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  while (buffer.size() % 4 != 0) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return int(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, int view, int component_type, int type, size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(accessor);
  return int(model.accessors.size() - 1);
}

int wrapToGl(WrapMode mode) {
  switch (mode) {
    case WrapMode::kClampToEdge: return TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    case WrapMode::kMirroredRepeat: return TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
    default: return TINYGLTF_TEXTURE_WRAP_REPEAT;
  }
}

tinygltf::TextureInfo textureInfo(const TextureRef& ref) {
  tinygltf::TextureInfo info;
  info.index = ref.texture;
  info.texCoord = ref.texcoord;
  if (ref.offset.x != 0 || ref.offset.y != 0 || ref.rotation_rad != 0 || ref.scale.x != 1 ||
      ref.scale.y != 1) {
    tinygltf::Value::Object t;
    t["offset"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(ref.offset.x)),
                                                         tinygltf::Value(double(ref.offset.y))});
    t["scale"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(double(ref.scale.x)),
                                                        tinygltf::Value(double(ref.scale.y))});
    t["rotation"] = tinygltf::Value(double(ref.rotation_rad));
    info.extensions["KHR_texture_transform"] = tinygltf::Value(t);
  }
  return info;
}

void addExtensionUsed(tinygltf::Model& model, const std::string& name) {
  if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), name) ==
      model.extensionsUsed.end()) {
    model.extensionsUsed.push_back(name);
  }
}

void writeTextures(const Scene& scene, tinygltf::Model& model) {
  for (const Texture& texture : scene.textures) {
    tinygltf::Image image;
    image.name = texture.name;
    image.width = texture.width;
    image.height = texture.height;
    image.component = texture.channels;
    image.bits = 8;
    image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image.mimeType = "image/png";
    image.image = texture.texels;
    model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.wrapS = wrapToGl(texture.wrap_s);
    sampler.wrapT = wrapToGl(texture.wrap_t);
    model.samplers.push_back(sampler);
    tinygltf::Texture t;
    t.source = int(model.images.size() - 1);
    t.sampler = int(model.samplers.size() - 1);
    model.textures.push_back(t);
  }
}

void writeMaterials(const Scene& scene, tinygltf::Model& model) {
  for (const Material& material : scene.materials) {
    tinygltf::Material m;
    m.name = material.name;
    m.pbrMetallicRoughness.baseColorFactor = {material.base_color.r, material.base_color.g,
                                              material.base_color.b, material.base_alpha};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (material.base_color_texture.texture >= 0) {
      m.pbrMetallicRoughness.baseColorTexture = textureInfo(material.base_color_texture);
    }
    if (material.emissive_texture.texture >= 0)
      m.emissiveTexture = textureInfo(material.emissive_texture);
    const Rgb& e = material.emissive_luminance;
    const double strength = std::max({double(e.r), double(e.g), double(e.b)});
    if (strength > 0) {
      // emissiveFactor must stay in [0, 1]; the rest goes into the strength.
      m.emissiveFactor = {e.r / strength, e.g / strength, e.b / strength};
      if (strength != 1.0) {
        tinygltf::Value::Object ext;
        ext["emissiveStrength"] = tinygltf::Value(strength);
        m.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(ext);
        addExtensionUsed(model, "KHR_materials_emissive_strength");
      }
    } else {
      m.emissiveFactor = {0.0, 0.0, 0.0};
    }
    m.doubleSided = material.double_sided;
    m.alphaMode = material.alpha_mode == AlphaMode::kMask    ? "MASK"
                  : material.alpha_mode == AlphaMode::kBlend ? "BLEND"
                                                             : "OPAQUE";
    m.alphaCutoff = material.alpha_cutoff;
    model.materials.push_back(m);
  }
}

void writeMesh(const Mesh& mesh, tinygltf::Model& model) {
  tinygltf::Mesh out;
  out.name = mesh.name;
  if (mesh.triangleCount() == 0) {
    model.meshes.push_back(out);
    return;
  }
  const size_t vertices = mesh.positions.size();
  const int positions = addAccessor(
      model, addView(model, mesh.positions.data(), vertices * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices);
  std::vector<double> lo(3, kNoUpperBound), hi(3, kNoLowerBound);
  for (const Vec3& p : mesh.positions) {
    const float c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      lo[size_t(k)] = std::min(lo[size_t(k)], double(c[k]));
      hi[size_t(k)] = std::max(hi[size_t(k)], double(c[k]));
    }
  }
  model.accessors[size_t(positions)].minValues = lo;
  model.accessors[size_t(positions)].maxValues = hi;
  const int normals = addAccessor(
      model, addView(model, mesh.normals.data(), vertices * 12, TINYGLTF_TARGET_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices);
  int uv0 = -1, uv1 = -1;
  if (!mesh.uv0.empty()) {
    uv0 = addAccessor(model,
                      addView(model, mesh.uv0.data(), vertices * 8, TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, vertices);
  }
  if (!mesh.uv1.empty()) {
    uv1 = addAccessor(model,
                      addView(model, mesh.uv1.data(), vertices * 8, TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, vertices);
  }
  // One primitive per material, in order of first use so re-import keeps
  // the triangle order within each material.
  std::map<uint32_t, std::vector<uint32_t>> by_material;
  std::vector<uint32_t> order;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t m = mesh.triangle_material[t];
    if (!by_material.count(m)) order.push_back(m);
    auto& list = by_material[m];
    list.insert(list.end(), &mesh.indices[t * 3], &mesh.indices[t * 3] + 3);
  }
  for (uint32_t m : order) {
    const std::vector<uint32_t>& indices = by_material[m];
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = int(m);
    primitive.attributes["POSITION"] = positions;
    primitive.attributes["NORMAL"] = normals;
    if (uv0 >= 0) primitive.attributes["TEXCOORD_0"] = uv0;
    if (uv1 >= 0) primitive.attributes["TEXCOORD_1"] = uv1;
    primitive.indices = addAccessor(
        model,
        addView(model, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
    out.primitives.push_back(primitive);
  }
  model.meshes.push_back(out);
}

void writeNodes(const Scene& scene, tinygltf::Model& model) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    const Node& node = scene.nodes[i];
    tinygltf::Node out;
    out.name = node.name;
    out.mesh = node.mesh;
    out.children = node.children;
    if (node.has_trs) {
      out.translation = {node.translation.x, node.translation.y, node.translation.z};
      out.rotation = {node.rotation.x, node.rotation.y, node.rotation.z, node.rotation.w};
      out.scale = {node.scale.x, node.scale.y, node.scale.z};
    } else {
      out.matrix.assign(node.parent_from_node.m.begin(), node.parent_from_node.m.end());
    }
    const bool parent_dynamic = node.parent >= 0 && scene.nodes[size_t(node.parent)].dynamic;
    if (node.dynamic && !parent_dynamic) {
      tinygltf::Value::Object svit_extras;
      svit_extras["dynamic"] = tinygltf::Value(true);
      tinygltf::Value::Object extras;
      extras["svit"] = tinygltf::Value(svit_extras);
      out.extras = tinygltf::Value(extras);
    }
    model.nodes.push_back(out);
  }
  for (const Light& light : scene.lights) {
    if (light.node < 0) continue;  // level.json lights stay in level.json
    tinygltf::Light out;
    out.name = light.name;
    out.type = light.type == LightType::kPoint  ? "point"
               : light.type == LightType::kSpot ? "spot"
                                                : "directional";
    out.color = {light.color.r, light.color.g, light.color.b};
    out.intensity = light.intensity;
    out.range = light.range_m;
    out.spot.innerConeAngle = light.inner_cone_rad;
    out.spot.outerConeAngle = light.outer_cone_rad;
    model.lights.push_back(out);
    tinygltf::Value::Object ext;
    ext["light"] = tinygltf::Value(int(model.lights.size() - 1));
    model.nodes[size_t(light.node)].extensions["KHR_lights_punctual"] = tinygltf::Value(ext);
  }
  for (const SceneCamera& camera : scene.cameras) {
    tinygltf::Camera out;
    out.name = camera.name;
    out.type = "perspective";
    out.perspective.yfov = camera.yfov_rad;
    out.perspective.znear = camera.near_m;
    out.perspective.zfar = camera.far_m;
    model.cameras.push_back(out);
    model.nodes[size_t(camera.node)].camera = int(model.cameras.size() - 1);
  }
  tinygltf::Scene gltf_scene;
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].parent < 0) gltf_scene.nodes.push_back(int(i));
  }
  model.scenes.push_back(gltf_scene);
  model.defaultScene = 0;
}

}  // namespace

Status writeGltf(const Scene& scene, const std::string& path) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "svit";
  model.buffers.resize(1);
  writeTextures(scene, model);
  writeMaterials(scene, model);
  for (const Mesh& mesh : scene.meshes) writeMesh(mesh, model);
  writeNodes(scene, model);

  const std::string temporary = path + ".tmp";
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, temporary, /*embedImages=*/true, /*embedBuffers=*/true,
                                   /*prettyPrint=*/true, /*writeBinary=*/false)) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    return Status(StatusCode::kIoError, path + ": cannot write glTF");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    return Status(StatusCode::kIoError,
                  path + ": cannot replace with " + temporary + ": " + ec.message());
  }
  return Status();
}

}  // namespace svit

// glTF materials and the textures they use: base colour (diffuse albedo) and
// emission (luminance in cd/m2, KHR_materials_emissive_strength).

#include <cmath>
#include <sstream>

#include <stb_image.h>
#include <tiny_gltf.h>

#include "gltf_import_context.h"

namespace svit::gltf {
namespace {

WrapMode wrapMode(int gl_wrap) {
  switch (gl_wrap) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::kMirroredRepeat;
    default: return WrapMode::kRepeat;
  }
}

// stb_image's reason as printable ASCII: for an unknown PNG chunk it is the
// chunk's four raw type bytes, and a warning must be text a reader (and
// svit-info --json) can take (found by fuzz_gltf).
std::string printableReason(const char* reason) {
  std::string out = reason ? reason : "no reason given";
  for (char& c : out) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return out;
}

std::string imageLabel(const tinygltf::Image& image, int index) {
  if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) return "'" + image.uri + "'";
  if (!image.name.empty()) return "'" + image.name + "'";
  return std::to_string(index);
}

// Decodes glTF texture `texture_index` once; returns its Scene::textures index
// or -1 (missing file, undecodable data) with a warning.
int decodeTexture(ImportContext& context, int texture_index, const std::string& user) {
  const tinygltf::Model& model = context.model;
  if (texture_index < 0 || size_t(texture_index) >= model.textures.size()) return -2;
  if (context.texture_map[size_t(texture_index)] != -3)
    return context.texture_map[size_t(texture_index)];
  int& slot = context.texture_map[size_t(texture_index)];
  slot = -1;
  if (!context.options.load_textures) return slot;
  const tinygltf::Texture& gltf_texture = model.textures[size_t(texture_index)];
  const int source = gltf_texture.source;
  if (source < 0 || size_t(source) >= model.images.size()) {
    context.scene.warnings.push_back(user + ": texture " + std::to_string(texture_index) +
                                     " has no image; the factor is used alone");
    ++context.scene.counters.missing_textures;
    return slot;
  }
  const tinygltf::Image& image = model.images[size_t(source)];
  const std::string label = "image " + imageLabel(image, source);
  const auto& encoded = *context.encoded_images;
  if (size_t(source) >= encoded.size() || encoded[size_t(source)].empty()) {
    context.scene.warnings.push_back(user + ": " + label + " is missing; the factor is used alone");
    ++context.scene.counters.missing_textures;
    return slot;
  }
  const std::vector<unsigned char>& bytes = encoded[size_t(source)];
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels =
      stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels, 0);
  if (pixels == nullptr) {
    context.scene.warnings.push_back(user + ": " + label + " cannot be decoded (" +
                                     printableReason(stbi_failure_reason()) +
                                     "); the factor is used alone");
    ++context.scene.counters.missing_textures;
    return slot;
  }
  Texture texture;
  texture.name = image.uri.empty() ? image.name : image.uri;
  texture.width = width;
  texture.height = height;
  texture.channels = channels;
  texture.texels.assign(pixels, pixels + size_t(width) * size_t(height) * size_t(channels));
  stbi_image_free(pixels);
  if (gltf_texture.sampler >= 0 && size_t(gltf_texture.sampler) < model.samplers.size()) {
    texture.wrap_s = wrapMode(model.samplers[size_t(gltf_texture.sampler)].wrapS);
    texture.wrap_t = wrapMode(model.samplers[size_t(gltf_texture.sampler)].wrapT);
  }
  slot = int(context.scene.textures.size());
  context.scene.textures.push_back(std::move(texture));
  return slot;
}

Status readFactor(const std::vector<double>& values, size_t expected, const std::string& what,
                  double max_value, float* out) {
  if (values.size() != expected) {
    return Status(StatusCode::kInvalidInput, what + " has " + std::to_string(values.size()) +
                                                 " values, expected " + std::to_string(expected));
  }
  for (size_t i = 0; i < expected; ++i) {
    if (!std::isfinite(values[i]) || values[i] < 0.0 || values[i] > max_value) {
      return Status(StatusCode::kInvalidInput, what + "[" + std::to_string(i) +
                                                   "] = " + std::to_string(values[i]) +
                                                   " is outside [0, 1]");
    }
    out[i] = float(values[i]);
  }
  return Status();
}

Status readTextureRef(ImportContext& context, const tinygltf::TextureInfo& info,
                      const std::string& what, TextureRef& ref) {
  if (info.index < 0) return Status();
  const int decoded = decodeTexture(context, info.index, what);
  if (decoded == -2) {
    return Status(StatusCode::kInvalidInput,
                  what + ": texture " + std::to_string(info.index) + " does not exist");
  }
  ref.texture = decoded;
  // The UV set as a double until it is known to be 0 or 1: an int cast of
  // KHR_texture_transform's 1e300 would be undefined.
  double texcoord = info.texCoord;
  auto transform = info.extensions.find("KHR_texture_transform");
  if (transform != info.extensions.end() && transform->second.IsObject()) {
    const tinygltf::Value& t = transform->second;
    auto number = [](const tinygltf::Value& v, double fallback) {
      return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
    };
    if (t.Has("offset") && t.Get("offset").ArrayLen() == 2) {
      ref.offset = {float(number(t.Get("offset").Get(0), 0)),
                    float(number(t.Get("offset").Get(1), 0))};
    }
    if (t.Has("scale") && t.Get("scale").ArrayLen() == 2) {
      ref.scale = {float(number(t.Get("scale").Get(0), 1)),
                   float(number(t.Get("scale").Get(1), 1))};
    }
    if (t.Has("rotation")) ref.rotation_rad = float(number(t.Get("rotation"), 0));
    if (t.Has("texCoord")) texcoord = number(t.Get("texCoord"), texcoord);
    if (!std::isfinite(ref.offset.x) || !std::isfinite(ref.offset.y) ||
        !std::isfinite(ref.scale.x) || !std::isfinite(ref.scale.y) ||
        !std::isfinite(ref.rotation_rad)) {
      return Status(StatusCode::kInvalidInput, what + ": KHR_texture_transform is not finite");
    }
  }
  if (texcoord != 0 && texcoord != 1) {
    std::ostringstream set;
    set << texcoord;
    context.scene.warnings.push_back(what + ": TEXCOORD_" + set.str() +
                                     " is not supported (only 0 and 1); texture ignored");
    // No texture, and a UV set that is one (TextureRef's contract: never
    // an unsupported set beside texture -1; found by fuzz_glb).
    ref.texture = -1;
    ref.texcoord = 0;
  } else {
    ref.texcoord = int(texcoord);
  }
  return Status();
}

}  // namespace

std::string meshLabel(const tinygltf::Model& model, int mesh_index) {
  const std::string& name = model.meshes[size_t(mesh_index)].name;
  return name.empty() ? "mesh " + std::to_string(mesh_index) : "mesh '" + name + "'";
}

std::string nodeLabel(const tinygltf::Model& model, int node_index) {
  const std::string& name = model.nodes[size_t(node_index)].name;
  return name.empty() ? "node " + std::to_string(node_index) : "node '" + name + "'";
}

std::string materialLabel(const tinygltf::Model& model, int material_index) {
  const std::string& name = model.materials[size_t(material_index)].name;
  return name.empty() ? "material " + std::to_string(material_index) : "material '" + name + "'";
}

Status importMaterials(ImportContext& context) {
  const tinygltf::Model& model = context.model;
  context.texture_map.assign(model.textures.size(), -3);  // -3: not decoded yet
  context.scene.materials.reserve(model.materials.size());
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& source = model.materials[i];
    const std::string what = context.path + ": " + materialLabel(model, int(i));
    Material material;
    material.name = source.name.empty() ? "material " + std::to_string(i) : source.name;
    float base[4];
    if (Status s = readFactor(source.pbrMetallicRoughness.baseColorFactor, 4,
                              what + ": baseColorFactor", 1.0, base);
        !s.ok()) {
      return s;
    }
    material.base_color = {base[0], base[1], base[2]};
    material.base_alpha = base[3];
    float emissive[3] = {0, 0, 0};
    if (!source.emissiveFactor.empty()) {
      if (Status s = readFactor(source.emissiveFactor, 3, what + ": emissiveFactor", 1.0, emissive);
          !s.ok()) {
        return s;
      }
    }
    double strength = 1.0;
    auto ext = source.extensions.find("KHR_materials_emissive_strength");
    if (ext != source.extensions.end() && ext->second.Has("emissiveStrength")) {
      const tinygltf::Value& v = ext->second.Get("emissiveStrength");
      strength = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!std::isfinite(strength) || strength < 0.0) {
        return Status(StatusCode::kInvalidInput,
                      what + ": KHR_materials_emissive_strength.emissiveStrength = " +
                          std::to_string(strength) + " must be a finite number >= 0");
      }
    }
    material.emissive_luminance = {float(emissive[0] * strength), float(emissive[1] * strength),
                                   float(emissive[2] * strength)};
    material.double_sided = source.doubleSided;
    material.alpha_mode = source.alphaMode == "MASK"    ? AlphaMode::kMask
                          : source.alphaMode == "BLEND" ? AlphaMode::kBlend
                                                        : AlphaMode::kOpaque;
    material.alpha_cutoff = float(source.alphaCutoff);
    if (Status s = readTextureRef(context, source.pbrMetallicRoughness.baseColorTexture,
                                  what + " baseColorTexture", material.base_color_texture);
        !s.ok()) {
      return s;
    }
    if (Status s = readTextureRef(context, source.emissiveTexture, what + " emissiveTexture",
                                  material.emissive_texture);
        !s.ok()) {
      return s;
    }
    context.scene.materials.push_back(std::move(material));
  }
  return Status();
}

}  // namespace svit::gltf

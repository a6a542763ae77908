// glTF 2.0 import driver: reads the file with tinygltf, checks required
// extensions, then runs the stages in gltf_*_import.cpp and finalizes.

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include <tiny_gltf.h>

#include "gltf_import_context.h"
#include "scene_finalize.h"
#include "svit/level.h"

namespace svit {
namespace {

const std::set<std::string>& supportedExtensions() {
  static const std::set<std::string> supported = {"KHR_lights_punctual",
                                                  "KHR_materials_emissive_strength",
                                                  "KHR_texture_transform", "KHR_mesh_quantization"};
  return supported;
}

// tinygltf's image callback: keep the encoded bytes and decode later, only
// for the images that base-colour or emissive textures use (a PBR level's
// normal and roughness maps, often most of its texels, would otherwise cost
// seconds and gigabytes for nothing the bake reads).
// Images stored in a bufferView are not read here: tinygltf 2.7 hands over
// buffer bytes [byteOffset, byteOffset + byteLength) without checking them
// against the buffer's size (a heap overread found by fuzz_glb), so
// copyBufferViewImages() reads them after the load, bounds-checked.
bool keepEncodedImage(tinygltf::Image* image, const int image_index, std::string* /*err*/,
                      std::string* /*warn*/, int, int, const unsigned char* bytes, int size,
                      void* user_data) {
  auto* images = static_cast<std::vector<std::vector<unsigned char>>*>(user_data);
  if (image_index < 0 || image->bufferView >= 0 || size < 0) return true;
  if (images->size() <= size_t(image_index)) images->resize(size_t(image_index) + 1);
  (*images)[size_t(image_index)].assign(bytes, bytes + size);
  return true;
}

// The encoded bytes of images stored in a bufferView (GLB files), once the
// view is known to lie inside its buffer.
Status copyBufferViewImages(const tinygltf::Model& model, const std::string& path,
                            std::vector<std::vector<unsigned char>>& images) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    const int view_index = model.images[i].bufferView;
    if (view_index < 0) continue;
    // tinygltf checked that the view and its buffer exist; check again
    // rather than depend on it.
    const std::string what =
        path + ": image " + std::to_string(i) + ": bufferView " + std::to_string(view_index);
    if (size_t(view_index) >= model.bufferViews.size()) {
      return Status(StatusCode::kInvalidInput, what + " does not exist");
    }
    const tinygltf::BufferView& view = model.bufferViews[size_t(view_index)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
      return Status(StatusCode::kInvalidInput,
                    what + ": buffer " + std::to_string(view.buffer) + " does not exist");
    }
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
      return Status(StatusCode::kInvalidInput,
                    what + " bytes [" + std::to_string(view.byteOffset) + ", " +
                        std::to_string(uint64_t(view.byteOffset) + view.byteLength) +
                        ") out of bounds of buffer " + std::to_string(view.buffer) + " (" +
                        std::to_string(data.size()) + " bytes)");
    }
    if (images.size() <= i) images.resize(i + 1);
    images[i].assign(data.begin() + long(view.byteOffset),
                     data.begin() + long(view.byteOffset + view.byteLength));
  }
  return Status();
}

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s) {
    if (c == '\n') c = ';';
  }
  return s;
}

Status checkReadable(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    return Status(StatusCode::kNotFound, path + ": file not found");
  }
  if (std::filesystem::is_directory(path, ec)) {
    return Status(StatusCode::kIoError, path + ": is a directory, not a file");
  }
  std::ifstream probe(path, std::ios::binary);
  if (!probe) {
    return Status(StatusCode::kIoError, path + ": cannot open: " + std::strerror(errno));
  }
  return Status();
}

// tinygltf reports a cut GLB only as "Invalid glTF binary"; say what is wrong.
Status checkGlbLength(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  unsigned char header[12] = {};
  file.read(reinterpret_cast<char*>(header), 12);
  const std::streamsize got = file.gcount();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (got < 12 || std::memcmp(header, "glTF", 4) != 0) {
    return Status(StatusCode::kInvalidInput, path + ": not a GLB file (no 12-byte 'glTF' header)");
  }
  const uint32_t declared = uint32_t(header[8]) | uint32_t(header[9]) << 8 |
                            uint32_t(header[10]) << 16 | uint32_t(header[11]) << 24;
  if (!ec && declared > size) {
    return Status(StatusCode::kInvalidInput, path + ": truncated GLB: header length " +
                                                 std::to_string(declared) + " bytes, file has " +
                                                 std::to_string(size));
  }
  return Status();
}

}  // namespace

Expected<Scene> importGltfUnfinalized(const std::string& path, const LoadOptions& options,
                                      std::vector<int>& scene_roots) {
  if (Status s = checkReadable(path); !s.ok()) return s;
  tinygltf::TinyGLTF loader;
  std::vector<std::vector<unsigned char>> encoded_images;
  if (options.load_textures) {
    loader.SetImageLoader(keepEncodedImage, &encoded_images);
  } else {
    loader.SetImageLoader(skipImage, nullptr);
  }
  tinygltf::Model model;
  std::string error, warning;
  const std::string extension = std::filesystem::path(path).extension().string();
  const bool binary = extension == ".glb" || extension == ".GLB";
  if (binary) {
    if (Status s = checkGlbLength(path); !s.ok()) return s;
  }
  const bool loaded = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                             : loader.LoadASCIIFromFile(&model, &error, &warning, path);
  if (!loaded) {
    if (error.find("File not found") != std::string::npos) {
      return Status(StatusCode::kNotFound, path + ": buffer file not found: " + trimmed(error));
    }
    return Status(StatusCode::kInvalidInput,
                  path + ": not a valid glTF 2.0 file: " +
                      trimmed(error.empty() ? "tinygltf gave no reason" : error));
  }
  if (options.load_textures) {
    if (Status s = copyBufferViewImages(model, path, encoded_images); !s.ok()) return s;
  }
  Scene scene;
  scene.source_path = path;
  scene.gltf_path = path;
  if (!warning.empty()) scene.warnings.push_back(path + ": " + trimmed(warning));

  for (const std::string& required : model.extensionsRequired) {
    if (!supportedExtensions().count(required)) {
      return Status(StatusCode::kUnsupported,
                    path + ": extensionsRequired: '" + required +
                        "' is not supported (svit supports KHR_lights_punctual, "
                        "KHR_materials_emissive_strength, KHR_texture_transform, "
                        "KHR_mesh_quantization)");
    }
  }

  gltf::ImportContext context{model, path, options, scene, {}, &encoded_images, -1};
  if (Status s = gltf::importMaterials(context); !s.ok()) return s;
  if (Status s = gltf::importNodesAndLights(context, scene_roots); !s.ok()) return s;
  if (Status s = gltf::importCameras(context); !s.ok()) return s;
  // Convert only meshes that nodes of the scene use; others stay empty.
  scene.meshes.resize(model.meshes.size());
  std::vector<bool> used(model.meshes.size(), false);
  std::vector<int> stack(scene_roots.begin(), scene_roots.end());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (scene.nodes[size_t(n)].mesh >= 0) used[size_t(scene.nodes[size_t(n)].mesh)] = true;
    for (int child : scene.nodes[size_t(n)].children) stack.push_back(child);
  }
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    if (!used[m]) {
      scene.meshes[m].name = model.meshes[m].name;
      continue;
    }
    if (Status s = gltf::importMesh(context, int(m), scene.meshes[m]); !s.ok()) return s;
  }
  if (Status s = gltf::importAnimations(context); !s.ok()) return s;
  return scene;
}

Expected<Scene> loadGltf(const std::string& path, const LoadOptions& options) {
  std::vector<int> roots;
  Expected<Scene> scene = importGltfUnfinalized(path, options, roots);
  if (!scene.ok()) return scene;
  if (Status s = finalizeScene(*scene, roots); !s.ok()) return s;
  return scene;
}

}  // namespace svit

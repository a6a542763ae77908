#pragma once
// State shared by the stages of glTF import (materials, meshes, nodes,
// animations); internal to svit::scene.

#include <string>
#include <vector>

#include "svit/level.h"
#include "svit/scene.h"

namespace tinygltf {
class Model;
}

namespace svit::gltf {

struct ImportContext {
  const tinygltf::Model& model;
  std::string path;  ///< prefix of every message
  LoadOptions options;
  Scene& scene;
  /// glTF texture index -> Scene::textures index (-1: missing or not decoded).
  std::vector<int> texture_map;
  /// glTF image index -> encoded bytes kept by the image loader callback.
  std::vector<std::vector<unsigned char>>* encoded_images = nullptr;
  /// Scene::materials index of glTF's default material, created on first use.
  int default_material = -1;
};

/// "mesh 'Crate'" or "mesh 3" when unnamed.
std::string meshLabel(const tinygltf::Model& model, int mesh_index);
/// "node 'Door'" or "node 7" when unnamed.
std::string nodeLabel(const tinygltf::Model& model, int node_index);
/// "material 'Brick'" or "material 2" when unnamed.
std::string materialLabel(const tinygltf::Model& model, int material_index);

/// Fills Scene::textures (only those materials use) and Scene::materials.
Status importMaterials(ImportContext& context);
/// Converts glTF mesh `mesh_index` (all triangle primitives) into `mesh`.
Status importMesh(ImportContext& context, int mesh_index, Mesh& mesh);
/// Fills Scene::nodes (local transforms, extras.svit.dynamic) and lights.
Status importNodesAndLights(ImportContext& context, std::vector<int>& scene_roots);
/// Sets Node::camera and lists the perspective cameras the nodes hold in
/// Scene::cameras (placed by finalizeScene); orthographic ones are a warning.
Status importCameras(ImportContext& context);
/// Fills Scene::animations; marks animated nodes.
Status importAnimations(ImportContext& context);

}  // namespace svit::gltf

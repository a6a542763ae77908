#pragma once
// Last stage of level loading, after glTF import and level.json: inherit
// dynamic marks, compute world transforms, place instances, lights and cameras, and
// reject scenes with nothing to light.

#include <string>
#include <vector>

#include "svit/level.h"
#include "svit/scene.h"

namespace svit {

/// glTF import without the final stage (level.json adds marks in between).
/// `scene_roots` receives the root nodes of the glTF's active scene.
Expected<Scene> importGltfUnfinalized(const std::string& path, const LoadOptions& options,
                                      std::vector<int>& scene_roots);

/// Computes world transforms from `scene_roots`, inherits Node::dynamic and
/// Node::animated down the hierarchy, fills Scene::instances and the world
/// placement of node lights. Errors: non-finite world transform, no triangles.
Status finalizeScene(Scene& scene, const std::vector<int>& scene_roots);

}  // namespace svit

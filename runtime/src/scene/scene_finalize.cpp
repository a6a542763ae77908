#include "scene_finalize.h"

#include <cmath>

#include <glm/glm.hpp>

#include "glm_interop.h"
#include "numeric.h"

namespace svit {
namespace {

std::string nodeName(const Scene& scene, int node) {
  const std::string& name = scene.nodes[size_t(node)].name;
  return name.empty() ? "node " + std::to_string(node) : "node '" + name + "'";
}

// Animated static nodes listed one by one before they are only counted.
constexpr size_t kListedAnimatedStatic = 5;

}  // namespace

int Scene::findNode(const std::string& name) const {
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].name == name) return int(i);
  }
  return -1;
}

namespace {

// Keeps an instance for a mesh node unless its transform is singular (a
// zero scale, used to hide things, flattens the mesh to zero area: nothing
// to light).
void addInstance(Scene& scene, int n, const glm::mat4& world) {
  const Node& node = scene.nodes[size_t(n)];
  const glm::mat3 linear(world);
  const double scale =
      double(glm::length(linear[0])) * glm::length(linear[1]) * glm::length(linear[2]);
  if (!(std::abs(double(glm::determinant(linear))) > 1e-12 * scale) || scale == 0.0) {
    scene.warnings.push_back(scene.gltf_path + ": " + nodeName(scene, n) +
                             ": singular transform (zero scale), instance skipped");
    ++scene.counters.degenerate_instances;
  } else {
    scene.instances.push_back({n, node.mesh, node.world_from_node, node.dynamic});
  }
}

// Depth-first from the roots: world transform, dynamic and animated marks
// flow from parent to children; each mesh node reached becomes an instance.
Status placeNodes(Scene& scene, const std::vector<int>& scene_roots, std::vector<bool>& reached) {
  const std::string& path = scene.gltf_path;
  std::vector<int> stack(scene_roots.rbegin(), scene_roots.rend());
  for (int root : scene_roots)
    scene.nodes[size_t(root)].world_from_node = scene.nodes[size_t(root)].parent_from_node;
  size_t animated_static = 0;
  scene.instances.clear();
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    Node& node = scene.nodes[size_t(n)];
    reached[size_t(n)] = true;
    const bool own_animation = node.animated;
    if (node.parent >= 0) {
      const Node& parent = scene.nodes[size_t(node.parent)];
      node.world_from_node = fromGlm(toGlm(parent.world_from_node) * toGlm(node.parent_from_node));
      node.dynamic = node.dynamic || parent.dynamic;
      node.animated = node.animated || parent.animated;
    }
    if (own_animation && !node.dynamic && ++animated_static <= kListedAnimatedStatic) {
      scene.warnings.push_back(path + ": " + nodeName(scene, n) +
                               " is animated but static: baked at its rest pose (mark it "
                               "dynamic in level.json)");
    }
    if (!finite(node.world_from_node)) {
      return Status(StatusCode::kInvalidInput,
                    path + ": " + nodeName(scene, n) + ": world transform is not finite");
    }
    if (node.mesh >= 0) addInstance(scene, n, toGlm(node.world_from_node));
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back(*it);
  }
  if (animated_static > kListedAnimatedStatic) {
    scene.warnings.push_back(path + ": " + std::to_string(animated_static) +
                             " animated nodes are static in all");
  }
  return Status();
}

// Places node lights; lights on nodes outside the active scene are dropped.
Status placeLights(Scene& scene, const std::vector<bool>& reached) {
  std::vector<Light> placed;
  for (Light& light : scene.lights) {
    if (light.node >= 0) {
      if (!reached[size_t(light.node)]) continue;
      const Node& node = scene.nodes[size_t(light.node)];
      const glm::mat4 world = toGlm(node.world_from_node);
      light.position = fromGlm(transformPoint(world, glm::vec3(0)));
      const glm::vec3 direction = glm::mat3(world) * glm::vec3(0, 0, -1);
      if (!(glm::length(direction) > 0.0f)) {
        return Status(StatusCode::kInvalidInput, scene.gltf_path + ": light '" + light.name +
                                                     "' on " + nodeName(scene, light.node) +
                                                     ": singular transform gives it no direction");
      }
      light.direction = fromGlm(glm::normalize(direction));
      light.dynamic = light.dynamic || node.dynamic;
    }
    placed.push_back(light);
  }
  scene.lights = std::move(placed);
  return Status();
}

// Places the cameras by their nodes (looking down the node's -Z, +Y up);
// cameras on nodes outside the active scene are dropped, like lights.
Status placeCameras(Scene& scene, const std::vector<bool>& reached) {
  std::vector<SceneCamera> placed;
  for (SceneCamera& camera : scene.cameras) {
    if (!reached[size_t(camera.node)]) continue;
    const glm::mat4 world = toGlm(scene.nodes[size_t(camera.node)].world_from_node);
    const glm::vec3 forward = glm::mat3(world) * glm::vec3(0, 0, -1);
    const glm::vec3 up = glm::mat3(world) * glm::vec3(0, 1, 0);
    const glm::vec3 right = glm::cross(forward, up);
    if (!(glm::length(right) > 0.0f)) {
      return Status(StatusCode::kInvalidInput, scene.gltf_path + ": camera '" + camera.name +
                                                   "' on " + nodeName(scene, camera.node) +
                                                   ": singular transform gives it no view");
    }
    camera.position = fromGlm(transformPoint(world, glm::vec3(0)));
    camera.forward = fromGlm(glm::normalize(forward));
    camera.up = fromGlm(glm::normalize(glm::cross(right, forward)));
    placed.push_back(camera);
  }
  scene.cameras = std::move(placed);
  return Status();
}

Status checkHasTriangles(const Scene& scene) {
  size_t triangles = 0;
  for (const Instance& instance : scene.instances)
    triangles += scene.meshes[size_t(instance.mesh)].triangleCount();
  if (triangles == 0) {
    return Status(StatusCode::kInvalidInput, scene.gltf_path +
                                                 ": empty scene: no triangles to light (" +
                                                 std::to_string(scene.nodes.size()) + " nodes, " +
                                                 std::to_string(scene.meshes.size()) + " meshes)");
  }
  return Status();
}

}  // namespace

Status finalizeScene(Scene& scene, const std::vector<int>& scene_roots) {
  std::vector<bool> reached(scene.nodes.size(), false);
  if (Status s = placeNodes(scene, scene_roots, reached); !s.ok()) return s;
  if (Status s = placeLights(scene, reached); !s.ok()) return s;
  if (Status s = placeCameras(scene, reached); !s.ok()) return s;
  return checkHasTriangles(scene);
}

}  // namespace svit

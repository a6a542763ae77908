#include "walk_motion.h"

#include <string>

#include "walk_math.h"

namespace svit::walk {
namespace {

bool sameMatrix(const Mat4& a, const Mat4& b) { return a.m == b.m; }

std::string nodeLabel(const Scene& scene, int node) {
  const std::string& name = scene.nodes[size_t(node)].name;
  return name.empty() ? "node " + std::to_string(node) : "node '" + name + "'";
}

}  // namespace

LevelMotion::LevelMotion(const Scene& scene)
    : scene_(scene),
      locals_(scene.nodes.size()),
      use_trs_(scene.nodes.size(), false),
      moved_(scene.nodes.size(), false),
      world_(scene.nodes.size()) {
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const Node& node = scene.nodes[n];
    locals_[n] = {node.translation, node.rotation, node.scale};
    world_[n] = node.world_from_node;
  }
  // Parents before children, from every root (depth first, file order).
  std::vector<int> stack;
  for (size_t n = scene.nodes.size(); n-- > 0;) {
    if (scene.nodes[n].parent < 0) stack.push_back(int(n));
  }
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    order_.push_back(n);
    const std::vector<int>& children = scene.nodes[size_t(n)].children;
    for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(*it);
  }
  for (const Instance& instance : scene.instances) {
    if (!instance.dynamic) continue;
    object_nodes_.push_back(instance.node);
    applied_.push_back(instance.world_from_object);
  }
  applied_light_world_.resize(scene.lights.size());
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    const int node = scene.lights[l].node;
    if (node >= 0) applied_light_world_[l] = scene.nodes[size_t(node)].world_from_node;
  }
}

void LevelMotion::moveNode(int node, const Trs& local) {
  locals_[size_t(node)] = local;
  use_trs_[size_t(node)] = true;
  moved_[size_t(node)] = true;
}

void LevelMotion::advance(float t_s) {
  for (const ObjectPath& path : scene_.object_paths) {
    if (path.node < 0 || moved_[size_t(path.node)]) continue;
    if (path.animation >= 0) {
      // A glTF animation: every track aimed at the path's node or a node
      // under it that no move has detached.
      const Animation& animation = scene_.animations[size_t(path.animation)];
      const float clip_t = clipTime(t_s, animation.duration_s, path.loop);
      for (const AnimationTrack& track : animation.tracks) {
        bool under = false;
        for (int n = track.node; n >= 0 && !under; n = scene_.nodes[size_t(n)].parent)
          under = n == path.node;
        if (!under || moved_[size_t(track.node)]) continue;
        applyTrack(track, clip_t, locals_[size_t(track.node)]);
        use_trs_[size_t(track.node)] = true;
      }
    } else if (!path.keys.empty()) {
      locals_[size_t(path.node)] = samplePathKeys(path.keys, t_s, path.loop);
      use_trs_[size_t(path.node)] = true;
    }
  }
  // World transforms: recomputed only below nodes that can change, so a
  // static node keeps the loader's matrix bit for bit.
  std::vector<bool> changed(scene_.nodes.size(), false);
  for (int n : order_) {
    const Node& node = scene_.nodes[size_t(n)];
    const bool parent_changed = node.parent >= 0 && changed[size_t(node.parent)];
    if (!use_trs_[size_t(n)] && !parent_changed) continue;
    const Mat4 local = use_trs_[size_t(n)] ? composeTrs(locals_[size_t(n)]) : node.parent_from_node;
    world_[size_t(n)] =
        node.parent >= 0 ? fromGlm(toGlm(world_[size_t(node.parent)]) * toGlm(local)) : local;
    changed[size_t(n)] = true;
  }
}

Status LevelMotion::applyTo(Runtime& runtime) {
  for (size_t i = 0; i < object_nodes_.size(); ++i) {
    const int node = object_nodes_[i];
    if (sameMatrix(world_[size_t(node)], applied_[i])) continue;
    const ObjectId object = runtime.objectForNode(node);
    if (object == kInvalidId) continue;  // not an object of this runtime (nothing to move)
    Status s = runtime.setObjectTransform(object, world_[size_t(node)]);
    if (!s.ok()) return Status(s.code(), nodeLabel(scene_, node) + ": " + s.message());
    applied_[i] = world_[size_t(node)];
  }
  for (size_t l = 0; l < scene_.lights.size(); ++l) {
    const Light& light = scene_.lights[l];
    if (light.node < 0 || sameMatrix(world_[size_t(light.node)], applied_light_world_[l])) continue;
    const LightId id = runtime.lightForSceneLight(int(l));
    if (id == kInvalidId) continue;  // a baked light on a static node never moves
    const glm::mat4 world = toGlm(world_[size_t(light.node)]);
    Light placed = light;
    placed.position = fromGlm(glm::vec3(world[3]));
    const glm::vec3 direction = glm::mat3(world) * glm::vec3(0, 0, -1);
    if (glm::length(direction) > 0) placed.direction = fromGlm(glm::normalize(direction));
    Status s = runtime.setLight(id, placed);
    if (!s.ok()) return Status(s.code(), "light '" + light.name + "': " + s.message());
    applied_light_world_[l] = world_[size_t(light.node)];
  }
  return Status();
}

}  // namespace svit::walk

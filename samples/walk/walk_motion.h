#pragma once
// Where a level's nodes are at a time: local transforms from the level's
// paths (keys or glTF animations) and from explicit moves, world transforms
// through the hierarchy, and the runtime told about what changed (dynamic
// objects, lights hung on nodes).

#include <vector>

#include "svit/runtime.h"
#include "svit/scene.h"
#include "svit/status.h"
#include "walk_animation.h"

namespace svit::walk {

class LevelMotion {
 public:
  /// Keeps a reference to `scene`, which must outlive this object.
  explicit LevelMotion(const Scene& scene);

  /// Poses every node that follows a path (Scene::object_paths) at global
  /// time `t_s` seconds and recomputes world transforms. Nodes moved by
  /// moveNode() no longer follow their paths.
  void advance(float t_s);

  /// Sets `node`'s local transform (parent space) and detaches it from its
  /// path for good. Takes effect at the next advance().
  void moveNode(int node, const Trs& local);
  /// The local transform a node has now (its path's pose, a move, or the file's).
  const Trs& localTrs(int node) const { return locals_[size_t(node)]; }

  /// World transform of `node` as of the last advance().
  const Mat4& worldFromNode(int node) const { return world_[size_t(node)]; }

  /// Tells `runtime` the new transforms of dynamic objects that moved since
  /// the last call, and places the runtime lights hung on nodes (position
  /// at the node's origin, direction its -Z axis). Errors: what the runtime
  /// refused (names the node).
  Status applyTo(Runtime& runtime);

  /// Nodes that hold a dynamic object (one per dynamic instance, scene order).
  const std::vector<int>& objectNodes() const { return object_nodes_; }

 private:
  const Scene& scene_;
  std::vector<Trs> locals_;
  std::vector<bool> use_trs_;  // false: the file's matrix (parent_from_node)
  std::vector<bool> moved_;    // detached from its path by moveNode()
  std::vector<Mat4> world_;
  std::vector<int> order_;  // parents before children
  std::vector<int> object_nodes_;
  std::vector<Mat4> applied_;              // per object node: what the runtime has
  std::vector<Mat4> applied_light_world_;  // per scene light: its node's world when last placed
};

}  // namespace svit::walk

#pragma once
// Elements and clusters as one tree (thesis ch. 4, static part;
// docs/architecture/baker-radiosity.md "Elements and clusters"): every static
// object with two or more triangle elements is a cluster split top-down into
// a binary tree; triangles subdivide into halves across their longest edge. A
// double-sided triangle is two elements, one per side, so light received on
// one side is reflected on that side only. Subdivision is conforming
// (Rivara's longest-edge bisection): a split propagates to the neighbours
// across the split edge so no T-vertex survives.

#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "svit/baker/bake_geometry.h"

namespace svit::baker {

enum class NodeKind : uint8_t { kCluster, kTriangle, kSubTriangle };

/// A node of the element/cluster tree. Clusters have two children; a triangle
/// or sub-triangle is a leaf until it is split in two.
struct TreeNode {
  NodeKind kind = NodeKind::kCluster;
  uint8_t side = 0;  ///< 0: front of the triangle, 1: back (double-sided only)
  uint16_t depth = 0;
  int32_t parent = -1;
  int32_t child[2] = {-1, -1};
  uint32_t triangle = 0;           ///< BakeGeometry triangle (elements only)
  uint32_t vertex[3] = {0, 0, 0};  ///< welded vertex ids, counter-clockwise seen from `normal`
  float bary[3][2] = {};           ///< corners as (u, v) barycentrics of the original triangle
  double area_m2 = 0;              ///< one side; clusters: sum over leaves
  double perimeter_m = 0;          ///< elements; clusters: 0
  glm::dvec3 centroid{0.0};        ///< area-weighted for clusters
  /// unit for elements; area-weighted mean for clusters (may be short)
  glm::dvec3 normal{0.0};
  glm::dvec3 reflectance_area{0.0};  ///< sum over leaves of albedo * area (per channel), m2
  glm::dvec3 emitted_flux{0.0};      ///< sum over leaves of pi * L * area, lm per channel
  bool isLeaf() const { return child[0] < 0; }
};

/// Evaluates the mean emitted luminance (cd/m2) of original triangle
/// `triangle` over the sub-triangle with the given barycentric corners; used
/// to split emitters whose halves emit unequally (emissive textures).
using EmissionOver = std::function<glm::dvec3(uint32_t triangle, const float (&bary)[3][2])>;

struct TreeSettings {
  /// An element splits only while its perimeter exceeds this (m).
  double min_perimeter_m = 0.1;
  /// An emitter splits while one half emits more than this many times the other.
  double emitter_split_ratio = 2.0;
  /// Clusters split by orientation while the normals spread wider than this (rad).
  double orientation_split_rad = 0.7853981633974483;  // 45 degrees
  /// Clusters split at a gap between centroids wider than this fraction of their extent.
  double gap_split_fraction = 0.25;
  /// Hard cap on nodes so a runaway criterion cannot exhaust memory.
  size_t max_nodes = 20'000'000;
};

class ElementTree {
 public:
  /// Builds the elements of `geometry` and one cluster tree per static
  /// instance. `emission_over` (optional) splits textured emitters.
  ElementTree(const BakeGeometry& geometry, const TreeSettings& settings,
              const EmissionOver& emission_over = {});

  const std::vector<TreeNode>& nodes() const { return nodes_; }
  const TreeNode& node(int index) const { return nodes_[size_t(index)]; }
  /// Top of each object's tree (a cluster, or a lone element).
  std::span<const int> objectRoots() const { return object_roots_; }
  /// Element node of a triangle side; -1 when the side does not exist
  /// (the back of a single-sided triangle).
  int elementRoot(uint32_t triangle, bool front) const {
    return element_roots_[size_t(triangle) * 2 + (front ? 0 : 1)];
  }
  /// Leaf below `element` containing barycentric (u, v) of its triangle.
  int locateLeaf(int element, double u, double v) const;
  /// Splits leaf `leaf` across its longest edge, and its neighbours as far
  /// as needed to leave no T-vertex. `on_split` is called for every node that
  /// stops being a leaf. Returns false (and splits nothing) at the node cap.
  bool subdivide(int leaf, const std::function<void(int)>& on_split);
  const glm::dvec3& vertexPosition(uint32_t vertex) const { return vertex_positions_[vertex]; }
  size_t vertexCount() const { return vertex_positions_.size(); }
  size_t leafCount() const { return leaf_count_; }
  /// World position of barycentric (b1, b2) inside element/sub-triangle `n`.
  glm::dvec3 pointIn(int n, double b1, double b2) const;
  /// The geometry the tree was built over.
  const BakeGeometry& geometry() const { return geometry_; }
  const TreeSettings& settings() const { return settings_; }

 private:
  uint32_t weld(const Vec3& p);
  uint32_t midpoint(uint32_t a, uint32_t b);
  int longestEdge(int n) const;
  void addEdges(int n);
  void removeEdges(int n);
  bool hasEdge(int n, uint32_t a, uint32_t b) const;
  bool splitLeaf(int n, const std::function<void(int)>& on_split);
  void refineAcross(int f, uint32_t a, uint32_t b, const std::function<void(int)>& on_split);
  int buildCluster(std::vector<int>& elements, uint16_t depth);
  void splitEmitters(int n);
  /// Sets leaf `n`'s emitted luminance (cd/m2) and updates the sums above it.
  void setEmission(int n, const glm::dvec3& luminance);
  void setDepths(int n, uint16_t depth);

  const BakeGeometry& geometry_;
  TreeSettings settings_;
  EmissionOver emission_over_;
  std::vector<TreeNode> nodes_;
  std::vector<int> element_roots_;
  std::vector<int> object_roots_;
  std::vector<glm::dvec3> vertex_positions_;
  std::unordered_map<uint64_t, uint32_t> weld_map_;  // position bits -> vertex (lookup only)
  // edge key -> midpoint vertex (lookup only)
  std::unordered_map<uint64_t, uint32_t> midpoints_;
  // edge key -> leaves using it (lookup only)
  std::unordered_map<uint64_t, std::vector<int>> edges_;
  size_t leaf_count_ = 0;
};

/// Key of the undirected edge (a, b).
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

}  // namespace svit::baker

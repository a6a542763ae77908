// Patches: the cluster-tree nodes of bounded area and similar normal that the
// runtime tracks radiosity deltas for (docs/architecture/baker-sections.md
// "Patches"; thesis ch. 5 works on such groups of elements). A top-down walk
// of each object's tree (element_tree.h) stops at the first node that is
// small and flat enough, so patches follow the solver's own clustering, and
// the cluster nodes above them become the runtime's cluster trees.

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "radiosity/element_tree.h"
#include "runtime_sections_internal.h"
#include "util/double_math.h"

namespace svit::baker {
namespace {

// The element nodes (triangle sides) below `n`, in tree order.
void collectElements(const ElementTree& tree, int n, std::vector<int>& out) {
  std::vector<int> stack{n};
  while (!stack.empty()) {
    const int m = stack.back();
    stack.pop_back();
    const TreeNode& node = tree.node(m);
    if (node.kind != NodeKind::kCluster) {
      out.push_back(m);  // an element; its sub-triangles belong to it
    } else {
      stack.push_back(node.child[1]);
      stack.push_back(node.child[0]);
    }
  }
}

// True when every element's normal lies within acos(cos_max) of the
// area-weighted mean normal of `elements`.
bool flatEnough(const ElementTree& tree, const std::vector<int>& elements, double cos_max) {
  glm::dvec3 sum(0.0);
  for (int e : elements) sum += tree.node(e).normal * tree.node(e).area_m2;
  const double length = glm::length(sum);
  if (!(length > 0)) return false;  // opposite sides cancel: never one patch
  const glm::dvec3 mean = sum / length;
  for (int e : elements) {
    if (glm::dot(tree.node(e).normal, mean) < cos_max) return false;
  }
  return true;
}

void growBounds(Aabb& box, const Vec3& p) {
  box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
  box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
}

// Adds the patch made of `elements` (sums over them in double, then one
// rounding) and marks it on cluster `index`.
void addPatch(const BakeGeometry& geometry, const ElementTree& tree,
              const std::vector<Rgb> (&radiosity)[2], const std::vector<int>& elements,
              int32_t index, PatchSet& out) {
  const uint32_t patch_index = uint32_t(out.patches.size());
  std::vector<uint32_t> ids;
  ids.reserve(elements.size());
  double area = 0;
  glm::dvec3 centroid(0.0), normal(0.0), reflectance(0.0), emitted(0.0), exitance(0.0);
  Aabb bounds;
  for (int e : elements) {
    const TreeNode& el = tree.node(e);
    const uint32_t id = el.triangle * 2 + el.side;
    ids.push_back(id);
    out.element_patch[id] = int32_t(patch_index);
    area += el.area_m2;
    centroid += el.centroid * el.area_m2;
    normal += el.normal * el.area_m2;
    reflectance += el.reflectance_area;
    emitted += el.emitted_flux;
    exitance += dvec(radiosity[el.side][el.triangle]) * el.area_m2;
    for (int k = 0; k < 3; ++k) growBounds(bounds, geometry.corner(el.triangle, k));
  }
  std::sort(ids.begin(), ids.end());
  BakePatch patch;
  patch.centroid = vec3(centroid / area);
  const double length = glm::length(normal);
  // A lone element's normal is unit; a flat-enough group's sum is long.
  patch.normal = vec3(length > 0 ? normal / length : tree.node(elements.front()).normal);
  patch.area_m2 = float(area);
  patch.albedo = rgb(reflectance / area);
  patch.emission = rgb(emitted / area);  // pi * L, lm/m2
  patch.radiosity = rgb(exitance / area);
  patch.first_element = uint32_t(out.patch_elements.size());
  patch.element_count = uint32_t(ids.size());
  out.patch_elements.insert(out.patch_elements.end(), ids.begin(), ids.end());
  out.patches.push_back(patch);
  out.clusters[size_t(index)].patch = int32_t(patch_index);
  out.clusters[size_t(index)].bounds = bounds;
}

// Interior bounds: children follow their parent in pre-order, so one
// backward sweep sees every child before its parent.
void growClusterBounds(PatchSet& out) {
  for (size_t i = out.clusters.size(); i-- > 0;) {
    const BakeClusterNode& c = out.clusters[i];
    if (c.parent < 0) continue;
    Aabb& parent = out.clusters[size_t(c.parent)].bounds;
    growBounds(parent, c.bounds.min);
    growBounds(parent, c.bounds.max);
  }
}

}  // namespace

PatchSet buildPatches(const BakeGeometry& geometry, const RadiositySolver& solver,
                      double max_area_m2, double max_normal_rad) {
  const ElementTree& tree = solver.tree();
  const std::vector<Rgb> radiosity[2] = {solver.triangleRadiosity(true),
                                         solver.triangleRadiosity(false)};
  const double cos_max = std::cos(max_normal_rad);
  PatchSet out;
  out.element_patch.assign(geometry.triangleCount() * 2, -1);

  struct Item {
    int node;
    int32_t parent;  // cluster index of the parent, -1 for a root
    int slot;        // which child of the parent
  };
  std::vector<Item> stack;
  std::vector<int> elements;
  for (int root : tree.objectRoots()) {
    stack.push_back({root, -1, 0});
    while (!stack.empty()) {
      const Item item = stack.back();
      stack.pop_back();
      const TreeNode& node = tree.node(item.node);
      const int32_t index = int32_t(out.clusters.size());
      out.clusters.emplace_back();
      out.clusters.back().parent = item.parent;
      out.clusters.back().area_m2 = float(node.area_m2);
      if (item.parent >= 0) out.clusters[size_t(item.parent)].child[item.slot] = index;

      elements.clear();
      bool is_patch = node.kind != NodeKind::kCluster;  // a lone element always is
      if (!is_patch && node.area_m2 <= max_area_m2) {
        collectElements(tree, item.node, elements);
        is_patch = flatEnough(tree, elements, cos_max);
      }
      if (!is_patch) {
        stack.push_back({node.child[1], index, 1});
        stack.push_back({node.child[0], index, 0});
        continue;
      }
      if (elements.empty()) collectElements(tree, item.node, elements);
      addPatch(geometry, tree, radiosity, elements, index, out);
    }
  }
  growClusterBounds(out);
  return out;
}

}  // namespace svit::baker

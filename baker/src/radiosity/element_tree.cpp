// Element/cluster tree: construction (clusters split by orientation, gaps
// and balance), conforming longest-edge bisection (Rivara 1984, as the thesis
// asks for T-vertex-free meshes), textured-emitter splitting and point
// location.

#include "element_tree.h"
#include "util/double_math.h"
#include "util/random.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace svit::baker {

ElementTree::ElementTree(const BakeGeometry& geometry, const TreeSettings& settings,
                         const EmissionOver& emission_over)
    : geometry_(geometry), settings_(settings), emission_over_(emission_over) {
  const size_t triangles = geometry.triangleCount();
  element_roots_.assign(triangles * 2, -1);
  nodes_.reserve(triangles * 3);
  // Elements, grouped per instance in triangle order.
  std::map<uint32_t, std::vector<int>> per_instance;  // ordered: deterministic
  for (size_t t = 0; t < triangles; ++t) {
    uint32_t v[3];
    for (int k = 0; k < 3; ++k) v[k] = weld(geometry.corner(t, k));
    const int sides = geometry.double_sided[t] ? 2 : 1;
    for (int side = 0; side < sides; ++side) {
      TreeNode n;
      n.kind = NodeKind::kTriangle;
      n.side = uint8_t(side);
      n.triangle = uint32_t(t);
      // The back side runs the corners the other way so it is
      // counter-clockwise seen from its own (flipped) normal.
      const int order[2][3] = {{0, 1, 2}, {0, 2, 1}};
      const float corners[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      for (int k = 0; k < 3; ++k) {
        n.vertex[k] = v[order[side][k]];
        n.bary[k][0] = corners[order[side][k]][0];
        n.bary[k][1] = corners[order[side][k]][1];
      }
      n.area_m2 = geometry.areas_m2[t];
      const glm::dvec3 p0 = dvec(geometry.corner(t, 0)), p1 = dvec(geometry.corner(t, 1)),
                       p2 = dvec(geometry.corner(t, 2));
      n.perimeter_m = glm::length(p1 - p0) + glm::length(p2 - p1) + glm::length(p0 - p2);
      n.centroid = (p0 + p1 + p2) / 3.0;
      n.normal = dvec(geometry.normals[t]) * (side == 0 ? 1.0 : -1.0);
      const Rgb& albedo = geometry.albedo[t];
      n.reflectance_area = glm::dvec3(albedo.r, albedo.g, albedo.b) * n.area_m2;
      const Rgb& e = geometry.emission[t];
      n.emitted_flux = glm::dvec3(e.r, e.g, e.b) * (kPi * n.area_m2);
      const int index = int(nodes_.size());
      nodes_.push_back(n);
      element_roots_[t * 2 + size_t(side)] = index;
      per_instance[geometry.instance[t]].push_back(index);
      addEdges(index);
      ++leaf_count_;
    }
  }
  for (auto& [instance, elements] : per_instance) {
    (void)instance;
    object_roots_.push_back(elements.size() >= 2 ? buildCluster(elements, 0) : elements.front());
  }
  for (int root : object_roots_) setDepths(root, 0);
  if (emission_over_) {
    for (size_t t = 0; t < triangles; ++t) {
      for (int side = 0; side < 2; ++side) {
        const int e = element_roots_[t * 2 + size_t(side)];
        if (e >= 0 && luminanceOf(nodes_[size_t(e)].emitted_flux) > 0) splitEmitters(e);
      }
    }
  }
}

void ElementTree::setDepths(int n, uint16_t depth) {
  nodes_[size_t(n)].depth = depth;
  for (int c : nodes_[size_t(n)].child) {
    if (c >= 0) setDepths(c, uint16_t(depth + 1));
  }
}

uint32_t ElementTree::weld(const Vec3& p) {
  // Exact positions: meshes that share a corner share its float bits; a
  // tolerance would merge distinct vertices of tiny or far-away geometry.
  uint32_t bits[3];
  std::memcpy(bits, &p, sizeof bits);
  const uint64_t key = hashIds(bits[0], bits[1], bits[2]);
  auto [it, inserted] = weld_map_.try_emplace(key, uint32_t(vertex_positions_.size()));
  if (inserted) {
    vertex_positions_.push_back(dvec(p));
  } else if (vertex_positions_[it->second] != dvec(p)) {
    // Hash collision between different positions: keep them apart by
    // probing with a perturbed key (rare; deterministic).
    uint64_t probe = key;
    while (true) {
      probe = probe * 0x9e3779b97f4a7c15ull + 1;
      auto [pit, pinserted] = weld_map_.try_emplace(probe, uint32_t(vertex_positions_.size()));
      if (pinserted) {
        vertex_positions_.push_back(dvec(p));
        return pit->second;
      }
      if (vertex_positions_[pit->second] == dvec(p)) return pit->second;
    }
  }
  return it->second;
}

uint32_t ElementTree::midpoint(uint32_t a, uint32_t b) {
  auto [it, inserted] = midpoints_.try_emplace(edgeKey(a, b), uint32_t(vertex_positions_.size()));
  if (inserted) vertex_positions_.push_back(0.5 * (vertex_positions_[a] + vertex_positions_[b]));
  return it->second;
}

int ElementTree::longestEdge(int n) const {
  const TreeNode& e = nodes_[size_t(n)];
  int best = 0;
  double best_length = -1;
  uint64_t best_key = 0;
  for (int k = 0; k < 3; ++k) {
    const uint32_t a = e.vertex[k], b = e.vertex[(k + 1) % 3];
    const glm::dvec3 d = vertex_positions_[a] - vertex_positions_[b];
    const double length = glm::dot(d, d);
    const uint64_t key = edgeKey(a, b);
    // Ties (isosceles elements) go to the smaller edge key, so both elements
    // sharing an edge agree on it.
    if (length > best_length || (length == best_length && key < best_key)) {
      best = k;
      best_length = length;
      best_key = key;
    }
  }
  return best;
}

void ElementTree::addEdges(int n) {
  const TreeNode& e = nodes_[size_t(n)];
  for (int k = 0; k < 3; ++k) edges_[edgeKey(e.vertex[k], e.vertex[(k + 1) % 3])].push_back(n);
}

void ElementTree::removeEdges(int n) {
  const TreeNode& e = nodes_[size_t(n)];
  for (int k = 0; k < 3; ++k) {
    auto it = edges_.find(edgeKey(e.vertex[k], e.vertex[(k + 1) % 3]));
    if (it == edges_.end()) continue;
    auto& list = it->second;
    list.erase(std::remove(list.begin(), list.end(), n), list.end());
    if (list.empty()) edges_.erase(it);
  }
}

bool ElementTree::hasEdge(int n, uint32_t a, uint32_t b) const {
  const TreeNode& e = nodes_[size_t(n)];
  const uint64_t key = edgeKey(a, b);
  for (int k = 0; k < 3; ++k) {
    if (edgeKey(e.vertex[k], e.vertex[(k + 1) % 3]) == key) return true;
  }
  return false;
}

glm::dvec3 ElementTree::pointIn(int n, double b1, double b2) const {
  const TreeNode& e = nodes_[size_t(n)];
  const glm::dvec3& p0 = vertex_positions_[e.vertex[0]];
  return p0 + b1 * (vertex_positions_[e.vertex[1]] - p0) +
         b2 * (vertex_positions_[e.vertex[2]] - p0);
}

bool ElementTree::splitLeaf(int n, const std::function<void(int)>& on_split) {
  if (nodes_.size() + 2 > settings_.max_nodes) return false;
  const int k = longestEdge(n);
  const TreeNode parent = nodes_[size_t(n)];  // copy: push_back below reallocates
  const uint32_t a = parent.vertex[k], b = parent.vertex[(k + 1) % 3],
                 c = parent.vertex[(k + 2) % 3];
  const uint32_t m = midpoint(a, b);
  const float* ba = parent.bary[k];
  const float* bb = parent.bary[(k + 1) % 3];
  const float* bc = parent.bary[(k + 2) % 3];
  const float bm[2] = {0.5f * (ba[0] + bb[0]), 0.5f * (ba[1] + bb[1])};
  removeEdges(n);
  const uint32_t corners[2][3] = {{a, m, c}, {m, b, c}};
  const float* bary[2][3] = {{ba, bm, bc}, {bm, bb, bc}};
  for (int i = 0; i < 2; ++i) {
    TreeNode child;
    child.kind = NodeKind::kSubTriangle;
    child.side = parent.side;
    child.depth = uint16_t(parent.depth + 1);
    child.parent = n;
    child.triangle = parent.triangle;
    for (int j = 0; j < 3; ++j) {
      child.vertex[j] = corners[i][j];
      child.bary[j][0] = bary[i][j][0];
      child.bary[j][1] = bary[i][j][1];
    }
    // A midpoint split halves the area exactly.
    child.area_m2 = 0.5 * parent.area_m2;
    const glm::dvec3 q0 = vertex_positions_[child.vertex[0]],
                     q1 = vertex_positions_[child.vertex[1]],
                     q2 = vertex_positions_[child.vertex[2]];
    child.perimeter_m = glm::length(q1 - q0) + glm::length(q2 - q1) + glm::length(q0 - q2);
    child.centroid = (q0 + q1 + q2) / 3.0;
    child.normal = parent.normal;
    child.reflectance_area = 0.5 * parent.reflectance_area;
    child.emitted_flux = 0.5 * parent.emitted_flux;
    const int index = int(nodes_.size());
    nodes_.push_back(child);
    nodes_[size_t(n)].child[i] = index;
    addEdges(index);
  }
  ++leaf_count_;
  if (on_split) on_split(n);
  // Conformity: every other leaf on edge (a, b) must split at m too.
  auto it = edges_.find(edgeKey(a, b));
  if (it != edges_.end()) {
    const std::vector<int> neighbours = it->second;
    for (int f : neighbours) refineAcross(f, a, b, on_split);
  }
  return true;
}

void ElementTree::refineAcross(int f, uint32_t a, uint32_t b,
                               const std::function<void(int)>& on_split) {
  // Rivara: split f on its own longest edge until the leaf holding (a, b)
  // has it as its longest edge, then split that one at the shared midpoint.
  while (nodes_[size_t(f)].isLeaf() && hasEdge(f, a, b)) {
    const TreeNode& e = nodes_[size_t(f)];
    const int k = longestEdge(f);
    const bool shared_is_longest = edgeKey(e.vertex[k], e.vertex[(k + 1) % 3]) == edgeKey(a, b);
    if (!splitLeaf(f, on_split)) return;
    if (shared_is_longest) return;
    const TreeNode& split = nodes_[size_t(f)];
    f = hasEdge(split.child[0], a, b) ? split.child[0] : split.child[1];
  }
}

bool ElementTree::subdivide(int leaf, const std::function<void(int)>& on_split) {
  if (!nodes_[size_t(leaf)].isLeaf()) return false;
  return splitLeaf(leaf, on_split);
}

int ElementTree::locateLeaf(int element, double u, double v) const {
  int n = element;
  while (!nodes_[size_t(n)].isLeaf()) {
    // Child 0 is (a, m, c) and child 1 is (m, b, c): the point belongs to
    // child 0 when it lies on a's side of the line m-c (one 2-D cross
    // product per level; points on the line may go either way).
    const TreeNode& first = nodes_[size_t(nodes_[size_t(n)].child[0])];
    const double ax = first.bary[0][0], ay = first.bary[0][1];
    const double mx = first.bary[1][0], my = first.bary[1][1];
    const double cx = first.bary[2][0] - mx, cy = first.bary[2][1] - my;
    const double side_a = cx * (ay - my) - cy * (ax - mx);
    const double side_p = cx * (v - my) - cy * (u - mx);
    n = (side_p * side_a >= 0.0) ? nodes_[size_t(n)].child[0] : nodes_[size_t(n)].child[1];
  }
  return n;
}

void ElementTree::setEmission(int n, const glm::dvec3& luminance) {
  const glm::dvec3 flux = luminance * (kPi * nodes_[size_t(n)].area_m2);
  const glm::dvec3 delta = flux - nodes_[size_t(n)].emitted_flux;
  for (int p = n; p >= 0; p = nodes_[size_t(p)].parent) nodes_[size_t(p)].emitted_flux += delta;
}

void ElementTree::splitEmitters(int n) {
  if (!nodes_[size_t(n)].isLeaf()) {
    // A neighbour's conforming split already split this element: its leaves
    // get their own mean emission below.
    const int first = nodes_[size_t(n)].child[0], second = nodes_[size_t(n)].child[1];
    splitEmitters(first);
    splitEmitters(second);
    return;
  }
  // Leaves made by conforming splits carry half their parent's mean; every
  // leaf takes the mean over its own part of the texture.
  setEmission(n, emission_over_(nodes_[size_t(n)].triangle, nodes_[size_t(n)].bary));
  const TreeNode& e = nodes_[size_t(n)];
  if (e.perimeter_m <= settings_.min_perimeter_m) return;
  // Evaluate both halves of a trial split before committing to it.
  const int k = longestEdge(n);
  const float* ba = e.bary[k];
  const float* bb = e.bary[(k + 1) % 3];
  const float* bc = e.bary[(k + 2) % 3];
  const float bm[2] = {0.5f * (ba[0] + bb[0]), 0.5f * (ba[1] + bb[1])};
  const float half0[3][2] = {{ba[0], ba[1]}, {bm[0], bm[1]}, {bc[0], bc[1]}};
  const float half1[3][2] = {{bm[0], bm[1]}, {bb[0], bb[1]}, {bc[0], bc[1]}};
  const glm::dvec3 l0 = emission_over_(e.triangle, half0), l1 = emission_over_(e.triangle, half1);
  const double y0 = luminanceOf(l0), y1 = luminanceOf(l1);
  const double ratio = settings_.emitter_split_ratio;
  if (!(y0 > ratio * y1 || y1 > ratio * y0)) return;
  if (!splitLeaf(n, {})) return;
  // The conforming split may have split neighbours too; they keep halves of
  // their parent's mean until their own turn re-evaluates them.
  setEmission(nodes_[size_t(n)].child[0], l0);
  setEmission(nodes_[size_t(n)].child[1], l1);
  splitEmitters(nodes_[size_t(n)].child[0]);
  splitEmitters(nodes_[size_t(n)].child[1]);
}

namespace {

// Splits elements of differing orientation: 2-means on normals seeded with
// the normal most deviant from the area-weighted mean and the normal
// farthest from it. Leaves `left` or `right` empty when the normals agree
// within `orientation_split_rad` or the 2-means puts all on one side.
void splitByOrientation(const std::vector<TreeNode>& nodes, const std::vector<int>& elements,
                        double orientation_split_rad, std::vector<int>& left,
                        std::vector<int>& right) {
  // Area-weighted mean normal and the widest deviation from it.
  glm::dvec3 mean_normal(0.0);
  for (int e : elements) mean_normal += nodes[size_t(e)].normal * nodes[size_t(e)].area_m2;
  const double mean_length = glm::length(mean_normal);
  const glm::dvec3 axis = mean_length > 0 ? mean_normal / mean_length : glm::dvec3(0, 1, 0);
  int farthest = elements.front();
  double min_cos = 2.0;
  for (int e : elements) {
    const double c = glm::dot(nodes[size_t(e)].normal, axis);
    if (c < min_cos) {
      min_cos = c;
      farthest = e;
    }
  }
  if (!(min_cos < std::cos(orientation_split_rad))) return;
  glm::dvec3 seed0 = nodes[size_t(farthest)].normal, seed1 = seed0;
  double worst = 2.0;
  for (int e : elements) {
    const double c = glm::dot(nodes[size_t(e)].normal, seed0);
    if (c < worst) {
      worst = c;
      seed1 = nodes[size_t(e)].normal;
    }
  }
  for (int iteration = 0; iteration < 4; ++iteration) {
    left.clear();
    right.clear();
    glm::dvec3 sum0(0.0), sum1(0.0);
    for (int e : elements) {
      const glm::dvec3& nrm = nodes[size_t(e)].normal;
      if (glm::dot(nrm, seed0) >= glm::dot(nrm, seed1)) {
        left.push_back(e);
        sum0 += nrm * nodes[size_t(e)].area_m2;
      } else {
        right.push_back(e);
        sum1 += nrm * nodes[size_t(e)].area_m2;
      }
    }
    if (left.empty() || right.empty()) break;
    if (glm::length(sum0) > 0) seed0 = glm::normalize(sum0);
    if (glm::length(sum1) > 0) seed1 = glm::normalize(sum1);
  }
}

// Spatial split along the longest axis of the centroids' bounds: at the
// widest gap when groups are distant (wider than `gap_split_fraction` of
// the extent), else at the median (balance). Sorts `elements` along it.
void splitSpatially(const std::vector<TreeNode>& nodes, std::vector<int>& elements,
                    double gap_split_fraction, std::vector<int>& left, std::vector<int>& right) {
  glm::dvec3 lo(kNoUpperBound), hi(kNoLowerBound);
  for (int e : elements) {
    lo = glm::min(lo, nodes[size_t(e)].centroid);
    hi = glm::max(hi, nodes[size_t(e)].centroid);
  }
  const glm::dvec3 extent = hi - lo;
  const int axis_index =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  std::sort(elements.begin(), elements.end(), [&](int a, int b) {
    const double ca = nodes[size_t(a)].centroid[axis_index],
                 cb = nodes[size_t(b)].centroid[axis_index];
    return ca < cb || (ca == cb && a < b);
  });
  size_t split = elements.size() / 2;
  double widest = 0;
  for (size_t i = 1; i < elements.size(); ++i) {
    const double gap = nodes[size_t(elements[i])].centroid[axis_index] -
                       nodes[size_t(elements[i - 1])].centroid[axis_index];
    if (gap > widest) {
      widest = gap;
      if (gap > gap_split_fraction * extent[axis_index]) split = i;
    }
  }
  left.assign(elements.begin(), elements.begin() + long(split));
  right.assign(elements.begin() + long(split), elements.end());
}

// The cluster over nodes a and b: sums, and area-weighted centroid and normal.
TreeNode clusterOver(const std::vector<TreeNode>& nodes, int a, int b) {
  TreeNode cluster;
  cluster.kind = NodeKind::kCluster;
  cluster.child[0] = a;
  cluster.child[1] = b;
  for (int c : {a, b}) {
    const TreeNode& child = nodes[size_t(c)];
    cluster.area_m2 += child.area_m2;
    cluster.centroid += child.centroid * child.area_m2;
    cluster.normal += child.normal * child.area_m2;
    cluster.reflectance_area += child.reflectance_area;
    cluster.emitted_flux += child.emitted_flux;
  }
  cluster.centroid /= cluster.area_m2;
  cluster.normal /= cluster.area_m2;
  return cluster;
}

}  // namespace

int ElementTree::buildCluster(std::vector<int>& elements, uint16_t depth) {
  if (elements.size() == 1) return elements.front();
  std::vector<int> left, right;
  splitByOrientation(nodes_, elements, settings_.orientation_split_rad, left, right);
  if (left.empty() || right.empty()) {
    left.clear();
    right.clear();
    splitSpatially(nodes_, elements, settings_.gap_split_fraction, left, right);
  }
  const int a = buildCluster(left, uint16_t(depth + 1));
  const int b = buildCluster(right, uint16_t(depth + 1));
  const int index = int(nodes_.size());
  nodes_.push_back(clusterOver(nodes_, a, b));
  nodes_[size_t(a)].parent = index;
  nodes_[size_t(b)].parent = index;
  return index;
}

}  // namespace svit::baker

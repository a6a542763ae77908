// The element tree the shooter refines (element_tree.h): the subdivision
// criterion (thesis 4.3.1), emitter splitting, conforming (T-vertex-free)
// meshes with conserved area, and the cost of propagating a hit down the
// tree. Every tolerance states its derivation; every random input comes
// from a fixed seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <set>
#include <vector>

#include "baker/radiosity_test_util.h"
#include "baker/test_scenes.h"
#include "radiosity/element_tree.h"
#include "scene/numeric.h"
#include "svit/baker/radiosity.h"
#include "util/random.h"

namespace svit::baker {
namespace {

using test::prepare;
using test::roomWithLight;
using test::SceneBuilder;
using test::solvePasses;
using test::spotLight;
using test::Timer;

// Leaves below node `n` (n itself when it is a leaf).
std::vector<int> leavesUnder(const ElementTree& tree, int n) {
  std::vector<int> out, stack{n};
  while (!stack.empty()) {
    const int m = stack.back();
    stack.pop_back();
    if (tree.node(m).isLeaf()) {
      out.push_back(m);
    } else {
      stack.push_back(tree.node(m).child[0]);
      stack.push_back(tree.node(m).child[1]);
    }
  }
  return out;
}

// Every triangle side's element root (front, then back where it exists).
std::vector<int> elementRoots(const ElementTree& tree, size_t triangles) {
  std::vector<int> roots;
  for (size_t t = 0; t < triangles; ++t) {
    for (bool front : {true, false}) {
      const int e = tree.elementRoot(uint32_t(t), front);
      if (e >= 0) roots.push_back(e);
    }
  }
  return roots;
}

// Leaves reachable from the element roots through child links.
std::vector<int> reachableLeaves(const ElementTree& tree, size_t triangles) {
  std::vector<int> leaves;
  for (int root : elementRoots(tree, triangles)) {
    for (int leaf : leavesUnder(tree, root)) leaves.push_back(leaf);
  }
  return leaves;
}

// Nodes whose parent does not list them as a child (lost subtrees).
size_t orphanCount(const ElementTree& tree) {
  size_t orphans = 0;
  for (size_t i = 0; i < tree.nodes().size(); ++i) {
    const TreeNode& n = tree.nodes()[i];
    if (n.parent >= 0 && tree.node(n.parent).child[0] != int(i) &&
        tree.node(n.parent).child[1] != int(i))
      ++orphans;
  }
  return orphans;
}

// T-vertices among `leaves`: a leaf vertex closer than 1e-9 of an edge's
// length to a leaf edge it is not an endpoint of. Brute force over vertices
// x edges with a bounding-box reject; the first few are reported as failures.
size_t countTVertices(const ElementTree& tree, const std::vector<int>& leaves) {
  std::set<uint32_t> vertex_set;
  std::set<uint64_t> edge_set;
  for (int leaf : leaves) {
    const TreeNode& n = tree.node(leaf);
    for (int k = 0; k < 3; ++k) {
      vertex_set.insert(n.vertex[k]);
      edge_set.insert(edgeKey(n.vertex[k], n.vertex[(k + 1) % 3]));
    }
  }
  const std::vector<uint32_t> vertices(vertex_set.begin(), vertex_set.end());
  size_t t_vertices = 0;
  for (uint64_t key : edge_set) {
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
    const glm::dvec3 p = tree.vertexPosition(a), q = tree.vertexPosition(b);
    const glm::dvec3 d = q - p;
    const double length2 = glm::dot(d, d);
    const double tolerance = 1e-9 * std::sqrt(length2);
    const glm::dvec3 lo = glm::min(p, q) - tolerance, hi = glm::max(p, q) + tolerance;
    for (uint32_t v : vertices) {
      if (v == a || v == b) continue;
      const glm::dvec3 x = tree.vertexPosition(v);
      if (x.x < lo.x || x.y < lo.y || x.z < lo.z || x.x > hi.x || x.y > hi.y || x.z > hi.z)
        continue;
      const double s = glm::dot(x - p, d) / length2;
      const glm::dvec3 closest = p + std::clamp(s, 0.0, 1.0) * d;
      if (glm::length(x - closest) < tolerance) {
        if (++t_vertices <= 5) {
          ADD_FAILURE() << "vertex " << v << " (" << x.x << ", " << x.y << ", " << x.z
                        << ") lies on leaf edge " << a << "-" << b << " at s = " << s;
        }
      }
    }
  }
  return t_vertices;
}

// ---------------------------------------------------------------------------
// Subdivision criterion (thesis 4.3.1).

// 4 x 4 m black floor facing up; a narrow spot 1.5 m above (0.6, 0.4).
Scene spotOverFloor() {
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  b.addQuad("floor", {0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}, black);
  b.scene().lights.push_back(spotLight({0.6f, 1.5f, 0.4f}, {0, -1, 0}, 1000.0f, 0.10f, 0.15f));
  return b.scene();
}

TEST(Subdivision, LeavesAreSmallUnderTheSpotAndLargeFarFromIt) {
  Timer timer("Subdivision.LeavesAreSmallUnderTheSpotAndLargeFarFromIt");
  const Scene scene = spotOverFloor();
  RadiositySettings settings;
  settings.min_perimeter_m = 0.1;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 3).ok());
  const ElementTree& tree = solved->solver->tree();
  const SolverStats stats = solved->solver->stats();
  EXPECT_GT(stats.subdivisions, 0u);

  // Footprint of the inner cone: radius 1.5 * tan(0.10) = 0.15 m around (0.6, 0.4).
  double near_area = 0, far_area = 0;
  size_t near_count = 0, far_count = 0;
  const double min_perimeter = tree.settings().min_perimeter_m;
  EXPECT_EQ(min_perimeter, 0.1);
  for (const TreeNode& n : tree.nodes()) {
    if (!n.isLeaf() || n.kind == NodeKind::kCluster) continue;
    // A leaf splits by the criterion only above MIN_PERIMETER, and bisection
    // keeps a child above half its parent (a/2 + b + median > b + c > P/2).
    // Conformity splits neighbours whatever their size; in general that
    // only guarantees > MIN_PERIMETER/3 (a child outgrows the shared edge,
    // >= P/3), but on this mesh of right isosceles leaves the neighbour
    // across a hypotenuse is as large or larger, so every piece keeps
    // >= P/sqrt(2) > MIN_PERIMETER/2.
    if (n.kind == NodeKind::kSubTriangle) {
      EXPECT_GT(n.perimeter_m, 0.5 * min_perimeter);
    }
    const double d = std::hypot(n.centroid.x - 0.6, n.centroid.z - 0.4);
    if (d < 0.15) {
      near_area += n.area_m2;
      ++near_count;
    } else if (d > 2.0) {
      far_area += n.area_m2;
      ++far_count;
    }
  }
  ASSERT_GT(near_count, 0u);
  ASSERT_GT(far_count, 0u);
  const double near_mean = near_area / double(near_count), far_mean = far_area / double(far_count);
  std::printf(
      "subdivision: %zu leaves, %llu splits; near the spot %zu leaves of %.2e m2, far %zu of %.2e "
      "m2\n",
      tree.leafCount(), (unsigned long long)stats.subdivisions, near_count, near_mean, far_count,
      far_mean);
  // The spot's 4096..16384 rays per pass land within its outer footprint
  // (1.5 tan 0.15 = 0.23 m: 0.16 m2), so leaves there split down to
  // MIN_PERIMETER (0.1 m: ~4e-4 m2); the unlit floor splits only for
  // conformity (~1 m2). A factor 20 leaves a wide margin.
  EXPECT_LT(near_mean * 20.0, far_mean);
}

TEST(Subdivision, TinySubdivNeverSplits) {
  Timer timer("Subdivision.TinySubdivNeverSplits");
  const Scene scene = spotOverFloor();
  RadiositySettings settings;
  settings.min_perimeter_m = 0.1;
  settings.first_pass_rays = 4096;
  // dist * hits * SUBDIV <= 5.7 m (the diagonal) * 65,536 hits (a batch)
  // * 1e-9 = 4e-4 m, far below the triangles' 13.7 m perimeters.
  settings.subdiv = 1e-9;
  auto solved = prepare(scene, settings);
  const size_t nodes_before = solved->solver->stats().nodes;
  ASSERT_TRUE(solvePasses(*solved->solver, 3).ok());
  const SolverStats stats = solved->solver->stats();
  EXPECT_EQ(stats.subdivisions, 0u);
  EXPECT_EQ(stats.nodes, nodes_before);
  EXPECT_EQ(stats.leaves, 2u);
  EXPECT_GT(stats.hits, 0u);
}

// ---------------------------------------------------------------------------
// Emitter splitting.

// One emissive triangle facing +y whose longest edge runs along u: the split
// at its midpoint separates u in [0, 0.5] from u in [0.5, 1]. `left` and
// `right` are the sRGB bytes of the 2 x 1 emissive texture's texels.
Scene texturedEmitter(uint8_t left, uint8_t right) {
  SceneBuilder b;
  const int light = b.material({0, 0, 0}, {1, 1, 1});
  // A (0,0,0), C (1,0,1), B (2,0,0): counter-clockwise seen from +y; AB is the
  // longest edge (2 m against sqrt 2), its midpoint (1,0,0) lies below C.
  const int mesh = b.addMesh("emitter", {{0, 0, 0}, {1, 0, 1}, {2, 0, 0}}, light);
  Scene& scene = b.scene();
  // v only gives the UV triangle an area (the texture is one row, clamped),
  // so the mean over each half is sampled over its area, not at one point.
  scene.meshes[size_t(mesh)].uv0 = {{0.0f, 0.0f}, {0.5f, 1.0f}, {1.0f, 0.0f}};
  Texture texture;
  texture.name = "emission";
  texture.width = 2;
  texture.height = 1;
  texture.channels = 3;
  texture.texels = {left, left, left, right, right, right};
  texture.wrap_s = WrapMode::kClampToEdge;
  texture.wrap_t = WrapMode::kClampToEdge;
  scene.textures.push_back(texture);
  scene.materials[size_t(light)].emissive_texture.texture = 0;
  return scene;
}

TEST(EmitterSplitting, HalfWhiteHalfBlackTextureSplitsTheEmitter) {
  Timer timer("EmitterSplitting.HalfWhiteHalfBlackTextureSplitsTheEmitter");
  const Scene scene = texturedEmitter(255, 0);
  RadiositySettings settings;
  settings.min_perimeter_m = 0.5;
  auto solved = prepare(scene, settings);
  const ElementTree& tree = solved->solver->tree();
  const int root = tree.elementRoot(0, true);
  ASSERT_GE(root, 0);
  ASSERT_FALSE(tree.node(root).isLeaf());
  auto luminanceOf = [](const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
  const double y0 = luminanceOf(tree.node(tree.node(root).child[0]).emitted_flux);
  const double y1 = luminanceOf(tree.node(tree.node(root).child[1]).emitted_flux);
  std::printf("emitter split: halves emit %.4f and %.4f lm, %zu leaves\n", y0, y1,
              tree.leafCount());
  // The white texel covers u < 0.25 and fades to black by u = 0.75 (clamped
  // bilinear): the bright half emits several times the dark half.
  const double ratio = settings.emitter_split_ratio;
  EXPECT_TRUE(y0 > ratio * y1 || y1 > ratio * y0);
  // The bright half is the one over u < 0.5: the child holding corner A
  // (u = 0), which is the front element's vertex 0.
  const uint32_t corner_a = tree.node(root).vertex[0];
  const TreeNode& child0 = tree.node(tree.node(root).child[0]);
  const bool child0_has_a =
      child0.vertex[0] == corner_a || child0.vertex[1] == corner_a || child0.vertex[2] == corner_a;
  EXPECT_GT(child0_has_a ? y0 : y1, child0_has_a ? y1 : y0);
  // Flux is conserved through the splits: the root holds its leaves' sum.
  glm::dvec3 leaf_sum(0.0);
  for (int leaf : leavesUnder(tree, root)) leaf_sum += tree.node(leaf).emitted_flux;
  EXPECT_NEAR(leaf_sum.y, tree.node(root).emitted_flux.y, 1e-12 * tree.node(root).emitted_flux.y);
  // And leaves stay above half MIN_PERIMETER, in one conforming tree.
  const std::vector<int> leaves = leavesUnder(tree, root);
  for (int leaf : leaves) EXPECT_GT(tree.node(leaf).perimeter_m, 0.25);
  EXPECT_EQ(leaves.size(), tree.leafCount());
  EXPECT_EQ(orphanCount(tree), 0u);
  EXPECT_EQ(countTVertices(tree, leaves), 0u);
}

TEST(EmitterSplitting, UniformTextureDoesNotSplit) {
  Timer timer("EmitterSplitting.UniformTextureDoesNotSplit");
  const Scene scene = texturedEmitter(255, 255);
  RadiositySettings settings;
  settings.min_perimeter_m = 0.5;
  auto solved = prepare(scene, settings);
  const ElementTree& tree = solved->solver->tree();
  const int root = tree.elementRoot(0, true);
  ASSERT_GE(root, 0);
  EXPECT_TRUE(tree.node(root).isLeaf());
  EXPECT_EQ(tree.nodes().size(), 1u);
  // White sRGB 255 decodes to exactly 1: the flux is pi * L * A = pi * 1 m2.
  EXPECT_NEAR(tree.node(root).emitted_flux.y, kPi * 1.0, 1e-6);
}

// Library bug (reported, not fixed here): ElementTree::splitEmitters calls
// splitLeaf on an element that a neighbour's emitter split has already split
// for conformity. splitLeaf does not check isLeaf(), so the element gets a
// second pair of children: the first pair is orphaned (its parent no longer
// lists it, leafCount() counts it, it stays in the edge map), and the new
// children miss the vertices the neighbour's deeper splits put on their
// shared edge: a T-vertex. Enable once fixed.
//
// Quad a (0,0,0), b (0,0,2), c (2,0,2), d (2,0,0) as triangles 0 = (a, b, c)
// and 1 = (a, c, d), both emissive with a 16 x 1 texture white for u < 0.5.
// Triangle 0 (u = 0, 1, 2 at a, b, c) splits at m = (1,0,1), then its half
// (m, a, b), then (a, (0,0,1), m) at q = (0.5,0,0.5) on the diagonal. Triangle
// 1 (u = 0, 1, 0.5 at a, c, d) was split at m for conformity; its own
// emitter split (halves u < 0.5 and u > 0.5 exactly) splits it again.
TEST(EmitterSplitting, NeighbouringTexturedEmittersStayConforming) {
  SceneBuilder b;
  const int light = b.material({0, 0, 0}, {1, 1, 1});
  const int mesh = b.addQuad("emitter", {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}, light);
  Scene& scene = b.scene();
  // Corners unshared: a, b, c, a, c, d. v only gives the UV triangles an area.
  scene.meshes[size_t(mesh)].uv0 = {{0.0f, 0.0f}, {1.0f, 1.0f}, {2.0f, 0.5f},
                                    {0.0f, 0.0f}, {1.0f, 0.5f}, {0.5f, 1.0f}};
  Texture texture;
  texture.name = "step";
  texture.width = 16;
  texture.height = 1;
  texture.channels = 3;
  for (int i = 0; i < 16; ++i)
    texture.texels.insert(texture.texels.end(), 3, uint8_t(i < 8 ? 255 : 0));
  texture.wrap_s = WrapMode::kClampToEdge;
  texture.wrap_t = WrapMode::kClampToEdge;
  scene.textures.push_back(texture);
  scene.materials[size_t(light)].emissive_texture.texture = 0;
  RadiositySettings settings;
  settings.min_perimeter_m = 1.0;
  auto solved = prepare(scene, settings);
  const ElementTree& tree = solved->solver->tree();
  const std::vector<int> leaves = reachableLeaves(tree, solved->geometry.triangleCount());
  // Today: 17 nodes, leafCount() 9 against 6 reachable leaves, 2 orphans, and
  // q is a T-vertex on triangle 1's leaf edge a-m.
  EXPECT_EQ(orphanCount(tree), 0u);
  EXPECT_EQ(leaves.size(), tree.leafCount());
  EXPECT_EQ(countTVertices(tree, leaves), 0u);
}

// ---------------------------------------------------------------------------
// T-vertex freedom and area conservation after real subdivision.

TEST(Conformity, NoTVerticesAndLeafAreasSumToTheElement) {
  Timer timer("Conformity.NoTVerticesAndLeafAreasSumToTheElement");
  // A light 0.3 m from the -x wall: dense, uneven hits split that wall, and
  // the splits run across its shared edges into the floor, ceiling and walls.
  // A double-sided panel (two elements per triangle sharing vertices) hangs
  // near the light too.
  SceneBuilder builder;
  const int wall = builder.material({0.5f, 0.5f, 0.5f});
  const int panel = builder.material({0.6f, 0.6f, 0.6f}, {0, 0, 0}, true);
  builder.addRoom("room", {0, 0, 0}, {3.0f, 2.5f, 4.0f}, wall);
  builder.addQuad("panel", {0.6f, 0.5f, 1.5f}, {0.6f, 0.5f, 2.5f}, {0.6f, 1.9f, 2.5f},
                  {0.6f, 1.9f, 1.5f}, panel);
  builder.addPointLight({0.3f, 1.2f, 2.0f}, 100.0f);
  const Scene& scene = builder.scene();
  RadiositySettings settings;
  settings.min_perimeter_m = 0.2;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 3).ok());
  const ElementTree& tree = solved->solver->tree();
  const SolverStats stats = solved->solver->stats();
  ASSERT_GT(stats.subdivisions, 20u);

  const std::vector<int> leaves = reachableLeaves(tree, solved->geometry.triangleCount());
  EXPECT_EQ(leaves.size(), tree.leafCount());
  EXPECT_EQ(orphanCount(tree), 0u);
  const size_t t_vertices = countTVertices(tree, leaves);
  std::printf("conformity: %zu leaves, %llu splits, %zu T-vertices\n", leaves.size(),
              (unsigned long long)stats.subdivisions, t_vertices);
  EXPECT_EQ(t_vertices, 0u);

  // Point location: the leaf found for a point of an element contains it
  // (its barycentric corners enclose the point, to float rounding 1e-6).
  Rng rng(hashIds(11, 13));
  for (int root : elementRoots(tree, solved->geometry.triangleCount())) {
    for (int i = 0; i < 20; ++i) {
      double u = rng.uniformDouble(), v = rng.uniformDouble();
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      const TreeNode& leaf = tree.node(tree.locateLeaf(root, u, v));
      const double x0 = leaf.bary[0][0], y0 = leaf.bary[0][1];
      const double x1 = leaf.bary[1][0] - x0, y1 = leaf.bary[1][1] - y0;
      const double x2 = leaf.bary[2][0] - x0, y2 = leaf.bary[2][1] - y0;
      const double det = x1 * y2 - x2 * y1;
      const double b1 = ((u - x0) * y2 - x2 * (v - y0)) / det,
                   b2 = (x1 * (v - y0) - (u - x0) * y1) / det;
      EXPECT_TRUE(b1 >= -1e-6 && b2 >= -1e-6 && b1 + b2 <= 1 + 1e-6)
          << "element " << root << " point (" << u << ", " << v << ") outside its leaf: " << b1
          << ", " << b2;
    }
  }

  // Halving is exact in binary floating point, so the sums are exact up to
  // the rounding of the additions (< 1e-15 per leaf; 1e-9 is generous).
  for (int root : elementRoots(tree, solved->geometry.triangleCount())) {
    double sum = 0;
    for (int leaf : leavesUnder(tree, root)) sum += tree.node(leaf).area_m2;
    EXPECT_NEAR(sum, tree.node(root).area_m2, 1e-9 * tree.node(root).area_m2);
  }
}

// ---------------------------------------------------------------------------
// Hit propagation cost.

TEST(Propagation, VisitsStayWithinTheSumOfDepths) {
  Timer timer("Propagation.VisitsStayWithinTheSumOfDepths");
  const Scene scene = roomWithLight(0.5f, {0.3f, 1.2f, 2.0f}, 100.0f);
  RadiositySettings settings;
  settings.min_perimeter_m = 0.2;
  settings.first_pass_rays = 2048;
  auto solved = prepare(scene, settings);
  uint64_t previous_hit_elements = 0, previous_bound = 0;
  for (uint32_t passes = 1; passes <= 3; ++passes) {
    ASSERT_TRUE(solvePasses(*solved->solver, passes).ok());
    const SolverStats stats = solved->solver->stats();
    size_t max_depth = 0;
    for (const TreeNode& n : solved->solver->tree().nodes())
      max_depth = std::max<size_t>(max_depth, n.depth);
    std::printf(
        "propagation after %u passes: %llu hit leaves, %llu visits, bound %llu, max depth %zu\n",
        passes, (unsigned long long)stats.hit_elements,
        (unsigned long long)stats.propagation_visits, (unsigned long long)stats.propagation_bound,
        max_depth);
    EXPECT_GT(stats.propagation_visits, 0u);
    // Every hit leaf is visited once per batch, and propagation visits each
    // node once at most (a union of root paths).
    EXPECT_GE(stats.propagation_visits, stats.hit_elements);
    EXPECT_LE(stats.propagation_visits, stats.propagation_bound);
    // The bound is a sum of depth + 1 over hit leaves: linear in them, with a
    // slope between 1 and the deepest leaf's depth + 1.
    EXPECT_GE(stats.propagation_bound, stats.hit_elements);
    EXPECT_LE(stats.propagation_bound, stats.hit_elements * (max_depth + 1));
    // What this call added obeys the same slope.
    const uint64_t added_hits = stats.hit_elements - previous_hit_elements;
    const uint64_t added_bound = stats.propagation_bound - previous_bound;
    EXPECT_GT(added_hits, 0u);
    EXPECT_GE(added_bound, added_hits);
    EXPECT_LE(added_bound, added_hits * (max_depth + 1));
    previous_hit_elements = stats.hit_elements;
    previous_bound = stats.propagation_bound;
  }
}

}  // namespace
}  // namespace svit::baker

// The shooter's behaviour beyond the closed forms of radiosity_analytic_test:
// the subdivision criterion, emitter splitting, conforming (T-vertex-free)
// meshes, propagation cost, determinism, the brute-force oracle, degenerate
// input, anytime/resumable solving, the light sources against closed forms,
// interpolation and the honesty of the error estimate. Every tolerance
// states its derivation; every random input comes from a fixed seed.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "element_tree.h"
#include "light_sources.h"
#include "random.h"
#include "svit/baker/radiosity.h"
#include "solver_fixture.h"
#include "test_scenes.h"

namespace svit::baker {
namespace {

using test::SceneBuilder;

constexpr double kPi = 3.14159265358979323846;

// Prints how long a test took (the file should stay under ~40 s on 2 cores).
class Timer {
 public:
  explicit Timer(const char* name) : name_(name), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { std::printf("[timing] %s: %.3f s\n", name_, seconds()); }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

using test::Solved;

std::unique_ptr<Solved> prepare(const Scene& scene, const RadiositySettings& settings, bool brute_force = false) {
  return test::prepareSolver(scene, settings, brute_force);
}

Status solvePasses(RadiositySolver& solver, uint32_t passes) {
  StopRule stop;
  stop.max_passes = passes;
  return solver.improve(stop);
}

// Area-weighted mean luminance of per-triangle values.
double areaMean(const std::vector<Rgb>& values, const BakeGeometry& g) {
  double sum = 0, area = 0;
  for (size_t t = 0; t < values.size(); ++t) {
    sum += double(luminance(values[t])) * g.areas_m2[t];
    area += g.areas_m2[t];
  }
  return sum / area;
}

bool finiteNonNegative(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 && c.b >= 0;
}

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
    if (n.parent >= 0 && tree.node(n.parent).child[0] != int(i) && tree.node(n.parent).child[1] != int(i)) ++orphans;
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
      if (x.x < lo.x || x.y < lo.y || x.z < lo.z || x.x > hi.x || x.y > hi.y || x.z > hi.z) continue;
      const double s = glm::dot(x - p, d) / length2;
      const glm::dvec3 closest = p + std::clamp(s, 0.0, 1.0) * d;
      if (glm::length(x - closest) < tolerance) {
        if (++t_vertices <= 5) {
          ADD_FAILURE() << "vertex " << v << " (" << x.x << ", " << x.y << ", " << x.z << ") lies on leaf edge " << a
                        << "-" << b << " at s = " << s;
        }
      }
    }
  }
  return t_vertices;
}

Light spotLight(Vec3 position, Vec3 direction, float intensity_cd, float inner_rad, float outer_rad) {
  Light light;
  light.name = "spot";
  light.type = LightType::kSpot;
  light.position = position;
  light.direction = direction;
  light.intensity = intensity_cd;
  light.inner_cone_rad = inner_rad;
  light.outer_cone_rad = outer_rad;
  return light;
}

// ---------------------------------------------------------------------------
// 1. Subdivision criterion (thesis 4.3.1).

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
  std::printf("subdivision: %zu leaves, %llu splits; near the spot %zu leaves of %.2e m2, far %zu of %.2e m2\n",
              tree.leafCount(), (unsigned long long)stats.subdivisions, near_count, near_mean, far_count, far_mean);
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
// 2. Emitter splitting.

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
  std::printf("emitter split: halves emit %.4f and %.4f lm, %zu leaves\n", y0, y1, tree.leafCount());
  // The white texel covers u < 0.25 and fades to black by u = 0.75 (clamped
  // bilinear): the bright half emits several times the dark half.
  const double ratio = settings.emitter_split_ratio;
  EXPECT_TRUE(y0 > ratio * y1 || y1 > ratio * y0);
  // The bright half is the one over u < 0.5: the child holding corner A
  // (u = 0), which is the front element's vertex 0.
  const uint32_t corner_a = tree.node(root).vertex[0];
  const TreeNode& child0 = tree.node(tree.node(root).child[0]);
  const bool child0_has_a = child0.vertex[0] == corner_a || child0.vertex[1] == corner_a || child0.vertex[2] == corner_a;
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
  scene.meshes[size_t(mesh)].uv0 = {{0.0f, 0.0f}, {1.0f, 1.0f}, {2.0f, 0.5f}, {0.0f, 0.0f}, {1.0f, 0.5f}, {0.5f, 1.0f}};
  Texture texture;
  texture.name = "step";
  texture.width = 16;
  texture.height = 1;
  texture.channels = 3;
  for (int i = 0; i < 16; ++i) texture.texels.insert(texture.texels.end(), 3, uint8_t(i < 8 ? 255 : 0));
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
// 3. T-vertex freedom and area conservation after real subdivision.

Scene roomWithLight(float albedo, Vec3 light, float intensity_cd, Vec3 hi = {3.0f, 2.5f, 4.0f}) {
  SceneBuilder b;
  const int wall = b.material({albedo, albedo, albedo});
  b.addRoom("room", {0, 0, 0}, hi, wall);
  b.addPointLight(light, intensity_cd);
  return b.scene();
}

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
  builder.addQuad("panel", {0.6f, 0.5f, 1.5f}, {0.6f, 0.5f, 2.5f}, {0.6f, 1.9f, 2.5f}, {0.6f, 1.9f, 1.5f}, panel);
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
      const double b1 = ((u - x0) * y2 - x2 * (v - y0)) / det, b2 = (x1 * (v - y0) - (u - x0) * y1) / det;
      EXPECT_TRUE(b1 >= -1e-6 && b2 >= -1e-6 && b1 + b2 <= 1 + 1e-6)
          << "element " << root << " point (" << u << ", " << v << ") outside its leaf: " << b1 << ", " << b2;
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
// 4. Hit propagation cost.

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
    for (const TreeNode& n : solved->solver->tree().nodes()) max_depth = std::max<size_t>(max_depth, n.depth);
    std::printf("propagation after %u passes: %llu hit leaves, %llu visits, bound %llu, max depth %zu\n", passes,
                (unsigned long long)stats.hit_elements, (unsigned long long)stats.propagation_visits,
                (unsigned long long)stats.propagation_bound, max_depth);
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

// ---------------------------------------------------------------------------
// 5. Determinism across thread counts.

// The room with a red panel 5 cm in front of the +x wall, facing -x.
Scene roomWithRedPanel() {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  const int red = b.material({0.8f, 0.1f, 0.1f});
  b.addRoom("room", {0, 0, 0}, {3.0f, 2.5f, 4.0f}, grey);
  b.addQuad("panel", {2.95f, 0.5f, 1.0f}, {2.95f, 0.5f, 3.0f}, {2.95f, 2.0f, 3.0f}, {2.95f, 2.0f, 1.0f}, red);
  b.addPointLight({1.0f, 1.8f, 1.5f}, 100.0f);
  return b.scene();
}

struct RunResult {
  std::vector<Rgb> irradiance;
  SolverStats stats;
  double estimate = 1;
};

RunResult runRedRoom(int threads, uint64_t seed, std::unique_ptr<Solved>* keep = nullptr) {
  static const Scene scene = roomWithRedPanel();
  RadiositySettings settings;
  settings.seed = seed;
  settings.threads = threads;
  settings.min_perimeter_m = 0.2;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  EXPECT_TRUE(solvePasses(*solved->solver, 3).ok());
  RunResult r{solved->solver->triangleIrradiance(true), solved->solver->stats(),
              solved->solver->estimatedRelativeError()};
  if (keep) *keep = std::move(solved);
  return r;
}

TEST(Determinism, BitIdenticalForOneTwoAndFourThreads) {
  Timer timer("Determinism.BitIdenticalForOneTwoAndFourThreads");
  const RunResult one = runRedRoom(1, 7);
  ASSERT_GT(one.stats.subdivisions, 0u);
  for (int threads : {2, 4}) {
    const RunResult many = runRedRoom(threads, 7);
    ASSERT_EQ(many.irradiance.size(), one.irradiance.size());
    EXPECT_EQ(std::memcmp(many.irradiance.data(), one.irradiance.data(), one.irradiance.size() * sizeof(Rgb)), 0)
        << threads << " threads";
    EXPECT_EQ(many.stats.nodes, one.stats.nodes);
    EXPECT_EQ(many.stats.rays, one.stats.rays);
    EXPECT_EQ(many.stats.hits, one.stats.hits);
    EXPECT_EQ(many.stats.subdivisions, one.stats.subdivisions);
  }
}

TEST(Determinism, AnotherSeedGivesADifferentButCloseAnswer) {
  Timer timer("Determinism.AnotherSeedGivesADifferentButCloseAnswer");
  std::unique_ptr<Solved> keep;
  const RunResult a = runRedRoom(2, 7, &keep);
  const RunResult b = runRedRoom(2, 8);
  ASSERT_EQ(a.irradiance.size(), b.irradiance.size());
  EXPECT_NE(std::memcmp(a.irradiance.data(), b.irradiance.data(), a.irradiance.size() * sizeof(Rgb)), 0);
  // Two independent answers differ by sqrt(2) times one's error; the
  // estimate is meant as that error (1 sigma), so 4 * sqrt(2) * the larger
  // estimate bounds the RMS difference.
  const double difference = keep->solver->relativeErrorAgainst(b.irradiance);
  const double bound = 4.0 * std::sqrt(2.0) * std::max(a.estimate, b.estimate);
  std::printf("seeds 7 and 8: RMS relative difference %.4f, estimates %.4f and %.4f\n", difference, a.estimate,
              b.estimate);
  EXPECT_GT(difference, 0.0);
  EXPECT_LT(difference, bound);
  // The area mean: the direct flux (100 cd * 4 pi, all captured in the
  // closed room) is exact whatever the seed, and the indirect is a mean over
  // ~10^5 bounces; 1% is far outside its noise.
  const double mean_a = areaMean(a.irradiance, keep->geometry), mean_b = areaMean(b.irradiance, keep->geometry);
  EXPECT_NEAR(mean_a, mean_b, 0.01 * mean_a);
}

// ---------------------------------------------------------------------------
// 6. Oracle: Embree against the brute-force caster.

// A closed 2 m room and 60 random double-sided triangles inside it (seeded).
Scene randomScene(uint64_t seed) {
  SceneBuilder b;
  const int wall = b.material({0.5f, 0.5f, 0.5f});
  const int clutter = b.material({0.6f, 0.4f, 0.3f}, {0, 0, 0}, true);
  b.addRoom("room", {0, 0, 0}, {2, 2, 2}, wall);
  Rng rng(hashIds(seed, 0x5eedull));
  std::vector<Vec3> corners;
  for (int t = 0; t < 60; ++t) {
    const double cx = 0.3 + 1.4 * rng.uniformDouble(), cy = 0.3 + 1.4 * rng.uniformDouble(),
                 cz = 0.3 + 1.4 * rng.uniformDouble();
    for (int k = 0; k < 3; ++k) {
      corners.push_back({float(cx + 0.5 * (rng.uniformDouble() - 0.5)), float(cy + 0.5 * (rng.uniformDouble() - 0.5)),
                         float(cz + 0.5 * (rng.uniformDouble() - 0.5))});
    }
  }
  b.addMesh("clutter", corners, clutter);
  b.addPointLight({float(0.2 + 1.6 * rng.uniformDouble()), 1.9f, float(0.2 + 1.6 * rng.uniformDouble())}, 50.0f);
  return b.scene();
}

TEST(Oracle, EmbreeMatchesBruteForceOnRandomScenes) {
  Timer timer("Oracle.EmbreeMatchesBruteForceOnRandomScenes");
  for (uint64_t seed : {1ull, 2ull, 3ull}) {
    const Scene scene = randomScene(seed);
    RadiositySettings settings;
    settings.seed = seed;
    settings.subdiv = 1e-12;  // no subdivision: the leaves are the triangles
    settings.min_hits_per_element = 1;
    settings.first_pass_rays = 2048;
    auto embree = prepare(scene, settings, false);
    auto brute = prepare(scene, settings, true);
    ASSERT_TRUE(solvePasses(*embree->solver, 2).ok());
    ASSERT_TRUE(solvePasses(*brute->solver, 2).ok());
    const SolverStats se = embree->solver->stats(), sb = brute->solver->stats();
    EXPECT_EQ(se.subdivisions, 0u);
    EXPECT_EQ(se.rays, sb.rays) << "seed " << seed;
    EXPECT_EQ(se.hits, sb.hits) << "seed " << seed;
    EXPECT_EQ(se.back_absorbed, sb.back_absorbed) << "seed " << seed;
    size_t mismatches = 0;
    for (bool front : {true, false}) {
      const std::vector<Rgb> a = embree->solver->triangleIrradiance(front);
      const std::vector<Rgb> b = brute->solver->triangleIrradiance(front);
      ASSERT_EQ(a.size(), b.size());
      for (size_t t = 0; t < a.size(); ++t) {
        // Same rays and same hits give the same sums; only float rounding
        // of the reported means can differ.
        const double x = luminance(a[t]), y = luminance(b[t]);
        if (std::abs(x - y) > std::max(1e-3 * std::max(std::abs(x), std::abs(y)), 1e-6)) {
          if (++mismatches <= 5) {
            ADD_FAILURE() << "seed " << seed << " triangle " << t << (front ? " front" : " back") << ": embree " << x
                          << ", brute force " << y;
          }
        }
      }
    }
    std::printf("oracle seed %llu: %llu rays, %llu hits, %zu mismatching triangle sides\n", (unsigned long long)seed,
                (unsigned long long)se.rays, (unsigned long long)se.hits, mismatches);
    EXPECT_EQ(mismatches, 0u) << "seed " << seed;
  }
}

// ---------------------------------------------------------------------------
// 7. Degenerate and sliver input.

TEST(Degenerate, SliversAndNearZeroAreaTrianglesSolveToFiniteValues) {
  Timer timer("Degenerate.SliversAndNearZeroAreaTrianglesSolveToFiniteValues");
  SceneBuilder b;
  const int wall = b.material({0.5f, 0.5f, 0.5f});
  const int thin = b.material({0.7f, 0.7f, 0.7f}, {0, 0, 0}, true);
  b.addRoom("room", {-1, -1, -1}, {1, 1, 1}, wall);
  const Vec3 p0{-0.5f, -0.5f, 0.0f}, p1{0.5f, -0.5f, 0.0f}, p2{0.0f, -0.5f, -0.5f};
  b.addMesh("normal", {p0, p1, p2}, thin);
  // Aspect 1e5: base 1 m, height 1e-5 m, sharing the normal triangle's edge p0-p1.
  b.addMesh("sliver", {p0, p1, {0.0f, -0.5f, 1e-5f}}, thin);
  // Height 5e-7 of its 0.71 m base (2 * area / longest^2 = 5e-7, above
  // import's 1e-7 cut), on edge p1-p2.
  // The apex sits 2.5e-7 * (1, 0, -1) off the edge's midpoint (0.25, -0.5,
  // -0.25): height 3.5e-7 m, about 8 float ulps at 0.25.
  b.addMesh("near zero", {p1, {0.25f + 2.5e-7f, -0.5f, -0.25f - 2.5e-7f}, p2}, thin);
  // An obtuse needle (its apex runs past the base), and one standing up from the floor.
  b.addMesh("needle", {{-0.5f, -0.45f, 0.1f}, {0.9f, -0.45f, 0.1f + 1e-5f}, {0.5f, -0.45f, 0.1f}}, thin);
  b.addMesh("standing", {{0.2f, -1.0f, 0.2f}, {0.2f + 1e-5f, -1.0f, 0.2f}, {0.2f, 0.0f, 0.2f}}, thin);
  // Below import's threshold: skipped at flattening, not solved.
  b.addMesh("flat", {{-0.5f, -0.6f, 0.5f}, {0.5f, -0.6f, 0.5f}, {0.0f, -0.6f, 0.5f + 1e-9f}}, thin);
  b.addPointLight({0.0f, -0.3f, 0.0f}, 20.0f);
  const Scene& scene = b.scene();

  size_t skipped = 0;
  Expected<BakeGeometry> flat = flattenStaticGeometry(scene, &skipped);
  ASSERT_TRUE(flat.ok());
  EXPECT_EQ(skipped, 1u);

  RadiositySettings settings;
  settings.min_perimeter_m = 0.05;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 3).ok());
  const size_t triangles = solved->geometry.triangleCount();
  EXPECT_EQ(triangles, 12u + 5u);
  for (bool front : {true, false}) {
    const std::vector<Rgb> irradiance = solved->solver->triangleIrradiance(front);
    const std::vector<Rgb> radiosity = solved->solver->triangleRadiosity(front);
    for (size_t t = 0; t < triangles; ++t) {
      EXPECT_TRUE(finiteNonNegative(irradiance[t])) << "triangle " << t << " irradiance " << irradiance[t].g;
      EXPECT_TRUE(finiteNonNegative(radiosity[t])) << "triangle " << t << " radiosity " << radiosity[t].g;
    }
  }
  // Interpolated values inside the slivers too (seeded points).
  Rng rng(hashIds(42, 7));
  for (uint32_t t = 12; t < triangles; ++t) {
    for (int i = 0; i < 50; ++i) {
      double u = rng.uniformDouble(), v = rng.uniformDouble();
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      for (InterpolationMode mode : {InterpolationMode::kVertex, InterpolationMode::kElementCentre}) {
        const Rgb value = solved->solver->irradianceAt(t, true, u, v, mode);
        EXPECT_TRUE(finiteNonNegative(value)) << "triangle " << t << " at (" << u << ", " << v << ")";
      }
    }
  }
  const std::vector<Rgb> front = solved->solver->triangleIrradiance(true);
  EXPECT_GT(luminance(front[12]), 0.0f);  // the normal triangle is lit
  std::printf("slivers: %zu leaves, %llu splits\n", solved->solver->tree().leafCount(),
              (unsigned long long)solved->solver->stats().subdivisions);
}

// ---------------------------------------------------------------------------
// 8. Anytime and resumable.

TEST(Anytime, CoarseAnswerAtOnceThenResumes) {
  Timer timer("Anytime.CoarseAnswerAtOnceThenResumes");
  // Closed 3 x 2.5 x 4 m room, albedo 0.5, 100 cd: Phi = 400 pi lm.
  const Scene scene = roomWithLight(0.5f, {1.0f, 1.8f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  StopRule quick;
  quick.max_seconds = 0.001;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(solved->solver->improve(quick).ok());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SolverStats first = solved->solver->stats();
  std::printf("anytime: first call %.4f s, %llu rays, %u passes\n", seconds, (unsigned long long)first.rays,
              first.passes_completed);
  // One 4096-ray batch is a few ms; 0.5 s is slack for a loaded machine.
  EXPECT_LT(seconds, 0.5);
  EXPECT_GT(first.rays, 0u);
  // The coarse answer is the direct light plus the ambient term for what
  // is still unshot: in a closed room of uniform albedo the two add up to
  // the exact area mean Phi / (A (1 - rho)) (flux conservation, exact up
  // to float rounding of the per-triangle means).
  const double rho = double(0.5f);
  const double area = 2.0 * (3.0 * 2.5 + 3.0 * 4.0 + 2.5 * 4.0);
  const double expected_mean = 4.0 * kPi * 100.0 / (area * (1.0 - rho));
  const std::vector<Rgb> coarse = solved->solver->triangleIrradiance(true);
  EXPECT_NEAR(areaMean(coarse, solved->geometry), expected_mean, 1e-4 * expected_mean);
  // ... and not merely the uniform ambient term: the shot batch put the
  // direct light on the walls (the light is 0.7 m from the ceiling, 3.3 m from +x).
  float lowest = 1e30f, highest = 0;
  for (const Rgb& e : coarse) {
    lowest = std::min(lowest, e.g);
    highest = std::max(highest, e.g);
  }
  EXPECT_GT(highest, 1.1f * lowest);
  const size_t points_before = solved->solver->errorSeries().size();
  ASSERT_GE(points_before, 1u);

  StopRule more;
  more.max_seconds = 0.05;
  ASSERT_TRUE(solved->solver->improve(more).ok());
  const SolverStats second = solved->solver->stats();
  EXPECT_GT(second.rays, first.rays);
  EXPECT_GT(second.seconds, first.seconds);
  const std::vector<ErrorPoint>& series = solved->solver->errorSeries();
  EXPECT_GT(series.size(), points_before);
  for (size_t i = 1; i < series.size(); ++i) {
    EXPECT_GE(series[i].t_s, series[i - 1].t_s) << i;
    EXPECT_GE(series[i].rays, series[i - 1].rays) << i;
  }
  EXPECT_GT(series.back().t_s, series[points_before - 1].t_s);
  for (const Rgb& e : solved->solver->triangleIrradiance(true)) EXPECT_TRUE(finiteNonNegative(e));
}

TEST(Anytime, CancelFlagAndProgressCallbackCancel) {
  Timer timer("Anytime.CancelFlagAndProgressCallbackCancel");
  const Scene scene = roomWithLight(0.5f, {1.0f, 1.8f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 1).ok());
  const uint64_t rays = solved->solver->stats().rays;
  const std::vector<Rgb> before = solved->solver->triangleIrradiance(true);

  std::atomic<bool> cancel{true};
  StopRule flagged;
  flagged.cancel = &cancel;
  const Status cancelled = solved->solver->improve(flagged);
  EXPECT_EQ(cancelled.code(), StatusCode::kCancelled);
  EXPECT_NE(cancelled.message().find("cancel"), std::string::npos) << cancelled.message();
  // Cancelled before any batch: nothing changed and the answer stays usable.
  EXPECT_EQ(solved->solver->stats().rays, rays);
  const std::vector<Rgb> after = solved->solver->triangleIrradiance(true);
  EXPECT_EQ(std::memcmp(before.data(), after.data(), before.size() * sizeof(Rgb)), 0);

  // A callback that lets three batches run, then says stop.
  int calls = 0;
  StopRule callback;
  callback.progress = [&calls](const SolverProgress& p) {
    EXPECT_GE(p.rays, 0u);
    return ++calls <= 3;
  };
  const Status stopped = solved->solver->improve(callback);
  EXPECT_EQ(stopped.code(), StatusCode::kCancelled);
  EXPECT_EQ(calls, 4);
  EXPECT_GT(solved->solver->stats().rays, rays);
  for (const Rgb& e : solved->solver->triangleIrradiance(true)) EXPECT_TRUE(finiteNonNegative(e));
}

TEST(Anytime, TargetErrorStopsAfterTwoPassesAtOrBelowTheTarget) {
  Timer timer("Anytime.TargetErrorStopsAfterTwoPassesAtOrBelowTheTarget");
  const Scene scene = roomWithLight(0.5f, {1.0f, 1.8f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  StopRule stop;
  stop.target_est_rel_error = 0.15;
  stop.max_seconds = 20;  // a safety net; the target is reached in well under a second
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const SolverStats stats = solved->solver->stats();
  const double estimate = solved->solver->estimatedRelativeError();
  std::printf("target 0.15: %u passes, %llu rays, %.3f s, estimate %.4f\n", stats.passes_completed,
              (unsigned long long)stats.rays, stats.seconds, estimate);
  EXPECT_GE(stats.passes_completed, 2u);
  EXPECT_LE(estimate, 0.15);
  EXPECT_LT(stats.seconds, 20.0);
}

// ---------------------------------------------------------------------------
// 9. Light sources against closed forms.

TEST(LightSources, PointLightAboveASmallReceiver) {
  Timer timer("LightSources.PointLightAboveASmallReceiver");
  // A 2 cm black receiver 1 mm above a 1 m black floor, a 10 cd point light
  // h = 5 cm above the receiver's centre.
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  b.addQuad("floor", {-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}, black);
  const float a = 0.01f, y = 0.001f;
  b.addQuad("receiver", {-a, y, -a}, {-a, y, a}, {a, y, a}, {a, y, -a}, black);
  const float intensity = 10.0f, light_y = 0.051f;
  b.addPointLight({0, light_y, 0}, intensity);
  RadiositySettings settings;
  settings.subdiv = 1e-12;  // no subdivision: the mean is all we measure
  settings.first_pass_rays = 1u << 22;
  settings.max_batch_rays = 1u << 18;
  auto solved = prepare(b.scene(), settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 1).ok());
  const std::vector<Rgb> irradiance = solved->solver->triangleIrradiance(true);
  const double received = test::receivedFlux(irradiance, solved->geometry.areas_m2, 2, 4);
  const double area = 4.0 * double(a) * double(a);
  const double mean = received / area;
  // E = I cos / d^2 integrates over the receiver to I * (its solid angle),
  // so the mean is I * Omega / A exactly; Omega of a 2a x 2a square at h
  // above its centre is 4 asin(a^2 / (a^2 + h^2)). As a/h -> 0 this is
  // I / h^2; at a/h = 0.2 it is 3.8% lower, so the test compares with the
  // exact mean and reports both.
  const double h = double(light_y) - double(y);
  const double omega = 4.0 * std::asin(double(a) * a / (double(a) * a + h * h));
  const double expected = intensity * omega / area;
  // 2^22 rays, a share f = Omega / 4 pi = 1.22% hits the receiver: 51,400
  // hits, binomial relative std. error sqrt((1 - f) / hits) = 0.44%; 2% is
  // 4.5 sigma.
  std::printf("point light: receiver mean %.2f lx, I*Omega/A %.2f lx, I/h^2 %.2f lx (%.4f%% off the exact mean)\n",
              mean, expected, intensity / (h * h), (mean / expected - 1) * 100);
  EXPECT_NEAR(mean, expected, 0.02 * expected);
  // The floor's irradiance is finite and the receiver's two halves agree.
  EXPECT_NEAR(luminance(irradiance[2]), luminance(irradiance[3]), 0.03 * expected);  // 0.62% each: 3.4 sigma
}

// A 10 x 10 m black plane facing up, alone.
Scene blackPlane() {
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  b.addQuad("plane", {-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, black);
  return b.scene();
}

TEST(LightSources, UniformSkyGivesPiTimesItsLuminance) {
  Timer timer("LightSources.UniformSkyGivesPiTimesItsLuminance");
  Scene scene = blackPlane();
  scene.sky.model = SkyModel::kUniform;
  scene.sky.zenith_luminance = {1000.0f, 1000.0f, 1000.0f};
  RadiositySettings settings;
  settings.subdiv = 1e-12;
  settings.first_pass_rays = 1u << 19;
  settings.max_batch_rays = 1u << 18;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 1).ok());
  const double mean = areaMean(solved->solver->triangleIrradiance(true), solved->geometry);
  const double expected = kPi * 1000.0;
  // Rays leave a disk of radius R = 1.01 * 7.07 m facing each direction; the
  // plane intercepts a share f = 100 cos / (pi R^2) of them, 0.306 averaged
  // over the hemisphere: 2^19 rays give a relative std. error
  // sqrt((1 - f) / (f N)) = 0.21%; 1% is 4.8 sigma.
  std::printf("sky: mean %.2f lx, pi L %.2f lx (%.3f%%)\n", mean, expected, (mean / expected - 1) * 100);
  EXPECT_NEAR(mean, expected, 0.01 * expected);
}

TEST(LightSources, SunAtThirtyDegreesGivesESin30) {
  Timer timer("LightSources.SunAtThirtyDegreesGivesESin30");
  Scene scene = blackPlane();
  scene.sun.enabled = true;
  scene.sun.illuminance_lux = 100000.0f;
  const double elevation = 30.0 * kPi / 180.0;
  scene.sun.direction_to_sun = {float(std::cos(elevation)), float(std::sin(elevation)), 0.0f};
  scene.sun.angular_radius_rad = 0.00465f;
  RadiositySettings settings;
  settings.subdiv = 1e-12;
  settings.first_pass_rays = 1u << 19;
  settings.max_batch_rays = 1u << 18;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 1).ok());
  const double mean = areaMean(solved->solver->triangleIrradiance(true), solved->geometry);
  const double expected = 100000.0 * std::sin(elevation);
  // The plane's shadow on the sun's disk (radius 1.014 R) is a share
  // f = 100 sin 30 / (pi (1.014 R)^2) = 0.30 of it: relative std. error
  // sqrt((1 - f) / (f N)) = 0.21% for 2^19 rays; 1% is 4.8 sigma. The
  // disk's angular radius changes the mean by O(0.00465^2): negligible.
  std::printf("sun: mean %.1f lx, E sin 30 %.1f lx (%.3f%%)\n", mean, expected, (mean / expected - 1) * 100);
  EXPECT_NEAR(mean, expected, 0.01 * expected);
}

TEST(LightSources, SpotFluxMatchesItsFalloffIntegral) {
  Timer timer("LightSources.SpotFluxMatchesItsFalloffIntegral");
  const float inner = 0.2f, outer = 0.4f, intensity = 500.0f;
  const double cos_inner = std::cos(double(inner)), cos_outer = std::cos(double(outer));
  const double expected = intensity * 2.0 * kPi * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 3.0);
  // The closed form is the integral of spotFalloff over the sphere: midpoint
  // rule in cos with 10^6 steps (error O(1e-12) on a piecewise quadratic).
  {
    const int steps = 1000000;
    double integral = 0;
    for (int i = 0; i < steps; ++i) {
      const double mu = -1.0 + (double(i) + 0.5) * 2.0 / steps;
      integral += spotFalloff(mu, cos_inner, cos_outer) * 2.0 / steps;
    }
    EXPECT_NEAR(intensity * 2.0 * kPi * integral, expected, 1e-6 * expected);
    EXPECT_EQ(spotFalloff(cos_inner, cos_inner, cos_outer), 1.0);
    EXPECT_EQ(spotFalloff(cos_outer, cos_inner, cos_outer), 0.0);
    EXPECT_NEAR(spotFalloff(0.5 * (cos_inner + cos_outer), cos_inner, cos_outer), 0.25, 1e-12);
  }
  // A closed black 4 m room around a spot 0.1 m under the ceiling, pointing
  // down: the outer cone meets the floor within 3.9 tan(0.4) = 1.65 m < 2 m.
  SceneBuilder b;
  const int black = b.material({0, 0, 0});
  b.addRoom("room", {-2, -2, -2}, {2, 2, 2}, black);
  b.scene().lights.push_back(spotLight({0, 1.9f, 0}, {0, -1, 0}, intensity, inner, outer));
  RadiositySettings settings;
  settings.subdiv = 1e-12;
  settings.first_pass_rays = 1u << 16;
  auto solved = prepare(b.scene(), settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 1).ok());
  const std::vector<Rgb> irradiance = solved->solver->triangleIrradiance(true);
  const double total = test::receivedFlux(irradiance, solved->geometry.areas_m2);
  const double floor = test::receivedFlux(irradiance, solved->geometry.areas_m2, 0, 2);
  // Every ray hits the closed room and carries Phi / N: the total is exact
  // up to float rounding of the means (1e-6); 0.5% as asked.
  std::printf("spot: received %.3f lm, closed form %.3f lm, floor %.3f lm\n", total, expected, floor);
  EXPECT_NEAR(total, expected, 0.005 * expected);
  // No ray leaves the outer cone: everything lands on the floor.
  EXPECT_NEAR(floor, total, 1e-6 * total);
}

// ---------------------------------------------------------------------------
// 10. Interpolation modes.

TEST(Interpolation, CentreModeAndHardCornersWithoutSubdivision) {
  Timer timer("Interpolation.CentreModeAndHardCornersWithoutSubdivision");
  // Light low and near the -x wall: floor, -x and -z walls see it differently.
  const Scene scene = roomWithLight(0.5f, {0.4f, 0.5f, 1.0f}, 100.0f);
  RadiositySettings settings;
  settings.subdiv = 1e-12;  // leaves are the triangles: their values are the triangle means
  settings.first_pass_rays = 8192;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 2).ok());
  RadiositySolver& solver = *solved->solver;
  solver.prepareQueries();
  const std::vector<Rgb> mean = solver.triangleIrradiance(true);
  const std::vector<float>& area = solved->geometry.areas_m2;
  // Float means against double leaf values: 1e-5 relative is ~100 float ulps.
  for (uint32_t t = 0; t < mean.size(); ++t) {
    const Rgb centre = solver.irradianceAt(t, true, 1.0 / 3.0, 1.0 / 3.0, InterpolationMode::kElementCentre);
    EXPECT_NEAR(centre.g, mean[t].g, 1e-5 * mean[t].g) << "triangle " << t;
    EXPECT_NEAR(centre.r, mean[t].r, 1e-5 * mean[t].r) << "triangle " << t;
  }
  // Corner (0, 0, 0) is corner 0 of floor triangles 0, 1, -x wall 4, 5 and
  // -z wall 8, 9 (addRoom's order). Walls meet at 90 degrees > 30, so each
  // side's vertex value averages its own two triangles only.
  auto side = [&](uint32_t t0, uint32_t t1) {
    return (double(mean[t0].g) * area[t0] + double(mean[t1].g) * area[t1]) / (double(area[t0]) + area[t1]);
  };
  const double floor_side = side(0, 1), x_side = side(4, 5), z_side = side(8, 9);
  const double floor_value = solver.irradianceAt(0, true, 0, 0, InterpolationMode::kVertex).g;
  const double x_value = solver.irradianceAt(4, true, 0, 0, InterpolationMode::kVertex).g;
  const double z_value = solver.irradianceAt(8, true, 0, 0, InterpolationMode::kVertex).g;
  std::printf("corner: floor %.3f (own %.3f), -x %.3f (own %.3f), -z %.3f (own %.3f)\n", floor_value, floor_side,
              x_value, x_side, z_value, z_side);
  EXPECT_NEAR(floor_value, floor_side, 1e-5 * floor_side);
  EXPECT_NEAR(x_value, x_side, 1e-5 * x_side);
  EXPECT_NEAR(z_value, z_side, 1e-5 * z_side);
  // The sides really differ (the light is 0.4 m from -x, 1 m from -z), so
  // averaging across the hard edge would have been visible.
  EXPECT_GT(std::abs(floor_value - x_value), 0.05 * floor_value);
  // The same corner seen from the other floor triangle (1: a, c, d) agrees.
  EXPECT_NEAR(solver.irradianceAt(1, true, 0, 0, InterpolationMode::kVertex).g, floor_value, 1e-6 * floor_value);
}

TEST(Interpolation, VertexModeIsContinuousAcrossTheFloorDiagonal) {
  Timer timer("Interpolation.VertexModeIsContinuousAcrossTheFloorDiagonal");
  const Scene scene = roomWithLight(0.5f, {1.0f, 1.0f, 1.5f}, 100.0f);
  RadiositySettings settings;
  settings.min_perimeter_m = 0.2;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  ASSERT_TRUE(solvePasses(*solved->solver, 2).ok());
  ASSERT_GT(solved->solver->stats().subdivisions, 0u);
  RadiositySolver& solver = *solved->solver;
  solver.prepareQueries();
  // Floor triangles 0 = (a, b, c) and 1 = (a, c, d) share the diagonal a-c:
  // the point a + s (c - a) is (u, v) = (0, s) in 0 and (s, 0) in 1.
  Rng rng(hashIds(3, 14));
  for (int i = 0; i < 200; ++i) {
    const double s = i < 9 ? 0.1 * (i + 1) : rng.uniformDouble();
    const Rgb from0 = solver.irradianceAt(0, true, 0.0, s, InterpolationMode::kVertex);
    const Rgb from1 = solver.irradianceAt(1, true, s, 0.0, InterpolationMode::kVertex);
    ASSERT_TRUE(finiteNonNegative(from0) && finiteNonNegative(from1));
    // Both interpolate the same two vertex values of one conforming leaf
    // edge; they differ by double rounding, then float (6e-8).
    EXPECT_NEAR(from0.g, from1.g, 1e-6 * std::max(from0.g, from1.g)) << "s = " << s;
  }
  // Both modes finite everywhere on every triangle (seeded points).
  for (uint32_t t = 0; t < solved->geometry.triangleCount(); ++t) {
    for (int i = 0; i < 50; ++i) {
      double u = rng.uniformDouble(), v = rng.uniformDouble();
      if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
      }
      EXPECT_TRUE(finiteNonNegative(solver.irradianceAt(t, true, u, v, InterpolationMode::kVertex)));
      EXPECT_TRUE(finiteNonNegative(solver.irradianceAt(t, true, u, v, InterpolationMode::kElementCentre)));
    }
  }
}

// ---------------------------------------------------------------------------
// 11. The error estimate stays honest in a stiff scene.

TEST(Stiffness, EstimateDoesNotClaimConvergenceItDoesNotHave) {
  Timer timer("Stiffness.EstimateDoesNotClaimConvergenceItDoesNotHave");
  // 2 m closed box, albedo 0.999, 10 cd at the centre: the area-mean
  // irradiance is Phi / (A (1 - rho)) exactly (all flux stays in the box
  // and every bounce keeps rho of it).
  const float rho = 0.999f;
  const Scene scene = roomWithLight(rho, {1.0f, 1.0f, 1.0f}, 10.0f, {2.0f, 2.0f, 2.0f});
  RadiositySettings settings;
  settings.first_pass_rays = 4096;
  auto solved = prepare(scene, settings);
  StopRule stop;
  stop.max_seconds = 1.0;
  ASSERT_TRUE(solved->solver->improve(stop).ok());
  const std::vector<Rgb> irradiance = solved->solver->triangleIrradiance(true);
  for (const Rgb& e : irradiance) EXPECT_TRUE(finiteNonNegative(e));
  const double expected = 4.0 * kPi * 10.0 / (24.0 * (1.0 - double(rho)));
  const double mean = areaMean(irradiance, solved->geometry);
  const double true_error = std::abs(mean - expected) / expected;
  // Per-triangle RMS against the (nearly uniform) mean, for the report.
  double rms = 0;
  for (size_t t = 0; t < irradiance.size(); ++t) {
    const double d = (luminance(irradiance[t]) - expected) / expected;
    rms += d * d * solved->geometry.areas_m2[t] / 24.0;
  }
  rms = std::sqrt(rms);
  const double estimate = solved->solver->estimatedRelativeError();
  const SolverStats stats = solved->solver->stats();
  std::printf("stiff box: %u passes, %llu rays, mean %.1f lx vs %.1f lx: true error %.4f (per-triangle RMS %.4f), "
              "estimate %.4f\n",
              stats.passes_completed, (unsigned long long)stats.rays, mean, expected, true_error, rms, estimate);
  EXPECT_TRUE(std::isfinite(estimate));
  EXPECT_LE(estimate, 1.0);
  EXPECT_GE(estimate, 0.5 * true_error);
  // The ambient term makes the area mean exact by construction here (it is
  // Phi/(A(1 - rho)) for the unshot flux), so also hold the estimate to the
  // per-triangle error: the exact answer is uniform to ~0.1% (the direct
  // light is 1 - rho = 0.1% of the total), so the RMS spread against the
  // mean bounds the true per-triangle error from above up to that 0.1%.
  EXPECT_GE(estimate, 0.5 * (rms - 0.001));
}

}  // namespace
}  // namespace svit::baker

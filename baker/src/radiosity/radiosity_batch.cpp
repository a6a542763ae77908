// One batch of progressive Monte Carlo shooting (thesis 4.2-4.3), in stages:
// collectShooters -> allocateRays -> takeShotFlux -> castRays ->
// findInsideOrigins -> binHits -> subdivideDenseLeaves -> sumSubtreeHits ->
// depositHits -> returnInsideFlux. Every stage runs in a fixed order (rays
// by index, nodes by id), so a batch is deterministic for the seed whatever
// the thread count.

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "radiosity_state.h"
#include "scene/glm_interop.h"
#include "util/double_math.h"
#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

enum class ShooterKind : uint8_t { kLight, kEmission, kEnergy };

struct Shooter {
  ShooterKind kind;
  int index;         // light index, or node
  glm::dvec3 rgb;    // flux to shoot before the batch fraction, lm
  glm::dvec3 level;  // kEnergy: the node's unshot irradiance (for choosing leaves)
  double y;          // luminance of rgb
};

struct RayPayload {
  glm::dvec3 flux{0.0};  // lm per channel
  bool from_surface = false;
  int origin_leaf = -1;        // kEnergy: the leaf the ray leaves from
  bool sealed_origin = false;  // kEnergy: from a point no light reaches (light_reach.h)
};

struct BatchHit {
  int element = -1;  // element root (triangle side)
  double u = 0, v = 0;
  glm::dvec3 position{0.0};
  glm::dvec3 flux{0.0};
};

// The batch's shooters and rays: who shoots each ray, what it carries, what
// it hit.
struct BatchRays {
  std::vector<Shooter> shooters;
  size_t count = 0;             // rays
  double fraction = 0;          // share of every shooter's unshot flux this batch shoots
  double ray_y = 0;             // luminous flux per ray, lm
  std::vector<uint32_t> owner;  // per ray: index into shooters
  std::vector<Ray> rays;
  std::vector<RayPayload> payload;
  std::vector<RayHit> hits;
  std::vector<int> hit_leaf;    // per ray: the leaf hit, or -1
  std::vector<uint8_t> inside;  // per ray: 1 when its origin lies inside a solid
};

// The batch's hits, binned per leaf, and the rays that went back to their
// shooters.
struct BinnedHits {
  std::vector<BatchHit> hits;
  // looked up only; order comes from `worklist`
  std::unordered_map<int, std::vector<uint32_t>> per_leaf;
  std::vector<int> worklist;
  std::vector<uint32_t> shooter_rays, returned_rays;  // per shooter
  std::vector<glm::dvec3> returned_flux;              // per shooter, lm
};

// Hits of a subtree: their count and flux.
struct AccumulatedHits {
  uint32_t count = 0;
  glm::dvec3 flux{0.0};
};

struct SubtreeHits {
  std::map<int, AccumulatedHits> accumulated;  // subtree totals, ordered by node id: deterministic
  std::vector<int> tops;                       // object roots holding hits
};

void RadiositySolver::State::runBatch() {
  BatchRays b;
  collectShooters(b);
  double unshot = 0;
  for (const Shooter& sh : b.shooters) unshot += sh.y;
  if (!(unshot > settings.pass_end_rays * ray_flux_y)) {
    endPass();
    return;
  }
  allocateRays(b, unshot);
  takeShotFlux(b.fraction, unshot);
  const auto cast_start = Clock::now();
  castRays(b);
  findInsideOrigins(b);
  stats.cast_seconds += std::chrono::duration<double>(Clock::now() - cast_start).count();
  stats.rays += b.count;
  BinnedHits binned = binHits(b);
  subdivideDenseLeaves(binned);
  SubtreeHits subtrees = sumSubtreeHits(binned);
  depositHits(subtrees);
  returnInsideFlux(b, binned);
  ++batch;
  ++stats.batches;
  ++version;
}

// Shooters in a fixed order: lights, emitting objects, receiving nodes.
void RadiositySolver::State::collectShooters(BatchRays& b) const {
  std::vector<Shooter>& shooters = b.shooters;
  for (size_t i = 0; i < lights.size(); ++i) {
    if (light_unshot[i] > 0) {
      shooters.push_back({ShooterKind::kLight, int(i), lights[i].flux_rgb * light_unshot[i],
                          glm::dvec3(0.0), lights[i].flux_y * light_unshot[i]});
    }
  }
  for (size_t i = 0; i < emitting_roots.size(); ++i) {
    if (emission_unshot[i] > 0) {
      const glm::dvec3 rgb = tree->node(emitting_roots[i]).emitted_flux * emission_unshot[i];
      shooters.push_back({ShooterKind::kEmission, int(i), rgb, glm::dvec3(0.0), luminanceOf(rgb)});
    }
  }
  for (int n : pending) {
    const glm::dvec3 rgb = tree->node(n).reflectance_area * e_unshot[size_t(n)];
    shooters.push_back({ShooterKind::kEnergy, n, rgb, e_unshot[size_t(n)], luminanceOf(rgb)});
  }
}

// Rays of equal luminous flux; a batch shoots fraction f of everything.
// Stratified allocation over the cumulative flux: shooter i gets floor or
// ceil of rays * y_i / U rays, deterministic for the seed.
void RadiositySolver::State::allocateRays(BatchRays& b, double unshot) const {
  const std::vector<Shooter>& shooters = b.shooters;
  const double wanted = std::ceil(unshot / ray_flux_y);
  const size_t rays = size_t(std::min<double>(wanted, settings.max_batch_rays));
  b.count = rays;
  b.fraction = std::min(1.0, double(rays) * ray_flux_y / unshot);
  b.ray_y = b.fraction * unshot / double(rays);
  b.owner.resize(rays);
  Rng offset_rng(hashIds(settings.seed, pass, batch, 0xffffffffull));
  const double offset = offset_rng.uniformDouble();
  size_t s = 0;
  double cumulative_end = shooters[0].y * b.fraction;
  for (size_t j = 0; j < rays; ++j) {
    const double position = (double(j) + offset) * b.ray_y;
    while (position >= cumulative_end && s + 1 < shooters.size()) {
      ++s;
      cumulative_end += shooters[s].y * b.fraction;
    }
    b.owner[j] = uint32_t(s);
  }
}

// What the batch shoots is no longer unshot.
void RadiositySolver::State::takeShotFlux(double fraction, double unshot) {
  for (size_t i = 0; i < lights.size(); ++i) light_unshot[i] *= (1.0 - fraction);
  for (size_t i = 0; i < emitting_roots.size(); ++i) emission_unshot[i] *= (1.0 - fraction);
  if (fraction >= 1.0) {
    for (int n : pending) e_unshot[size_t(n)] = glm::dvec3(0.0);
    pending.clear();
  } else {
    for (int n : pending) e_unshot[size_t(n)] *= (1.0 - fraction);
  }
  shot_pass_y += fraction * unshot;
}

// Ray j of the batch, from its own random stream.
void RadiositySolver::State::generateRay(BatchRays& b, size_t j) const {
  const ElementTree& t = *tree;
  Rng rng(hashIds(settings.seed, pass, batch, j));
  const Shooter& sh = b.shooters[b.owner[j]];
  glm::dvec3 origin, direction, colour;
  bool from_surface = false;
  int origin_leaf = -1;
  bool sealed_origin = false;
  if (sh.kind == ShooterKind::kLight) {
    const LightRay lr = lights[size_t(sh.index)].sample(rng);
    origin = lr.origin;
    direction = lr.direction;
    colour = lr.colour;
  } else {
    // Descend to a leaf with probability proportional to what it emits.
    int n = sh.kind == ShooterKind::kEmission ? emitting_roots[size_t(sh.index)] : sh.index;
    auto weight = [&](int c) {
      const TreeNode& node = t.node(c);
      return sh.kind == ShooterKind::kEmission ? luminanceOf(node.emitted_flux)
                                               : luminanceOf(node.reflectance_area * sh.level);
    };
    while (!t.node(n).isLeaf()) {
      const double w0 = weight(t.node(n).child[0]), w1 = weight(t.node(n).child[1]);
      n = (w0 + w1 > 0 && rng.uniformDouble() * (w0 + w1) >= w0) ? t.node(n).child[1]
                                                                 : t.node(n).child[0];
    }
    const TreeNode& leaf = t.node(n);
    if (sh.kind == ShooterKind::kEnergy) origin_leaf = n;
    const glm::dvec3 leaf_rgb =
        sh.kind == ShooterKind::kEmission ? leaf.emitted_flux : leaf.reflectance_area * sh.level;
    const double leaf_y = luminanceOf(leaf_rgb);
    colour = leaf_y > 0 ? leaf_rgb / leaf_y : glm::dvec3(1.0);
    const glm::dvec2 bary = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
    const glm::dvec3 p = t.pointIn(n, bary.x, bary.y);
    direction = cosineHemisphere(leaf.normal, rng.uniformDouble(), rng.uniformDouble());
    const Vec3 offset = offsetRayOrigin(fromGlm(glm::vec3(p)), fromGlm(glm::vec3(leaf.normal)),
                                        cornerMagnitude(*geometry, leaf.triangle));
    origin = dvec(offset);
    from_surface = true;
    sealed_origin = sh.kind == ShooterKind::kEnergy && !reach.reaches(p, leaf.normal);
  }
  Ray& ray = b.rays[j];
  ray.origin = fromGlm(glm::vec3(origin));
  ray.direction = fromGlm(glm::vec3(direction));
  ray.t_near = 0.0f;
  b.payload[j].flux = colour * b.ray_y;
  b.payload[j].from_surface = from_surface;
  b.payload[j].origin_leaf = origin_leaf;
  b.payload[j].sealed_origin = sealed_origin;
}

// Generate and cast, in parallel over fixed chunks; then locate the leaf
// each ray hit (point location reads the tree only; the tree changes after
// the batch).
void RadiositySolver::State::castRays(BatchRays& b) const {
  const size_t rays = b.count;
  b.rays.resize(rays);
  b.payload.resize(rays);
  b.hits.resize(rays);
  b.hit_leaf.resize(rays);
  const ElementTree& t = *tree;
  parallelFor(rays, 1024, threads, [&](size_t begin, size_t end) {
    for (size_t j = begin; j < end; ++j) generateRay(b, j);
    caster->intersect(std::span<const Ray>(b.rays.data() + begin, end - begin),
                      std::span<RayHit>(b.hits.data() + begin, end - begin));
    for (size_t j = begin; j < end; ++j) {
      const RayHit& h = b.hits[j];
      const int element = h.hit() ? t.elementRoot(h.triangle, h.front) : -1;
      b.hit_leaf[j] = element >= 0 ? t.locateLeaf(element, h.u, h.v) : -1;
    }
  });
}

// Origins inside solids. A node's irradiance applies to all its leaves, so
// energy that arrived on the visible part of the floor is also shot from
// the part a box stands on, into the box's black insides: lost light, ~1% at
// albedo 0.5 and 85% at albedo 0.999, where it is lost again on each of
// ~1000 bounces (tests/stability,
// Stiff.ClosedRoomWithABoxOnTheFloorConservesFluxAtAlbedo0p999). A reflected
// ray that hits the back of a single-sided surface is probed along its
// origin's normal; when the probe meets a back face too, the origin lies
// inside geometry, where no light arrives, and the ray's flux goes back to
// its shooter to leave from elsewhere (returnInsideFlux). A genuine view of
// a back face (its normal probe sees a front face or nothing) is absorbed
// as before: black from behind.
void RadiositySolver::State::findInsideOrigins(BatchRays& b) const {
  const size_t rays = b.count;
  const ElementTree& t = *tree;
  b.inside.assign(rays, 0);
  std::vector<uint32_t> suspects;
  for (size_t j = 0; j < rays; ++j) {
    if (b.payload[j].sealed_origin) {
      b.inside[j] = 1;  // no light reaches its origin: it goes back like one from inside
      continue;
    }
    if (b.payload[j].origin_leaf >= 0 && b.hits[j].hit() &&
        t.elementRoot(b.hits[j].triangle, b.hits[j].front) < 0) {
      suspects.push_back(uint32_t(j));
    }
  }
  if (suspects.empty()) return;
  std::vector<Ray> probes(suspects.size());
  std::vector<RayHit> probe_hits(suspects.size());
  for (size_t k = 0; k < suspects.size(); ++k) {
    probes[k].origin = b.rays[suspects[k]].origin;
    probes[k].direction = fromGlm(glm::vec3(t.node(b.payload[suspects[k]].origin_leaf).normal));
  }
  parallelFor(suspects.size(), 1024, threads, [&](size_t begin, size_t end) {
    caster->intersect(std::span<const Ray>(probes.data() + begin, end - begin),
                      std::span<RayHit>(probe_hits.data() + begin, end - begin));
  });
  for (size_t k = 0; k < suspects.size(); ++k) {
    const RayHit& p = probe_hits[k];
    if (p.hit() && t.elementRoot(p.triangle, p.front) < 0) b.inside[suspects[k]] = 1;
  }
}

// Hits, in ray order (deterministic), binned per leaf; rays from inside
// solids are counted back to their shooters.
BinnedHits RadiositySolver::State::binHits(const BatchRays& b) {
  const size_t rays = b.count;
  const ElementTree& t = *tree;
  BinnedHits out;
  out.hits.reserve(rays);
  out.shooter_rays.assign(b.shooters.size(), 0);
  out.returned_rays.assign(b.shooters.size(), 0);
  out.returned_flux.assign(b.shooters.size(), glm::dvec3(0.0));
  for (size_t j = 0; j < rays; ++j) {
    ++out.shooter_rays[b.owner[j]];
    if (b.inside[j]) {
      ++stats.inside_origin_rays;
      ++out.returned_rays[b.owner[j]];
      out.returned_flux[b.owner[j]] += b.payload[j].flux;
      continue;
    }
    if (b.payload[j].from_surface) ++surface_rays;
    const RayHit& h = b.hits[j];
    if (!h.hit()) continue;
    if (b.payload[j].from_surface) ++surface_hits;
    const int element = t.elementRoot(h.triangle, h.front);
    if (element < 0) {
      ++stats.back_absorbed;  // the black back of a single-sided surface
      continue;
    }
    ++stats.hits;
    BatchHit bh;
    bh.element = element;
    bh.u = h.u;
    bh.v = h.v;
    const size_t tri = h.triangle;
    const glm::dvec3 c0 = dvec(geometry->corner(tri, 0));
    bh.position = c0 + double(h.u) * (dvec(geometry->corner(tri, 1)) - c0) +
                  double(h.v) * (dvec(geometry->corner(tri, 2)) - c0);
    bh.flux = b.payload[j].flux;
    const int leaf = b.hit_leaf[j];
    auto [it, inserted] = out.per_leaf.try_emplace(leaf);
    if (inserted) out.worklist.push_back(leaf);
    it->second.push_back(uint32_t(out.hits.size()));
    out.hits.push_back(bh);
  }
  return out;
}

// Dense, uneven hits subdivide their receiver (thesis 4.3.1); hits of every
// split leaf (criterion or conformity) move to the children.
void RadiositySolver::State::subdivideDenseLeaves(BinnedHits& binned) {
  std::vector<int>& worklist = binned.worklist;
  auto& per_leaf = binned.per_leaf;
  std::sort(worklist.begin(), worklist.end());
  const auto on_split = [&](int split) {
    auto it = per_leaf.find(split);
    ++stats.subdivisions;
    if (it == per_leaf.end()) return;
    std::vector<uint32_t> moved = std::move(it->second);
    per_leaf.erase(it);
    for (uint32_t index : moved) {
      const BatchHit& bh = binned.hits[index];
      const int child = tree->locateLeaf(split, bh.u, bh.v);
      auto [cit, inserted] = per_leaf.try_emplace(child);
      if (inserted) worklist.push_back(child);
      cit->second.push_back(index);
    }
  };
  for (size_t w = 0; w < worklist.size(); ++w) {
    const int leaf = worklist[size_t(w)];
    auto it = per_leaf.find(leaf);
    if (it == per_leaf.end() || !tree->node(leaf).isLeaf()) continue;
    const std::vector<uint32_t>& list = it->second;
    glm::dvec3 mean(0.0);
    for (uint32_t index : list) mean += binned.hits[index].position;
    mean /= double(list.size());
    const TreeNode& node = tree->node(leaf);
    const double spread = glm::length(node.centroid - mean) * double(list.size()) * settings.subdiv;
    if (spread > node.perimeter_m && node.perimeter_m > settings.min_perimeter_m) {
      // on_split moves the hits and queues the children that got some.
      if (tree->subdivide(leaf, on_split)) {
        subdivided.push_back(leaf);
        growNodeArrays();
      }
    }
  }
}

// Every node learns its subtree's hits, bottom-up, each node once:
// O(hit leaves + ancestors).
SubtreeHits RadiositySolver::State::sumSubtreeHits(const BinnedHits& binned) {
  SubtreeHits out;
  std::map<int, AccumulatedHits>& accumulated = out.accumulated;
  size_t max_depth = 0;
  for (const auto& [leaf, list] : binned.per_leaf) {
    if (list.empty()) continue;
    AccumulatedHits a;
    for (uint32_t index : list) a.flux += binned.hits[index].flux;
    a.count = uint32_t(list.size());
    accumulated[leaf] = a;
    max_depth = std::max<size_t>(max_depth, tree->node(leaf).depth);
    ++stats.hit_elements;
    stats.propagation_bound += tree->node(leaf).depth + 1u;
  }
  std::vector<std::vector<int>> by_depth(max_depth + 1);
  for (const auto& [node, a] : accumulated) by_depth[tree->node(node).depth].push_back(node);
  for (size_t d = by_depth.size(); d-- > 0;) {
    std::sort(by_depth[d].begin(), by_depth[d].end());
    for (int n : by_depth[d]) {
      ++stats.propagation_visits;
      const TreeNode& node = tree->node(n);
      if (node.parent < 0) {
        out.tops.push_back(n);
        continue;
      }
      const AccumulatedHits a = accumulated[n];
      auto [pit, inserted] = accumulated.try_emplace(node.parent);
      if (inserted) by_depth[d - 1].push_back(node.parent);
      pit->second.count += a.count;
      pit->second.flux += a.flux;
    }
  }
  return out;
}

// Sparse hits spread over clusters (thesis 4.3). From the top, a node hands
// its hits down to its children only when its larger child expects at least
// min_hits_per_element of them by area, and otherwise deposits all of them
// at its own level, whose irradiance spreads over its leaves in proportion
// to their areas. The decision reads the node's count, never how the hits
// split between the children. Deciding per child from its own realised
// count (keep it when >= min, else hand it up) is biased: a small child
// hands up most of its flux and gets back only its area share of the pool
// while its larger sibling keeps its own, and with small batches (stiff
// scenes shoot ~1000 generations of a few hundred rays) that never averages
// out: the faces of a box in an albedo-0.999 room come out 0.5 to 1.5 times
// their true irradiance that way (tests/stability, Stiff.EstimatedErrorIsNeverBelow...).
void RadiositySolver::State::depositHits(SubtreeHits& subtrees) {
  std::map<int, AccumulatedHits>& accumulated = subtrees.accumulated;
  std::vector<int>& tops = subtrees.tops;
  std::sort(tops.begin(), tops.end());
  std::vector<int> stack(tops.rbegin(), tops.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    const TreeNode& node = tree->node(n);
    const AccumulatedHits& a = accumulated[n];
    if (!node.isLeaf()) {
      const double larger_m2 =
          std::max(tree->node(node.child[0]).area_m2, tree->node(node.child[1]).area_m2);
      if (double(a.count) * larger_m2 >= double(settings.min_hits_per_element) * node.area_m2) {
        for (int c : {node.child[1], node.child[0]}) {
          if (accumulated.count(c)) stack.push_back(c);
        }
        continue;
      }
    }
    // Deposit: irradiance at this level; reflected later if anything reflects.
    const glm::dvec3 irradiance = a.flux / node.area_m2;
    e_pass[size_t(n)] += irradiance;
    if (luminanceOf(node.reflectance_area) > 0) {
      e_unshot[size_t(n)] += irradiance;
      pending.insert(n);
    }
  }
}

// Flux of rays that started inside solids goes back to its shooter, as
// unshot reflected flux. A shooter all of whose rays came back may be hidden
// as a whole: it hands the flux to its parent, so no pass can loop on it; an
// object root absorbs it once at least kHiddenEvidenceRays rays all came
// back (a wholly buried object), and keeps it while fewer did (a pass ends
// anyway once the unshot flux is below pass_end_rays rays, and a root
// holding more gets that many).
void RadiositySolver::State::returnInsideFlux(const BatchRays& b, const BinnedHits& binned) {
  constexpr uint32_t kHiddenEvidenceRays = 8;
  for (size_t i = 0; i < b.shooters.size(); ++i) {
    if (binned.returned_rays[i] == 0) continue;
    int n = b.shooters[i].index;
    if (binned.returned_rays[i] == binned.shooter_rays[i]) {
      const int parent = tree->node(n).parent;
      if (parent >= 0) {
        n = parent;
      } else if (binned.returned_rays[i] >= kHiddenEvidenceRays) {
        stats.back_absorbed += binned.returned_rays[i];
        continue;
      }
    }
    const glm::dvec3& reflectance_area = tree->node(n).reflectance_area;
    glm::dvec3 level(0.0);
    for (int c = 0; c < 3; ++c)
      level[c] = reflectance_area[c] > 0 ? binned.returned_flux[i][c] / reflectance_area[c] : 0.0;
    e_unshot[size_t(n)] += level;
    pending.insert(n);
  }
}

}  // namespace svit::baker

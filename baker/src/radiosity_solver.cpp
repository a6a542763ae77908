// Progressive Monte Carlo shooting (thesis 4.2-4.3): every batch shoots the
// unshot flux of lights, emitters and receiving nodes with rays of equal
// luminous flux, allocated by importance (stratified over the shooters'
// cumulative flux). After a batch, dense uneven hits subdivide their
// receivers, sparse hits propagate up to clusters, and the rest is deposited
// where it rests. A pass ends when little flux is left; the remainder is
// compensated as ambient light (thesis 5.5). Passes repeat with more rays
// and are averaged; their spread is the error estimate.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "double_math.h"
#include "parallel_for.h"
#include "radiosity_state.h"
#include "random.h"
#include "sampling.h"
#include "texture_sampling.h"
#include "glm_interop.h"

namespace svit::baker {
namespace {

using Clock = std::chrono::steady_clock;

enum class ShooterKind : uint8_t { kLight, kEmission, kEnergy };

struct Shooter {
  ShooterKind kind;
  int index;           // light index, or node
  glm::dvec3 rgb;      // flux to shoot before the batch fraction, lm
  glm::dvec3 level;    // kEnergy: the node's unshot irradiance (for choosing leaves)
  double y;            // luminance of rgb
};

struct RayPayload {
  glm::dvec3 flux{0.0};  // lm per channel
  bool from_surface = false;
  int origin_leaf = -1;  // kEnergy: the leaf the ray leaves from
};

struct BatchHit {
  int element = -1;  // element root (triangle side)
  double u = 0, v = 0;
  glm::dvec3 position{0.0};
  glm::dvec3 flux{0.0};
};

// Emission of original triangle `t` over a sub-triangle, from the material's
// emissive texture (for splitting textured emitters).
EmissionOver makeEmissionOver(const Scene& scene, const BakeGeometry& geometry) {
  return [&scene, &geometry](uint32_t t, const float (&bary)[3][2]) -> glm::dvec3 {
    const Instance& instance = scene.instances[geometry.instance[t]];
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    const uint32_t mt = geometry.mesh_triangle[t];
    const Material& material = scene.materials[mesh.triangle_material[mt]];
    const Rgb& factor = material.emissive_luminance;
    const TextureRef& ref = material.emissive_texture;
    const std::vector<Vec2>& uvs = ref.texcoord == 1 ? mesh.uv1 : mesh.uv0;
    if (ref.texture < 0 || uvs.empty()) return {factor.r, factor.g, factor.b};
    Vec2 corner_uv[3];
    for (int k = 0; k < 3; ++k) {
      // Sub-triangle corner in the original triangle's UVs.
      const Vec2 a = uvs[mesh.indices[mt * 3]], b = uvs[mesh.indices[mt * 3 + 1]], c = uvs[mesh.indices[mt * 3 + 2]];
      const float u = bary[k][0], v = bary[k][1];
      corner_uv[k] = transformUv(ref, {a.x + u * (b.x - a.x) + v * (c.x - a.x), a.y + u * (b.y - a.y) + v * (c.y - a.y)});
    }
    const Rgb mean = meanOverTriangle(scene.textures[size_t(ref.texture)], corner_uv[0], corner_uv[1], corner_uv[2], true);
    return {factor.r * mean.r, factor.g * mean.g, factor.b * mean.b};
  };
}

}  // namespace

RadiositySolver::RadiositySolver() : state_(std::make_unique<State>()) {}
RadiositySolver::~RadiositySolver() = default;

Expected<std::unique_ptr<RadiositySolver>> RadiositySolver::create(const Scene& scene, const BakeGeometry& geometry,
                                                                   const RayCaster& caster,
                                                                   const RadiositySettings& settings) {
  if (!(settings.subdiv > 0) || !(settings.min_perimeter_m >= 0) || settings.first_pass_rays == 0 ||
      !(settings.pass_growth >= 1.0) || settings.max_batch_rays == 0 || !(settings.pass_end_rays >= 1.0) ||
      !(settings.emitter_split_ratio > 1.0) || settings.min_hits_per_element == 0 || settings.threads < 0) {
    return Status(StatusCode::kInvalidInput, "radiosity settings: out of range (subdiv > 0, min_perimeter_m >= 0, "
                                             "first_pass_rays > 0, pass_growth >= 1, max_batch_rays > 0, "
                                             "pass_end_rays >= 1, emitter_split_ratio > 1, "
                                             "min_hits_per_element > 0, threads >= 0)");
  }
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    const Rgb& a = geometry.albedo[t];
    const Rgb& e = geometry.emission[t];
    const bool albedo_ok = a.r >= 0 && a.r <= 1 && a.g >= 0 && a.g <= 1 && a.b >= 0 && a.b <= 1;
    const bool emission_ok = std::isfinite(e.r) && std::isfinite(e.g) && std::isfinite(e.b) && e.r >= 0 &&
                             e.g >= 0 && e.b >= 0;
    if (!albedo_ok || !emission_ok) {
      // Name the element as the file does: mesh, primitive, triangle, material.
      std::string where = scene.source_path + ": triangle " + std::to_string(t);
      if (geometry.instance[t] < scene.instances.size()) {
        const Mesh& mesh = scene.meshes[size_t(scene.instances[geometry.instance[t]].mesh)];
        const uint32_t mt = geometry.mesh_triangle[t];
        where = scene.source_path + ": mesh '" + mesh.name + "'";
        if (mt < mesh.triangle_source.size()) {
          where += " primitive " + std::to_string(mesh.triangle_source[mt].primitive) + " triangle " +
                   std::to_string(mesh.triangle_source[mt].triangle);
        }
        if (mt < mesh.triangle_material.size() && mesh.triangle_material[mt] < scene.materials.size()) {
          where += " (material '" + scene.materials[mesh.triangle_material[mt]].name + "')";
        }
      }
      char values[160];
      if (!emission_ok) {
        std::snprintf(values, sizeof values, "emitted luminance (%g, %g, %g) cd/m2 must be finite and >= 0",
                      double(e.r), double(e.g), double(e.b));
      } else {
        std::snprintf(values, sizeof values, "albedo (%g, %g, %g) must be in [0, 1]", double(a.r), double(a.g),
                      double(a.b));
      }
      return Status(StatusCode::kInvalidInput, where + ": " + values);
    }
  }
  std::unique_ptr<RadiositySolver> solver(new RadiositySolver());
  State& s = *solver->state_;
  s.scene = &scene;
  s.geometry = &geometry;
  s.caster = &caster;
  s.settings = settings;
  s.threads = resolveThreads(settings.threads);
  TreeSettings tree_settings;
  const double diagonal = glm::length(dvec(geometry.bounds.max) - dvec(geometry.bounds.min));
  tree_settings.min_perimeter_m = settings.min_perimeter_m > 0 ? settings.min_perimeter_m : 0.02 * diagonal;
  s.settings.min_perimeter_m = tree_settings.min_perimeter_m;
  tree_settings.emitter_split_ratio = settings.emitter_split_ratio;
  s.tree = std::make_unique<ElementTree>(geometry, tree_settings, makeEmissionOver(scene, geometry));
  Expected<std::vector<LightSource>> lights = makeLightSources(scene, geometry);
  if (!lights.ok()) return lights.status();
  s.lights = std::move(lights).value();

  for (const LightSource& light : s.lights) s.emitted_y += light.flux_y;
  glm::dvec3 reflectance(0.0);
  for (int root : s.tree->objectRoots()) {
    const TreeNode& n = s.tree->node(root);
    if (luminanceOf(n.emitted_flux) > 0) {
      s.emitting_roots.push_back(root);
      s.emitted_y += luminanceOf(n.emitted_flux);
    }
    reflectance += n.reflectance_area;
    s.total_area_m2 += n.area_m2;
  }
  s.mean_albedo = s.total_area_m2 > 0 ? reflectance / s.total_area_m2 : glm::dvec3(0.0);
  s.element_s1.assign(geometry.triangleCount() * 2, 0.0);
  s.element_s2.assign(geometry.triangleCount() * 2, 0.0);
  s.stats.elements = 0;
  for (size_t t = 0; t < geometry.triangleCount(); ++t) s.stats.elements += geometry.double_sided[t] ? 2 : 1;
  s.growNodeArrays();
  return solver;
}

void RadiositySolver::State::growNodeArrays() {
  const size_t n = tree->nodes().size();
  e_pass.resize(n, glm::dvec3(0.0));
  e_unshot.resize(n, glm::dvec3(0.0));
  e_sum.resize(n, glm::dvec3(0.0));
}

void RadiositySolver::State::startPass() {
  std::fill(e_pass.begin(), e_pass.end(), glm::dvec3(0.0));
  std::fill(e_unshot.begin(), e_unshot.end(), glm::dvec3(0.0));
  pending.clear();
  light_unshot.assign(lights.size(), 1.0);
  emission_unshot.assign(emitting_roots.size(), 1.0);
  pass_rays = double(settings.first_pass_rays) * std::pow(settings.pass_growth, double(pass));
  ray_flux_y = emitted_y / pass_rays;
  shot_pass_y = 0;
  batch = 0;
  started = true;
  ++version;
}

double RadiositySolver::State::unshotY() const {
  double u = 0;
  for (size_t i = 0; i < lights.size(); ++i) u += lights[i].flux_y * light_unshot[i];
  for (size_t i = 0; i < emitting_roots.size(); ++i) {
    u += luminanceOf(tree->node(emitting_roots[i]).emitted_flux) * emission_unshot[i];
  }
  for (int n : pending) u += luminanceOf(tree->node(n).reflectance_area * e_unshot[size_t(n)]);
  return u;
}

glm::dvec3 RadiositySolver::State::currentAmbient() const {
  // Unshot flux U would reach surfaces as U*c, reflect rho*c of it and so
  // on: U*c / (1 - rho*c) in all, spread over every surface (thesis 5.5).
  // c, the share of surface rays that hit the scene, keeps open scenes
  // (sun and sky leaving through windows) from being over-compensated.
  glm::dvec3 unshot(0.0);
  for (size_t i = 0; i < lights.size(); ++i) unshot += lights[i].flux_rgb * light_unshot[i];
  for (size_t i = 0; i < emitting_roots.size(); ++i) unshot += tree->node(emitting_roots[i]).emitted_flux * emission_unshot[i];
  for (int n : pending) unshot += tree->node(n).reflectance_area * e_unshot[size_t(n)];
  const double captured = surface_rays > 0 ? double(surface_hits) / double(surface_rays) : 1.0;
  glm::dvec3 ambient(0.0);
  for (int c = 0; c < 3; ++c) {
    // Albedo 1 in a closed scene has no finite answer; 1e-3 caps the
    // amplification at 1000 rather than dividing by zero.
    const double denominator = std::max(1e-3, 1.0 - mean_albedo[c] * captured);
    ambient[c] = total_area_m2 > 0 ? unshot[c] * captured / (total_area_m2 * denominator) : 0.0;
  }
  return ambient;
}

void RadiositySolver::State::endPass() {
  const glm::dvec3 ambient = currentAmbient();
  const double weight = pass_rays;
  for (size_t n = 0; n < e_sum.size(); ++n) e_sum[n] += weight * e_pass[n];
  ambient_sum += weight * ambient;
  weight_sum += weight;
  const std::vector<glm::dvec3> means = elementMeans(e_pass, ambient);
  for (size_t e = 0; e < means.size(); ++e) {
    const double x = luminanceOf(means[e]);
    element_s1[e] += weight * x;
    element_s2[e] += weight * x * x;
  }
  ++stats.passes_completed;
  ++pass;
  startPass();
}

void RadiositySolver::State::runBatch() {
  // 1. Shooters in a fixed order: lights, emitting objects, receiving nodes.
  std::vector<Shooter> shooters;
  for (size_t i = 0; i < lights.size(); ++i) {
    if (light_unshot[i] > 0) {
      shooters.push_back({ShooterKind::kLight, int(i), lights[i].flux_rgb * light_unshot[i], glm::dvec3(0.0),
                          lights[i].flux_y * light_unshot[i]});
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
  double unshot = 0;
  for (const Shooter& sh : shooters) unshot += sh.y;
  if (!(unshot > settings.pass_end_rays * ray_flux_y)) {
    endPass();
    return;
  }
  // 2. Rays of equal luminous flux; a batch shoots fraction f of everything.
  const double wanted = std::ceil(unshot / ray_flux_y);
  const size_t rays = size_t(std::min<double>(wanted, settings.max_batch_rays));
  const double fraction = std::min(1.0, double(rays) * ray_flux_y / unshot);
  const double ray_y = fraction * unshot / double(rays);
  // Stratified allocation over the cumulative flux: shooter i gets
  // floor or ceil of rays * y_i / U rays, deterministic for the seed.
  std::vector<uint32_t> owner(rays);
  {
    Rng offset_rng(hashIds(settings.seed, pass, batch, 0xffffffffull));
    const double offset = offset_rng.uniformDouble();
    size_t s = 0;
    double cumulative_end = shooters[0].y * fraction;
    for (size_t j = 0; j < rays; ++j) {
      const double position = (double(j) + offset) * ray_y;
      while (position >= cumulative_end && s + 1 < shooters.size()) {
        ++s;
        cumulative_end += shooters[s].y * fraction;
      }
      owner[j] = uint32_t(s);
    }
  }
  for (size_t i = 0; i < lights.size(); ++i) light_unshot[i] *= (1.0 - fraction);
  for (size_t i = 0; i < emitting_roots.size(); ++i) emission_unshot[i] *= (1.0 - fraction);
  if (fraction >= 1.0) {
    for (int n : pending) e_unshot[size_t(n)] = glm::dvec3(0.0);
    pending.clear();
  } else {
    for (int n : pending) e_unshot[size_t(n)] *= (1.0 - fraction);
  }
  shot_pass_y += fraction * unshot;

  // 3. Generate and cast, in parallel over fixed chunks.
  std::vector<Ray> batch_rays(rays);
  std::vector<RayPayload> payload(rays);
  std::vector<RayHit> hits(rays);
  std::vector<int> hit_leaf(rays);
  const ElementTree& t = *tree;
  const auto generate = [&](size_t begin, size_t end) {
    for (size_t j = begin; j < end; ++j) {
      Rng rng(hashIds(settings.seed, pass, batch, j));
      const Shooter& sh = shooters[owner[j]];
      glm::dvec3 origin, direction, colour;
      bool from_surface = false;
      int origin_leaf = -1;
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
          n = (w0 + w1 > 0 && rng.uniformDouble() * (w0 + w1) >= w0) ? t.node(n).child[1] : t.node(n).child[0];
        }
        const TreeNode& leaf = t.node(n);
        if (sh.kind == ShooterKind::kEnergy) origin_leaf = n;
        const glm::dvec3 leaf_rgb =
            sh.kind == ShooterKind::kEmission ? leaf.emitted_flux : leaf.reflectance_area * sh.level;
        const double leaf_y = luminanceOf(leaf_rgb);
        colour = leaf_y > 0 ? leaf_rgb / leaf_y : glm::dvec3(1.0);
        const glm::dvec2 b = uniformTriangle(rng.uniformDouble(), rng.uniformDouble());
        const glm::dvec3 p = t.pointIn(n, b.x, b.y);
        direction = cosineHemisphere(leaf.normal, rng.uniformDouble(), rng.uniformDouble());
        const Vec3 offset = offsetRayOrigin(fromGlm(glm::vec3(p)), fromGlm(glm::vec3(leaf.normal)),
                                            cornerMagnitude(*geometry, leaf.triangle));
        origin = dvec(offset);
        from_surface = true;
      }
      Ray& ray = batch_rays[j];
      ray.origin = fromGlm(glm::vec3(origin));
      ray.direction = fromGlm(glm::vec3(direction));
      ray.t_near = 0.0f;
      payload[j].flux = colour * ray_y;
      payload[j].from_surface = from_surface;
      payload[j].origin_leaf = origin_leaf;
    }
    caster->intersect(std::span<const Ray>(batch_rays.data() + begin, end - begin),
                      std::span<RayHit>(hits.data() + begin, end - begin));
    // Point location reads the tree only; the tree changes after the batch.
    for (size_t j = begin; j < end; ++j) {
      const RayHit& h = hits[j];
      const int element = h.hit() ? t.elementRoot(h.triangle, h.front) : -1;
      hit_leaf[j] = element >= 0 ? t.locateLeaf(element, h.u, h.v) : -1;
    }
  };
  const auto cast_start = Clock::now();
  parallelFor(rays, 1024, threads, generate);

  // 3b. Origins inside solids. A node's irradiance applies to all its
  // leaves, so energy that arrived on the visible part of the floor is also
  // shot from the part a box stands on, into the box's black insides: lost
  // light, ~1% at albedo 0.5 and 85% at albedo 0.999, where it is lost
  // again on each of ~1000 bounces (tests/stability,
  // Stiff.ClosedRoomWithABoxOnTheFloorConservesFluxAtAlbedo0p999). A reflected ray
  // that hits the back of a single-sided surface is probed along its
  // origin's normal; when the probe meets a back face too, the origin lies
  // inside geometry, where no light arrives, and the ray's flux goes back
  // to its shooter to leave from elsewhere (step 7). A genuine view of a
  // back face (its normal probe sees a front face or nothing) is absorbed
  // as before: black from behind.
  std::vector<uint8_t> inside(rays, 0);
  {
    std::vector<uint32_t> suspects;
    for (size_t j = 0; j < rays; ++j) {
      if (payload[j].origin_leaf >= 0 && hits[j].hit() && t.elementRoot(hits[j].triangle, hits[j].front) < 0) {
        suspects.push_back(uint32_t(j));
      }
    }
    if (!suspects.empty()) {
      std::vector<Ray> probes(suspects.size());
      std::vector<RayHit> probe_hits(suspects.size());
      for (size_t k = 0; k < suspects.size(); ++k) {
        probes[k].origin = batch_rays[suspects[k]].origin;
        probes[k].direction = fromGlm(glm::vec3(t.node(payload[suspects[k]].origin_leaf).normal));
      }
      parallelFor(suspects.size(), 1024, threads, [&](size_t begin, size_t end) {
        caster->intersect(std::span<const Ray>(probes.data() + begin, end - begin),
                          std::span<RayHit>(probe_hits.data() + begin, end - begin));
      });
      for (size_t k = 0; k < suspects.size(); ++k) {
        const RayHit& p = probe_hits[k];
        if (p.hit() && t.elementRoot(p.triangle, p.front) < 0) inside[suspects[k]] = 1;
      }
    }
  }
  stats.cast_seconds += std::chrono::duration<double>(Clock::now() - cast_start).count();
  stats.rays += rays;

  // 4. Hits, in ray order (deterministic), binned per leaf.
  std::vector<BatchHit> batch_hits;
  batch_hits.reserve(rays);
  std::unordered_map<int, std::vector<uint32_t>> per_leaf;  // looked up only; order comes from `worklist`
  std::vector<int> worklist;
  std::vector<uint32_t> shooter_rays(shooters.size(), 0), returned_rays(shooters.size(), 0);
  std::vector<glm::dvec3> returned_flux(shooters.size(), glm::dvec3(0.0));
  for (size_t j = 0; j < rays; ++j) {
    ++shooter_rays[owner[j]];
    if (inside[j]) {
      ++stats.inside_origin_rays;
      ++returned_rays[owner[j]];
      returned_flux[owner[j]] += payload[j].flux;
      continue;
    }
    if (payload[j].from_surface) ++surface_rays;
    const RayHit& h = hits[j];
    if (!h.hit()) continue;
    if (payload[j].from_surface) ++surface_hits;
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
    bh.position = c0 + double(h.u) * (dvec(geometry->corner(tri, 1)) - c0) + double(h.v) * (dvec(geometry->corner(tri, 2)) - c0);
    bh.flux = payload[j].flux;
    const int leaf = hit_leaf[j];
    auto [it, inserted] = per_leaf.try_emplace(leaf);
    if (inserted) worklist.push_back(leaf);
    it->second.push_back(uint32_t(batch_hits.size()));
    batch_hits.push_back(bh);
  }

  // 5. Dense, uneven hits subdivide their receiver (thesis 4.3.1); hits of
  // every split leaf (criterion or conformity) move to the children.
  std::sort(worklist.begin(), worklist.end());
  const auto on_split = [&](int split) {
    auto it = per_leaf.find(split);
    ++stats.subdivisions;
    if (it == per_leaf.end()) return;
    std::vector<uint32_t> moved = std::move(it->second);
    per_leaf.erase(it);
    for (uint32_t index : moved) {
      const BatchHit& bh = batch_hits[index];
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
    for (uint32_t index : list) mean += batch_hits[index].position;
    mean /= double(list.size());
    const TreeNode& node = tree->node(leaf);
    const double spread = glm::length(node.centroid - mean) * double(list.size()) * settings.subdiv;
    if (spread > node.perimeter_m && node.perimeter_m > settings.min_perimeter_m) {
      // on_split moves the hits and queues the children that got some.
      if (tree->subdivide(leaf, on_split)) growNodeArrays();
    }
  }

  // 6. Sparse hits spread over clusters (thesis 4.3), O(hit leaves +
  // ancestors). Every node learns its subtree's hits (bottom-up, each node
  // once); then, from the top, a node hands its hits down to its children
  // only when its larger child expects at least min_hits_per_element of
  // them by area, and otherwise deposits all of them at its own level, whose
  // irradiance spreads over its leaves in proportion to their areas. The
  // decision reads the node's count, never how the hits split between the
  // children. Deciding per child from its own realised count (keep it when
  // >= min, else hand it up) is biased: a small child hands up most of its
  // flux and gets back only its area share of the pool while its larger
  // sibling keeps its own, and with small batches (stiff scenes shoot ~1000
  // generations of a few hundred rays) that never averages out: the faces
  // of a box in an albedo-0.999 room came out 0.5 to 1.5 times their true
  // irradiance (tests/stability, Stiff.EstimatedErrorIsNeverBelow...).
  struct Accumulated {
    uint32_t count = 0;
    glm::dvec3 flux{0.0};
  };
  std::map<int, Accumulated> accumulated;  // subtree totals, ordered by node id: deterministic
  size_t max_depth = 0;
  for (const auto& [leaf, list] : per_leaf) {
    if (list.empty()) continue;
    Accumulated a;
    for (uint32_t index : list) a.flux += batch_hits[index].flux;
    a.count = uint32_t(list.size());
    accumulated[leaf] = a;
    max_depth = std::max<size_t>(max_depth, tree->node(leaf).depth);
    ++stats.hit_elements;
    stats.propagation_bound += tree->node(leaf).depth + 1u;
  }
  std::vector<std::vector<int>> by_depth(max_depth + 1);
  for (const auto& [node, a] : accumulated) by_depth[tree->node(node).depth].push_back(node);
  std::vector<int> tops;  // object roots holding hits
  for (size_t d = by_depth.size(); d-- > 0;) {
    std::sort(by_depth[d].begin(), by_depth[d].end());
    for (int n : by_depth[d]) {
      ++stats.propagation_visits;
      const TreeNode& node = tree->node(n);
      if (node.parent < 0) {
        tops.push_back(n);
        continue;
      }
      const Accumulated a = accumulated[n];
      auto [pit, inserted] = accumulated.try_emplace(node.parent);
      if (inserted) by_depth[d - 1].push_back(node.parent);
      pit->second.count += a.count;
      pit->second.flux += a.flux;
    }
  }
  std::sort(tops.begin(), tops.end());
  std::vector<int> stack(tops.rbegin(), tops.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    const TreeNode& node = tree->node(n);
    const Accumulated& a = accumulated[n];
    if (!node.isLeaf()) {
      const double larger_m2 = std::max(tree->node(node.child[0]).area_m2, tree->node(node.child[1]).area_m2);
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
  // 7. Flux of rays that started inside solids goes back to its shooter,
  // as unshot reflected flux. A shooter all of whose rays came back may be
  // hidden as a whole: it hands the flux to its parent, so no pass can
  // loop on it; an object root absorbs it once at least
  // kHiddenEvidenceRays rays all came back (a wholly buried object), and
  // keeps it while fewer did (a pass ends anyway once the unshot flux is
  // below pass_end_rays rays, and a root holding more gets that many).
  constexpr uint32_t kHiddenEvidenceRays = 8;
  for (size_t i = 0; i < shooters.size(); ++i) {
    if (returned_rays[i] == 0) continue;
    int n = shooters[i].index;
    if (returned_rays[i] == shooter_rays[i]) {
      const int parent = tree->node(n).parent;
      if (parent >= 0) {
        n = parent;
      } else if (returned_rays[i] >= kHiddenEvidenceRays) {
        stats.back_absorbed += returned_rays[i];
        continue;
      }
    }
    const glm::dvec3& reflectance_area = tree->node(n).reflectance_area;
    glm::dvec3 level(0.0);
    for (int c = 0; c < 3; ++c) level[c] = reflectance_area[c] > 0 ? returned_flux[i][c] / reflectance_area[c] : 0.0;
    e_unshot[size_t(n)] += level;
    pending.insert(n);
  }
  ++batch;
  ++stats.batches;
  ++version;
}

Status RadiositySolver::improve(const StopRule& stop) {
  State& s = *state_;
  const auto call_start = Clock::now();
  const double elapsed_before = s.stats.seconds;
  if (!s.started) {
    s.startPass();
    s.recordPoint(0.0);
  }
  while (true) {
    const double call_s = std::chrono::duration<double>(Clock::now() - call_start).count();
    s.stats.seconds = elapsed_before + call_s;
    const double unshot = s.unshotY();
    SolverProgress progress{s.stats.seconds, s.stats.passes_completed, s.stats.rays, s.last_estimate,
                            s.shot_pass_y + unshot > 0 ? s.shot_pass_y / (s.shot_pass_y + unshot) : 1.0};
    // Points between pass ends at most every 0.25 s, and rarer when each
    // costs more (O(nodes): about 20x its own cost apart).
    if (s.stats.seconds - s.last_point_s >= std::max(0.25, 20.0 * s.last_point_cost_s)) s.recordPoint(s.stats.seconds);
    if (stop.cancel && stop.cancel->load()) return Status(StatusCode::kCancelled, "radiosity: cancelled");
    if (stop.progress && !stop.progress(progress)) return Status(StatusCode::kCancelled, "radiosity: cancelled");
    if (s.emitted_y <= 0) break;  // nothing emits: the answer is black, exactly
    if (call_s >= stop.max_seconds || s.stats.passes_completed >= stop.max_passes || s.stats.rays >= stop.max_rays) break;
    if (s.stats.passes_completed >= 2 && s.last_estimate <= stop.target_est_rel_error) break;
    if (progress.shot_fraction >= stop.target_shot_fraction) break;
    const uint32_t passes = s.stats.passes_completed;
    s.runBatch();
    if (s.stats.passes_completed != passes) s.recordPoint(elapsed_before + std::chrono::duration<double>(Clock::now() - call_start).count());
  }
  s.stats.seconds = elapsed_before + std::chrono::duration<double>(Clock::now() - call_start).count();
  s.recordPoint(s.stats.seconds);
  return Status();
}

}  // namespace svit::baker

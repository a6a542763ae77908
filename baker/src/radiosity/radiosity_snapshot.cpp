// RadiositySolver::snapshot and ::restore (radiosity.h): a solution handed
// from a sharded bake's plan to its shards and its merge, bit for bit.
//
// Why the tree is not written out: create() rebuilds the unsplit tree from
// the geometry deterministically, and ElementTree::subdivide is a pure
// function of the tree, so replaying the criterion's splits in their order
// rebuilds every node, vertex and edge map exactly; a hash of the nodes
// proves it did. What the shooting accumulated (per-node irradiance, pass
// sums, statistics) is written as it is.

#include <cstring>

#include "radiosity_state.h"
#include "svit/bake_file.h"
#include "util/byte_stream.h"

namespace svit::baker {
namespace {

constexpr uint32_t kSnapshotVersion = 3;  // 2: leak_guard_max_voxel_m, 3: the odd passes' sums

void putSettings(ByteWriter& w, const RadiositySettings& s) {
  w.put(s.seed);
  w.put(s.subdiv);
  w.put(s.min_perimeter_m);
  w.put(s.min_hits_per_element);
  w.put(s.first_pass_rays);
  w.put(s.pass_growth);
  w.put(s.max_batch_rays);
  w.put(s.pass_end_rays);
  w.put(s.emitter_split_ratio);
  w.put(s.hard_edge_rad);
  w.put(s.leak_guard_max_voxel_m);
}

RadiositySettings getSettings(ByteReader& r, int threads) {
  RadiositySettings s;
  s.seed = r.get<uint64_t>();
  s.subdiv = r.get<double>();
  s.min_perimeter_m = r.get<double>();
  s.min_hits_per_element = r.get<uint32_t>();
  s.first_pass_rays = r.get<uint32_t>();
  s.pass_growth = r.get<double>();
  s.max_batch_rays = r.get<uint32_t>();
  s.pass_end_rays = r.get<double>();
  s.emitter_split_ratio = r.get<double>();
  s.hard_edge_rad = r.get<double>();
  s.leak_guard_max_voxel_m = r.get<double>();
  s.threads = threads;
  return s;
}

// The counters the shooting keeps (nodes, leaves and captured fraction are
// derived in stats()).
void putStats(ByteWriter& w, const SolverStats& s) {
  for (uint64_t v : {s.rays, s.hits, s.back_absorbed, s.inside_origin_rays, s.batches,
                     s.subdivisions, s.hit_elements, s.propagation_visits, s.propagation_bound})
    w.put(v);
  w.put(s.passes_completed);
  w.put(uint64_t(s.elements));
  w.put(s.cast_seconds);
  w.put(s.seconds);
  w.putString(s.compensation);
}

SolverStats getStats(ByteReader& r) {
  SolverStats s;
  for (uint64_t* v :
       {&s.rays, &s.hits, &s.back_absorbed, &s.inside_origin_rays, &s.batches, &s.subdivisions,
        &s.hit_elements, &s.propagation_visits, &s.propagation_bound})
    *v = r.get<uint64_t>();
  s.passes_completed = r.get<uint32_t>();
  s.elements = size_t(r.get<uint64_t>());
  s.cast_seconds = r.get<double>();
  s.seconds = r.get<double>();
  s.compensation = r.getString();
  return s;
}

// Hash of every node's structure, so a restore over other geometry (or a
// replay that went another way) is refused instead of answering wrongly.
uint64_t treeHash(const ElementTree& tree) {
  uint64_t h = fnv1a64(nullptr, 0);
  for (const TreeNode& n : tree.nodes()) {
    const int32_t fields[] = {int32_t(n.kind),      int32_t(n.side),      n.parent,
                              n.child[0],           n.child[1],           int32_t(n.triangle),
                              int32_t(n.vertex[0]), int32_t(n.vertex[1]), int32_t(n.vertex[2])};
    h = fnv1a64(fields, sizeof fields, h);
    h = fnv1a64(&n.area_m2, sizeof n.area_m2, h);
  }
  return h;
}

std::vector<double> flatten(const std::vector<glm::dvec3>& values) {
  std::vector<double> out(values.size() * 3);
  if (!values.empty()) std::memcpy(out.data(), values.data(), out.size() * sizeof(double));
  return out;
}

std::vector<glm::dvec3> unflatten(const std::vector<double>& values) {
  std::vector<glm::dvec3> out(values.size() / 3);
  if (!out.empty()) std::memcpy(out.data(), values.data(), out.size() * sizeof(glm::dvec3));
  return out;
}

void putSeries(ByteWriter& w, const std::vector<ErrorPoint>& series) {
  w.put(uint64_t(series.size()));
  for (const ErrorPoint& p : series) {
    w.put(p.t_s);
    w.put(p.est_rel_error);
    w.put(p.ref_rel_error);
    w.put(p.rays);
  }
}

std::vector<ErrorPoint> getSeries(ByteReader& r) {
  const uint64_t count = r.get<uint64_t>();
  std::vector<ErrorPoint> series;
  for (uint64_t i = 0; i < count && r.ok(); ++i) {
    ErrorPoint p;
    p.t_s = r.get<double>();
    p.est_rel_error = r.get<double>();
    p.ref_rel_error = r.get<double>();
    p.rays = r.get<uint64_t>();
    series.push_back(p);
  }
  return series;
}

Status notThisSolution(const std::string& what) {
  return Status(StatusCode::kInvalidInput, "radiosity snapshot: " + what);
}

}  // namespace

// The current pass and the completed passes' sums.
void RadiositySolver::State::putShooting(ByteWriter& w) const {
  const State& s = *this;
  w.putVector(flatten(s.e_pass));
  w.putVector(flatten(s.e_unshot));
  w.putVector(flatten(s.e_sum));
  w.putVector(flatten(s.e_sum_odd));
  w.putVector(std::vector<int>(s.pending.begin(), s.pending.end()));
  w.put(uint8_t(s.started));
  w.put(s.pass);
  w.put(s.batch);
  for (double v : {s.pass_rays, s.ray_flux_y, s.shot_pass_y, s.weight_sum}) w.put(v);
  w.putVector(s.light_unshot);
  w.putVector(s.emission_unshot);
  w.put(s.ambient_sum);
  w.put(s.weight_sum_odd);
  w.put(s.ambient_sum_odd);
  w.putVector(s.element_s1);
  w.putVector(s.element_s2);
  w.put(s.surface_rays);
  w.put(s.surface_hits);
}

void RadiositySolver::State::getShooting(ByteReader& r) {
  State& s = *this;
  s.e_pass = unflatten(r.getVector<double>());
  s.e_unshot = unflatten(r.getVector<double>());
  s.e_sum = unflatten(r.getVector<double>());
  s.e_sum_odd = unflatten(r.getVector<double>());
  const std::vector<int> pending_nodes = r.getVector<int>();
  s.pending = std::set<int>(pending_nodes.begin(), pending_nodes.end());
  s.started = r.get<uint8_t>() != 0;
  s.pass = r.get<uint32_t>();
  s.batch = r.get<uint32_t>();
  for (double* v : {&s.pass_rays, &s.ray_flux_y, &s.shot_pass_y, &s.weight_sum})
    *v = r.get<double>();
  s.light_unshot = r.getVector<double>();
  s.emission_unshot = r.getVector<double>();
  s.ambient_sum = r.get<glm::dvec3>();
  s.weight_sum_odd = r.get<double>();
  s.ambient_sum_odd = r.get<glm::dvec3>();
  s.element_s1 = r.getVector<double>();
  s.element_s2 = r.getVector<double>();
  s.surface_rays = r.get<uint64_t>();
  s.surface_hits = r.get<uint64_t>();
}

// Whether the per-node and per-element arrays read back have the sizes the
// rebuilt tree and the geometry give them.
bool RadiositySolver::State::shootingFits() const {
  const State& s = *this;
  const size_t nodes = s.tree->nodes().size();
  const size_t sides = s.geometry->triangleCount() * 2;
  const bool pending_ok =
      s.pending.empty() || (*s.pending.begin() >= 0 && size_t(*s.pending.rbegin()) < nodes);
  return s.e_pass.size() == nodes && s.e_unshot.size() == nodes && s.e_sum.size() == nodes &&
         s.e_sum_odd.size() == nodes && s.element_s1.size() == sides &&
         s.element_s2.size() == sides && pending_ok &&
         s.light_unshot.size() == (s.started ? s.lights.size() : s.light_unshot.size()) &&
         s.emission_unshot.size() ==
             (s.started ? s.emitting_roots.size() : s.emission_unshot.size());
}

Status RadiositySolver::State::replaySubdivisions(const std::vector<int>& splits) {
  State& s = *this;
  for (int leaf : splits) {
    if (leaf < 0 || size_t(leaf) >= s.tree->nodes().size() || !s.tree->node(leaf).isLeaf())
      return notThisSolution("split " + std::to_string(leaf) +
                             " is not a leaf of this level's tree");
    if (!s.tree->subdivide(leaf, [](int) {}))
      return notThisSolution("split " + std::to_string(leaf) + " exceeds the node cap");
  }
  s.subdivided = splits;
  return Status();
}

std::vector<uint8_t> RadiositySolver::snapshot() const {
  const State& s = *state_;
  ByteWriter w;
  w.put(kSnapshotVersion);
  putSettings(w, s.settings);
  w.put(uint64_t(s.geometry->triangleCount()));
  w.putVector(s.subdivided);
  w.put(uint64_t(s.tree->nodes().size()));
  w.put(treeHash(*s.tree));
  s.putShooting(w);
  putStats(w, s.stats);
  putSeries(w, s.series);
  for (double v : {s.last_estimate, s.last_point_s, s.last_point_cost_s}) w.put(v);
  w.putVector(s.reference);
  w.put(s.version);
  return w.take();
}

Expected<std::unique_ptr<RadiositySolver>> RadiositySolver::restore(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster, int threads,
    const std::vector<uint8_t>& snapshot) {
  ByteReader r(snapshot);
  if (r.get<uint32_t>() != kSnapshotVersion) return notThisSolution("unknown version");
  const RadiositySettings settings = getSettings(r, threads);
  if (r.get<uint64_t>() != geometry.triangleCount() || !r.ok())
    return notThisSolution("taken over another level's geometry (triangle count differs)");
  Expected<std::unique_ptr<RadiositySolver>> solver = create(scene, geometry, caster, settings);
  if (!solver.ok()) return solver.status();
  State& s = *(*solver)->state_;
  const std::vector<int> subdivided = r.getVector<int>();
  if (Status status = s.replaySubdivisions(subdivided); !status.ok()) return status;
  const uint64_t nodes = r.get<uint64_t>();
  if (nodes != s.tree->nodes().size() || r.get<uint64_t>() != treeHash(*s.tree))
    return notThisSolution("its element tree differs from the one rebuilt for this level");
  s.getShooting(r);
  s.stats = getStats(r);
  s.series = getSeries(r);
  for (double* v : {&s.last_estimate, &s.last_point_s, &s.last_point_cost_s}) *v = r.get<double>();
  s.reference = r.getVector<Rgb>();
  s.version = r.get<uint64_t>();
  if (!r.atEnd() || !s.shootingFits()) return notThisSolution("truncated or malformed");
  return solver;
}

}  // namespace svit::baker

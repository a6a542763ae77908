#include "emitter_set.h"

#include <algorithm>
#include <cmath>

#include "aabb_ops.h"
#include "scene/numeric.h"

namespace svit::gl {
namespace {

glm::dvec3 dvec(const Rgb& c) { return {c.r, c.g, c.b}; }

int sampleCount(double flux, double max_flux, const RuntimeSettings& s) {
  if (!(max_flux > 0)) return s.min_samples_per_emitter;
  const int n = int(std::ceil(double(s.max_samples_per_emitter) * std::abs(flux) / max_flux));
  return std::clamp(n, s.min_samples_per_emitter, s.max_samples_per_emitter);
}

/// Per static group: the luminous flux of its members' baked exitance.
std::vector<double> groupFlux(const EmitterContext& c) {
  const StaticLevel& level = c.level;
  std::vector<double> group_flux(level.static_groups, 0.0);
  for (uint32_t r = 0; r < level.static_receivers; ++r) {
    group_flux[level.patches.shooter[r]] +=
        std::max(0.0, luminanceOf(level.patches.baseline[r])) * double(c.receivers[r].area_m2);
  }
  return group_flux;
}

/// The groups with baseline flux, brightest first (ties by group).
std::vector<std::pair<double, uint32_t>> brightestGroups(const std::vector<double>& group_flux) {
  std::vector<std::pair<double, uint32_t>> bright;
  for (uint32_t g = 0; g < group_flux.size(); ++g) {
    if (group_flux[g] > 0) bright.push_back({group_flux[g], g});
  }
  std::sort(bright.begin(), bright.end(), [](auto& a, auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  return bright;
}

// Whether the bake shades emitter `i` per pixel (a shadow mask's light).
bool isMaskedEmitter(const BakeData& bake, uint32_t i) {
  return std::any_of(bake.masks.lights.begin(), bake.masks.lights.end(),
                     [&](const BakeMaskedLight& m) { return m.emitter == i; });
}

void addBakedLights(EmitterSet& set, const EmitterContext& c) {
  const BakeData& bake = c.level.bake;
  for (uint32_t i = 0; i < bake.emitters.size(); ++i) {
    const BakeEmitter& be = bake.emitters[i];
    if (be.kind == BakeEmitter::Kind::kPatch) continue;
    Emitter e;
    e.kind = be.kind == BakeEmitter::Kind::kLight ? EmitterKind::kBakedLight
             : be.kind == BakeEmitter::Kind::kSun ? EmitterKind::kSun
                                                  : EmitterKind::kSky;
    e.index = i;
    e.bake_emitter = i;
    e.needs_baseline = true;
    e.masked = isMaskedEmitter(bake, i);
    e.flux = dvec(be.flux);  // until its samples give the exact lobe's flux
    initBakeShares(e, c);
    set.emitters.push_back(std::move(e));
  }
}

/// A lamp's emissive patch: its shooters can be dimmed as the baked emitter.
void addLampPatches(EmitterSet& set, const EmitterContext& c, const std::vector<double>& group_flux,
                    double max_flux) {
  const StaticLevel& level = c.level;
  for (uint32_t i = 0; i < level.bake.emitters.size(); ++i) {
    const BakeEmitter& be = level.bake.emitters[i];
    if (be.kind != BakeEmitter::Kind::kPatch) continue;
    for (uint32_t g = 0; g < level.static_groups; ++g) {
      if (level.patches.shooter_bake_patch[g] != be.index) continue;
      const uint32_t id = addGroupEmitter(set, c, g, true, group_flux[g], max_flux);
      set.emitters[id].bake_emitter = i;
      set.emitters[id].masked = isMaskedEmitter(level.bake, i);
      initBakeShares(set.emitters[id], c);
    }
  }
}

}  // namespace

void addBakedEmitters(EmitterSet& set, const EmitterContext& c) {
  const std::vector<double> group_flux = groupFlux(c);
  const std::vector<std::pair<double, uint32_t>> bright = brightestGroups(group_flux);
  double bright_total = 0, max_flux = 0;
  for (double f : group_flux) {
    bright_total += f;
    max_flux = std::max(max_flux, f);
  }
  addBakedLights(set, c);
  // The bright patches: those carrying secondary_emitter_share of the
  // reflected baseline flux.
  double covered = 0;
  for (auto& [f, g] : bright) {
    if (covered >= c.settings.secondary_emitter_share * bright_total) break;
    covered += f;
    addGroupEmitter(set, c, g, true, f, max_flux);
  }
  addLampPatches(set, c, group_flux, max_flux);
}

uint32_t addGroupEmitter(EmitterSet& set, const EmitterContext& c, uint32_t group, bool bright,
                         double wanted_flux, double max_flux) {
  const StaticLevel& level = c.level;
  const bool static_group = group < level.static_groups;
  if (set.group_emitter[group] != kInvalidId) {
    set.emitters[set.group_emitter[group]].needs_baseline |= bright && static_group;
    return set.group_emitter[group];
  }
  Emitter e;
  e.kind = static_group ? EmitterKind::kStaticPatch : EmitterKind::kDynamicObject;
  e.index = static_group ? group : group - level.static_groups;
  e.needs_baseline = bright && static_group;
  if (e.kind == EmitterKind::kStaticPatch) {
    for (uint32_t r : level.patches.shooter_members[group]) {
      e.flux += level.patches.baseline[r] * double(c.receivers[r].area_m2);
    }
  }
  if (e.kind == EmitterKind::kDynamicObject) e.flux = glm::dvec3(wanted_flux);
  e.sample_count = sampleCount(wanted_flux, max_flux, c.settings);
  set.emitters.push_back(std::move(e));
  set.group_emitter[group] = uint32_t(set.emitters.size() - 1);
  return set.group_emitter[group];
}

std::vector<uint32_t> eraseGroupEmitters(EmitterSet& set, uint32_t first_group, uint32_t count) {
  std::vector<uint32_t> erased;
  for (uint32_t g = first_group; g < first_group + count; ++g) {
    if (set.group_emitter[g] == kInvalidId) continue;
    erased.push_back(set.group_emitter[g]);
    set.group_emitter[g] = kInvalidId;
  }
  if (erased.empty()) return erased;
  std::sort(erased.begin(), erased.end());
  // One pass moving the kept records down over the erased ones.
  size_t kept = erased.front(), next_erased = 0;
  for (size_t id = erased.front(); id < set.emitters.size(); ++id) {
    if (next_erased < erased.size() && erased[next_erased] == id) {
      ++next_erased;
      continue;
    }
    set.emitters[kept++] = std::move(set.emitters[id]);
  }
  set.emitters.resize(kept);
  for (uint32_t& id : set.group_emitter) {
    if (id != kInvalidId) id = emitterIdAfterErase(id, erased);
  }
  return erased;
}

uint32_t emitterIdAfterErase(uint32_t id, const std::vector<uint32_t>& erased) {
  const auto below = std::lower_bound(erased.begin(), erased.end(), id) - erased.begin();
  return id - uint32_t(below);
}

namespace {

/// Each bake patch's factor spread over its runtime patches by area,
/// merged per receiver in receiver order.
SparseShares spreadBakeFactors(const BakeEmitter& be, const EmitterContext& c) {
  const RuntimePatches& patches = c.level.patches;
  std::vector<std::pair<uint32_t, float>> entries;
  for (size_t i = 0; i < be.patches.size(); ++i) {
    const uint32_t p = be.patches[i];
    if (p >= patches.bake_members.size()) continue;
    double area = 0;
    for (uint32_t r : patches.bake_members[p]) area += c.receivers[r].area_m2;
    if (!(area > 0)) continue;
    for (uint32_t r : patches.bake_members[p]) {
      const float share = float(double(be.factors[i]) * c.receivers[r].area_m2 / area);
      if (share > 0) entries.push_back({r, share});
    }
  }
  std::sort(entries.begin(), entries.end());
  SparseShares shares;
  for (auto& [r, share] : entries) {
    if (!shares.receivers.empty() && shares.receivers.back() == r) {
      shares.shares.back() += share;
    } else {
      shares.receivers.push_back(r);
      shares.shares.push_back(share);
    }
  }
  shares.indexBlocks();
  return shares;
}

}  // namespace

void initBakeShares(Emitter& e, const EmitterContext& c) {
  if (e.bake_emitter == kInvalidId) return;
  const BakeEmitter& be = c.level.bake.emitters[e.bake_emitter];
  e.bake_shares = spreadBakeFactors(be, c);
  // Reach: what the bake saw it light, and the light itself. The sun and
  // the sky reach everything.
  if (be.kind == BakeEmitter::Kind::kSun || be.kind == BakeEmitter::Kind::kSky) {
    e.reach.region = Aabb::everything();
    e.reach.region_known = true;
    return;
  }
  const RuntimePatches& patches = c.level.patches;
  if (be.kind == BakeEmitter::Kind::kLight)
    grow(e.reach.source_box, c.level.scene.lights[be.index].position);
  if (e.kind == EmitterKind::kStaticPatch) {
    for (uint32_t r : patches.shooter_members[e.index]) grow(e.reach.source_box, patches.bounds[r]);
  }
  e.reach.region = e.reach.source_box;
  for (uint32_t r : e.bake_shares.receivers) grow(e.reach.region, patches.bounds[r]);
  e.reach.region_known = true;
}

}  // namespace svit::gl

#include "pass_sizing.h"

#include <algorithm>
#include <cmath>

#include "svit/baker/texel_lighting.h"

namespace svit::baker {
namespace {

// Every kProbeStride-th texel, spread over all pages and charts.
std::vector<uint32_t> probeTexels(const TexelSet& texels) {
  std::vector<uint32_t> out;
  for (size_t j = 0; j < texels.samples.size(); j += kProbeStride) out.push_back(uint32_t(j));
  return out;
}

uint32_t scaledRays(uint32_t rays, double share) {
  return std::max(1u, uint32_t(std::lround(double(rays) * share)));
}

// The probe texels lit with `share` of pass 0's rays (its solution half
// too, so its cost is the one predicted); its wall seconds.
Expected<double> probeSeconds(BakeRun& run, const LoadedLevel& level, const RadiositySolver& solver,
                              const AtlasTexels& atlas, const std::vector<uint32_t>& probe,
                              double share) {
  TexelLightingSettings settings = passLightingSettings(run, level, 0);
  settings.gather_rays = scaledRays(settings.gather_rays, share);
  settings.area_light_samples = scaledRays(settings.area_light_samples, share);
  const double start = run.clock.elapsed();
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexelList(level.scene, level.geometry, *level.caster, solver, atlas.texels, probe,
                     settings, run.cancel, {});
  if (!lit.ok()) return run.orCancelled(lit.status());
  return run.clock.elapsed() - start;
}

// A whole pass's cost from the probes: all rays twice (the first also
// warms caches and threads; the faster counts), then a quarter of them.
Expected<PassCost> measurePassCost(BakeRun& run, const LoadedLevel& level,
                                   const RadiositySolver& solver, const AtlasTexels& atlas,
                                   double& probe_s) {
  const std::vector<uint32_t> probe = probeTexels(atlas.texels);
  double seconds[3] = {0, 0, 0};
  const double shares[3] = {1.0, 1.0, kMinRayShare};
  for (int k = 0; k < 3; ++k) {
    Expected<double> s = probeSeconds(run, level, solver, atlas, probe, shares[k]);
    if (!s.ok()) return s.status();
    seconds[k] = *s;
    probe_s += *s;
  }
  const double scale = double(atlas.texels.samples.size()) / double(probe.size());
  const double full = std::min(seconds[0], seconds[1]) * scale, quarter = seconds[2] * scale;
  PassCost cost;
  cost.per_share_s = std::max(0.0, (full - quarter) / (1 - kMinRayShare));
  cost.fixed_s = std::max(0.0, full - cost.per_share_s);
  return cost;
}

}  // namespace

uint32_t filteringsOf(uint32_t passes) {
  if (passes < kFilteredPasses) return 0;
  uint32_t filterings = 0;
  for (uint32_t pass = kFilteredPasses - 1; pass < passes; ++pass)
    filterings += measuredPass(pass) ? 1 : 0;
  return filterings + (measuredPass(passes - 1) ? 0 : 1);
}

PassPlan planPasses(double seconds_for_passes, const PassCost& cost, double filter_s) {
  PassPlan plan;
  const double usable = seconds_for_passes / kPassPlanSlack;
  if (!(cost.at(1) > 0) || !(usable > 0)) return plan;
  // The seconds each of n passes has, once their filterings are paid.
  const auto perPass = [&](uint32_t n) { return (usable - filteringsOf(n) * filter_s) / n; };
  uint32_t n = kFewestPasses;
  while (perPass(n) > cost.at(1) && n < kMaxBakePasses) ++n;
  const double share = cost.per_share_s > 0 ? (perPass(n) - cost.fixed_s) / cost.per_share_s : 1.0;
  plan.ray_share = std::clamp(share, kMinRayShare, 1.0);
  plan.passes = n;
  while (plan.passes > 1 && perPass(plan.passes) < cost.at(plan.ray_share)) --plan.passes;
  if (plan.passes >= kFewestPasses || !(cost.per_share_s > 0)) return plan;
  // Too little time for kFewestPasses at a quarter: thinner filtered
  // passes, or one pass with what fits.
  if (share >= kFilteredPassesMinShare) return {kFewestPasses, share};
  const double one = (usable - cost.fixed_s) / cost.per_share_s;
  return {1, std::clamp(one, kMinRayShare, 1.0)};
}

double finishSeconds(const BakePlan& plan, double filter_s) {
  return 1.5 * filter_s + plan.pass_time_margin_s;
}

Expected<PassSizing> sizePassesToBudget(BakeRun& run, const LoadedLevel& level,
                                        const RadiositySolver& solver, const AtlasTexels& atlas,
                                        double finish_s) {
  PassSizing out;
  if (!run.plan.has_budget || atlas.texels.samples.empty()) return out;
  Expected<PassCost> cost = measurePassCost(run, level, solver, atlas, out.probe_s);
  if (!cost.ok()) return cost.status();
  out.sized = true;
  out.full_pass_s = cost->at(1);
  out.fixed_pass_s = cost->fixed_s;
  out.seconds_for_passes = std::max(0.0, run.plan.budget_s - run.clock.elapsed() - finish_s);
  const double filter_s = run.options.indirect_filter ? kFilterPassShare * cost->at(1) : 0.0;
  const PassPlan planned = planPasses(out.seconds_for_passes, *cost, filter_s);
  out.planned_passes = planned.passes;
  out.ray_share = planned.ray_share;
  run.plan.gather_rays = scaledRays(run.plan.gather_rays, out.ray_share);
  run.plan.area_light_samples = scaledRays(run.plan.area_light_samples, out.ray_share);
  return out;
}

}  // namespace svit::baker

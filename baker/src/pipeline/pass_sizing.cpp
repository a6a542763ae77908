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

}  // namespace

double rayShare(double seconds_for_passes, double predicted_pass_s) {
  if (!(predicted_pass_s > 0)) return 1.0;
  return std::clamp(seconds_for_passes / (kMinBudgetPasses * predicted_pass_s), kMinRayShare, 1.0);
}

double finishSeconds(const BakePlan& plan, double filter_s) {
  return 1.5 * filter_s + plan.pass_time_margin_s;
}

Expected<PassSizing> sizePassesToBudget(BakeRun& run, const LoadedLevel& level,
                                        const RadiositySolver& solver, const AtlasTexels& atlas,
                                        double finish_s) {
  PassSizing out;
  if (!run.plan.has_budget || atlas.texels.samples.empty()) return out;
  const std::vector<uint32_t> probe = probeTexels(atlas.texels);
  // Pass 0's own settings (and solution half), so its cost is the one predicted.
  const TexelLightingSettings settings = passLightingSettings(run, level, 0);
  const double start = run.clock.elapsed();
  Expected<std::vector<TexelIrradiance>> lit =
      lightTexelList(level.scene, level.geometry, *level.caster, solver, atlas.texels, probe,
                     settings, run.cancel, {});
  if (!lit.ok()) return run.orCancelled(lit.status());
  out.sized = true;
  out.probe_s = run.clock.elapsed() - start;
  out.predicted_pass_s = out.probe_s * double(atlas.texels.samples.size()) / double(probe.size());
  out.seconds_for_passes = std::max(0.0, run.plan.budget_s - run.clock.elapsed() - finish_s);
  out.ray_share = rayShare(out.seconds_for_passes, out.predicted_pass_s);
  run.plan.gather_rays = scaledRays(run.plan.gather_rays, out.ray_share);
  run.plan.area_light_samples = scaledRays(run.plan.area_light_samples, out.ray_share);
  return out;
}

}  // namespace svit::baker

// The bake's policy numbers (see bake_plan.h).

#include "bake_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace svit::baker {
namespace {

// With a budget the solver gets this share of it; the lighting passes,
// whose spread dominates the lightmap's error, use the rest.
constexpr double kSolverBudgetShare = 0.3;
// With a budget the solver stops early only once its error is far below
// what the lighting passes can resolve.
constexpr double kBudgetSolverTarget = 0.002;
// Without a budget: error target 0.005 at quality 1, rising by 0.05 towards
// quality 0, and a wall-time cap of 30 s plus 600 s per unit of quality.
constexpr double kBestSolverTarget = 0.005;
constexpr double kSolverTargetPerLostQuality = 0.05;
constexpr double kSolverBaseSeconds = 30.0;
constexpr double kSolverSecondsPerQuality = 600.0;
// Lighting passes without a budget: 8 at quality 1, never fewer than one.
constexpr double kPassesPerQuality = 8.0;
// With a budget, a pass starts only if one 5% slower than the slowest so
// far still leaves the measured filtering and pages and 0.1 s for the
// write (pass_sizing.h): passes of a bake vary by a few percent.
constexpr double kPassTimeSafety = 1.05;
constexpr double kPassTimeMarginS = 0.1;
// Rays per texel and pass: few, so a pass is cheap and a bake runs many,
// whose spread gives the error estimate; the sun's disk is small and needs
// fewer than area lights.
constexpr uint32_t kGatherRays = 16;
constexpr uint32_t kAreaLightSamples = 16;
constexpr uint32_t kSunSamples = 2;
// Default atlas: about 512 x 512 texels over the level's surface, between
// 1 texel per metre (huge levels) and 512 (tiny ones).
constexpr double kAutoAtlasTexels = 262144.0;
constexpr double kMinAutoTexelsPerM = 1.0;
constexpr double kMaxAutoTexelsPerM = 512.0;
// Keeps the square root finite for a level without surface area, m^2.
constexpr double kMinAtlasAreaM2 = 1e-9;

}  // namespace

BakePlan planBake(const BakeOptions& options) {
  BakePlan plan;
  plan.budget_s = options.time_budget_s;
  plan.has_budget = std::isfinite(plan.budget_s);
  plan.solver_target_est_rel_error =
      plan.has_budget ? kBudgetSolverTarget
                      : kBestSolverTarget + kSolverTargetPerLostQuality * (1.0 - options.quality);
  plan.solver_max_seconds = plan.has_budget
                                ? kSolverBudgetShare * plan.budget_s
                                : kSolverSecondsPerQuality * options.quality + kSolverBaseSeconds;
  plan.texels_per_m = options.texels_per_m;
  plan.quality_passes = std::max(1u, uint32_t(std::lround(kPassesPerQuality * options.quality)));
  plan.max_lighting_passes = kMaxBakePasses;
  plan.pass_time_safety = kPassTimeSafety;
  plan.pass_time_margin_s = kPassTimeMarginS;
  if (options.passes > 0) {
    // Defined by passes, not wall time: the same result on any machine.
    plan.quality_passes = options.passes;
    plan.solver_max_seconds = std::numeric_limits<double>::infinity();
    plan.solver_targets_at_pass_ends = true;
  }
  plan.gather_rays = kGatherRays;
  plan.area_light_samples = kAreaLightSamples;
  plan.sun_samples = kSunSamples;
  return plan;
}

double atlasTexelsPerM(const BakePlan& plan, double total_area_m2) {
  if (plan.texels_per_m > 0) return plan.texels_per_m;
  return std::clamp(std::sqrt(kAutoAtlasTexels / std::max(total_area_m2, kMinAtlasAreaM2)),
                    kMinAutoTexelsPerM, kMaxAutoTexelsPerM);
}

bool measuredPass(uint32_t pass) { return ((pass + 1) & pass) == 0; }

bool wantLightingPass(const BakePlan& plan, uint32_t pass, double elapsed_s, double pass_s,
                      double finish_s) {
  if (pass >= plan.max_lighting_passes) return false;
  if (plan.has_budget) {
    return !(pass > 0 && elapsed_s + pass_s * plan.pass_time_safety + finish_s > plan.budget_s);
  }
  return pass < plan.quality_passes;
}

}  // namespace svit::baker

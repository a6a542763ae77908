#pragma once
// Lighting passes sized to a time budget from their measured cost (issue 46
// item 2; the figures behind each choice: docs/architecture/baker-pipeline.md,
// "Passes sized to the budget"). Passes are whole (each lights every texel
// once, and the split-half estimate and the filter need them alike), so the
// last one that fits leaves up to a pass of the budget unused. Before the
// first pass, timed passes over every 16th texel at all of the plan's rays
// and at a quarter of them measure a pass's cost: a part that shrinks with
// its rays and a part that does not (texel setup, a shadow ray per point
// light). The fewest passes that fill the time the passes have then run (4
// at least, for the filter and the split half), with their rays shrunk so
// that they fill it (to a quarter, or an eighth where only that lets four
// fit): more, smaller passes in the same seconds cast fewer rays. The plan keeps time for the
// filterings of the measured passes (4, 8, 16, ... and the last), each taken as kFilterPassShare of
// a pass: the filter's cost is unknown until it has run once.

#include <cstdint>

#include "bake_plan.h"
#include "bake_stages.h"
#include "lightmap/filtered_passes.h"

namespace svit::baker {

/// Every this many texels one is lit by the probe passes.
inline constexpr uint32_t kProbeStride = 16;
/// Smallest share of the plan's rays a pass keeps: below it a pass is
/// mostly its fixed part, and a single gather ray has no stratification.
inline constexpr double kMinRayShare = 0.25;
/// Passes a budget holds at least: those the filter needs (and the split
/// half).
inline constexpr uint32_t kFewestPasses = kFilteredPasses;
/// Where kFewestPasses do not fit at kMinRayShare, they still run down to
/// this share: the filter they allow outweighs the rays. Below it, one pass
/// with as many rays as fit (unfiltered passes of a ray or two are noise).
inline constexpr double kFilteredPassesMinShare = 0.125;
/// The passes are planned to fill the time less this share of slack: a next
/// pass starts only if 1.05x the slowest one fits (bake_plan.h), and passes
/// vary by a few percent.
inline constexpr double kPassPlanSlack = 1.06;

/// A filtering of the passes as a share of a pass at the plan's rays, as
/// on the double-sided Cornell box; where rays cost more it is less.
inline constexpr double kFilterPassShare = 0.45;

/// A whole pass's cost at a share s of the plan's rays.
struct PassCost {
  double fixed_s = 0;      ///< what does not shrink with the rays
  double per_share_s = 0;  ///< what does, at all of them
  double at(double share) const { return fixed_s + per_share_s * share; }
};

/// The passes planned for `seconds_for_passes` at `cost`.
struct PassPlan {
  uint32_t passes = 0;
  double ray_share = 1;
};

/// The filterings a bake of `passes` lighting passes runs: after each
/// measured pass (measuredPass) from kFilteredPasses on, and after the last.
uint32_t filteringsOf(uint32_t passes);

/// The fewest passes, kFewestPasses at least, that with their filterings
/// (`filter_s` each) fill `seconds_for_passes` (less kPassPlanSlack) at no
/// more than the plan's rays, and the share of them that fills it
/// (kMinRayShare at least). Where that leaves fewer than kFewestPasses,
/// kFewestPasses at down to kFilteredPassesMinShare, else one pass at the
/// share that fits (kMinRayShare at least). Pure.
PassPlan planPasses(double seconds_for_passes, const PassCost& cost, double filter_s = 0);

/// With a budget, probes the pass cost and scales run.plan's gather rays and
/// area-light samples per pass by planPasses' share for the time left but
/// `finish_s`; without one, changes nothing. Errors: cancellation.
Expected<PassSizing> sizePassesToBudget(BakeRun& run, const LoadedLevel& level,
                                        const RadiositySolver& solver, const AtlasTexels& atlas,
                                        double finish_s);

/// The seconds after the last pass: its filtering (measured, `filter_s`),
/// the pages (half as long at most, measured on the Cornell box and the
/// house) and the write.
double finishSeconds(const BakePlan& plan, double filter_s);

}  // namespace svit::baker

#pragma once
// Lighting passes sized to a time budget from their measured cost (issue 46
// item 2). Passes are whole (each lights every texel once, and the
// split-half estimate and the filter need them alike), so the last one
// that fits leaves up to a pass of the budget unused: at 10 s on the
// Cornell box a pass of 16 gather rays took a tenth of the budget and
// bakes ended at 8.1-9.1 s. Before the first pass a timed gather over
// every 32nd texel predicts a pass, and the rays per texel and pass shrink
// (down to a quarter) until at least 30 passes fit the time the passes
// have, so what the last one leaves is at most a thirtieth of it. Never
// below a quarter: a pass has costs that do not shrink with its rays (the
// texel's setup, a shadow ray per light), and a single gather ray has no
// stratification. The double-sided Cornell box at 256 texels/m (1.6 M
// texels) in 10 s runs one pass at a quarter (17.7 % RMS against Mitsuba,
// ending at 8.3 s); two passes of one gather ray each read 113 %.

#include <cstdint>

#include "bake_stages.h"

namespace svit::baker {

/// Every this many texels one is lit by the probe pass.
inline constexpr uint32_t kProbeStride = 32;
/// Passes the budget should hold at least (where a quarter of the rays allow).
inline constexpr double kMinBudgetPasses = 30;
/// Smallest share of the plan's rays a pass keeps.
inline constexpr double kMinRayShare = 0.25;

/// With a budget, probes the pass cost and scales run.plan's gather rays and
/// area-light samples per pass so that kMinBudgetPasses fit the time left
/// but `finish_s` (rayShare); without one, changes nothing. Errors:
/// cancellation.
Expected<PassSizing> sizePassesToBudget(BakeRun& run, const LoadedLevel& level,
                                        const RadiositySolver& solver, const AtlasTexels& atlas,
                                        double finish_s);

/// The share of the plan's rays a pass keeps when a pass at the plan's rays
/// takes `predicted_pass_s` and the passes have `seconds_for_passes`.
double rayShare(double seconds_for_passes, double predicted_pass_s);

/// The seconds after the last pass: its filtering (measured, `filter_s`),
/// the pages (half as long at most, measured on the Cornell box and the
/// house) and the write.
double finishSeconds(const BakePlan& plan, double filter_s);

}  // namespace svit::baker

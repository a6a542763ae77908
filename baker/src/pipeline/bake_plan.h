#pragma once
// The bake's policy: how the options (quality, time budget, texel density)
// become the solver's stop rule, the atlas density and the lighting passes.
// Every number of that policy lives here, with its reason. Internal.

#include <cstdint>

#include "svit/baker/bake.h"

namespace svit::baker {

struct BakePlan {
  bool has_budget = false;  ///< a finite time budget; otherwise the quality decides
  double budget_s = 0;      ///< the options' time budget (infinity without one)

  // Radiosity.
  double solver_target_est_rel_error = 0;  ///< stop rule's error target
  double solver_max_seconds = 0;           ///< stop rule's wall-time cap
  /// targets checked at pass ends only (with a pass count: no clock in the result)
  bool solver_targets_at_pass_ends = false;

  // Atlas.
  double texels_per_m = 0;  ///< the option; 0: chosen from the level's area by atlasTexelsPerM

  // Lighting passes.
  uint32_t quality_passes = 1;       ///< passes without a budget
  uint32_t max_lighting_passes = 0;  ///< hard cap, budget or not
  /// with a budget: the next pass is assumed this much slower than the slowest so far
  double pass_time_safety = 0;
  /// with a budget: seconds kept free for writing, beyond the measured
  /// filtering and pages (pass_sizing.h finishSeconds)
  double pass_time_margin_s = 0;
  uint32_t gather_rays = 0;         ///< final-gather rays per texel and pass
  uint32_t area_light_samples = 0;  ///< shadow rays to emissive surfaces per texel and pass
  uint32_t sun_samples = 0;         ///< shadow rays across the sun's disk per texel and pass
};

/// The plan for `options` (which validateBakeOptions accepted). Pure.
BakePlan planBake(const BakeOptions& options);

/// Atlas density for `total_area_m2` of static surface (double sides
/// not counted): the plan's texels_per_m when set, else the density that
/// puts about 256k texels on that area, clamped to [1, 512] texels per metre.
double atlasTexelsPerM(const BakePlan& plan, double total_area_m2);

/// Whether the passes are filtered and measured after pass `pass` (0-based):
/// after 1, 2, 4, 8, ... passes (and the last), the error against a
/// reference and the split-half estimate, so a budgeted bake spends a few
/// page builds on them.
bool measuredPass(uint32_t pass);

/// Whether a lighting pass `pass` (0-based) should run, `elapsed_s` into the
/// bake, the slowest pass so far having taken `pass_s`, with `finish_s`
/// needed after the last pass (the first pass always runs).
bool wantLightingPass(const BakePlan& plan, uint32_t pass, double elapsed_s, double pass_s,
                      double finish_s);

}  // namespace svit::baker

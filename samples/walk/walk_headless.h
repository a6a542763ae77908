#pragma once
// The headless walkthrough: simulated time t = frame / fps, scripted events,
// one update and one offscreen render per frame, PNG or EXR frames and stats.

#include "svit/status.h"
#include "walk_session.h"

namespace svit::walk {

/// Runs session.frames frames. Per frame: the script's events for it, nodes
/// placed at t, Runtime::update(budget), render from the script's or the
/// level's camera, the statistics overlay with --overlay, DIR/frame-NNNN.png
/// (or .exr with --frames-format exr: the linear radiance, which the overlay
/// does not draw into) with --frames-out, a stats record.
/// Errors: a failed event, update, render or frame write (names the frame).
Status runHeadless(WalkSession& session);

}  // namespace svit::walk

#pragma once
// The interactive walkthrough (samples/walk/README.md "Window"): fly with
// WASD and the mouse, pick and move dynamic objects, switch and dim lights,
// cycle the views; the statistics are drawn over the frame (F1 toggles
// them) and carried in the window title.

#include "svit/status.h"
#include "walk_session.h"

namespace svit::walk {

/// Runs until Esc or the window closes. Level paths play in real time and
/// script events fire when their frame's time (frame / fps) has passed.
/// Errors: a failed update or render.
Status runWindow(WalkSession& session);

}  // namespace svit::walk

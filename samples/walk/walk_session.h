#pragma once
// Everything one svit-walk run holds: the level, its bake, the script, the
// GL window, svit's Runtime and SceneRenderer, and the level's motion; and
// the steps every frame shares (events, placing, update, render).

#include <memory>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/runtime.h"
#include "svit/scene.h"
#include "svit/scene_renderer.h"
#include "svit/status.h"
#include "walk_args.h"
#include "walk_gl_window.h"
#include "walk_motion.h"
#include "walk_overlay.h"
#include "walk_probe.h"
#include "walk_script.h"
#include "walk_stats.h"

namespace svit::walk {

struct WalkSession {
  WalkOptions options;
  Scene scene;
  BakeData bake;
  WalkScript script;
  std::vector<ProbePoint> probe_points;
  float fps = 30;
  int frames = 90;  ///< headless frame count
  double budget_ms = 0;
  ShadingView view = ShadingView::kRuntime;
  Camera overview;          ///< levelOverview(scene)
  int scene_camera = -1;    ///< Scene::cameras index looked from (chooseSceneCamera), or -1
  std::string gl_renderer;  ///< GL_RENDERER
  // Declared in the order they are made: destroyed renderer first, window last.
  std::unique_ptr<GlWindow> window;
  std::unique_ptr<Runtime> runtime;
  std::unique_ptr<SceneRenderer> renderer;
  std::unique_ptr<LevelMotion> motion;
  std::unique_ptr<StatsOverlay> overlay;  ///< made for a window and for --overlay
  // Baked lights switched by script events (Scene::lights index -> state);
  // the runtime scales their bake emitter by dimmer, or 0 when off.
  std::vector<float> baked_light_dimmer;
  std::vector<bool> baked_light_enabled;
  WalkStats stats;
};

/// Loads the level, the bake (OUT/bake.svit), the script and probe points
/// (all validated before any window opens), then opens the window and makes
/// the runtime and renderer. Errors name the file and element; a bake of
/// another level is refused by Runtime::create.
Expected<std::unique_ptr<WalkSession>> openSession(const WalkOptions& options);

/// Applies a script event to the motion (moves), the runtime (lights,
/// baked emitters) or the session (view). Errors: what the runtime refused.
Status applyEvent(WalkSession& session, const WalkEvent& event);

/// Scales bake emitter `emitter` to `scale` in the runtime (the light it
/// casts) and the renderer (what is drawn of it: a lamp's glowing surface).
/// Errors: the runtime's (index out of range, bad scale).
Status scaleBakeEmitter(WalkSession& session, uint32_t emitter, float scale);

/// One frame's work after events: places nodes at `t_s`, tells the runtime
/// and the view it ranks emitters for (`camera` at `aspect`), updates it
/// within the budget. Errors: the runtime's (FrameStats::error).
Expected<FrameStats> stepLighting(WalkSession& session, float t_s, const Camera& camera,
                                  float aspect);

/// After the run: the runtime's irradiance at the probe points (--probe-out)
/// and the stats JSON (--stats). Errors name the file.
Status writeOutputs(const WalkSession& session);

}  // namespace svit::walk

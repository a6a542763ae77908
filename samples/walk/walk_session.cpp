#include "walk_session.h"

#include <filesystem>
#include <utility>

#include "scene/file_output.h"
#include "svit/gl_context.h"
#include "svit/level.h"
#include "walk_camera.h"

namespace svit::walk {
namespace {

// The runtime scale of a baked light's bake emitter (kLight, same index).
Status scaleBakedLight(WalkSession& session, int light) {
  const float scale =
      session.baked_light_enabled[size_t(light)] ? session.baked_light_dimmer[size_t(light)] : 0.0f;
  for (uint32_t e = 0; e < session.bake.emitters.size(); ++e) {
    const BakeEmitter& emitter = session.bake.emitters[e];
    if (emitter.kind != BakeEmitter::Kind::kLight || emitter.index != uint32_t(light)) continue;
    if (Status s = scaleBakeEmitter(session, e, scale); !s.ok()) return s;
  }
  return Status();
}

// --frames-out DIR, --stats FILE and --probe-out FILE are tried before the
// level is loaded, so a typo fails at once rather than after the walk.
Status checkOutputPaths(const WalkOptions& options) {
  namespace fs = std::filesystem;
  auto named = [](const char* option, const std::string& path, const Status& s) {
    return Status(s.code(), std::string(option) + " " + path + ": " + s.message());
  };
  std::error_code ec;
  if (!options.frames_out.empty()) {
    // DIR is made later with its missing parents, in the nearest directory that exists.
    fs::path existing = options.frames_out;
    while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
    if (Status s = checkWritableDirectory(existing.string()); !s.ok())
      return named("--frames-out", options.frames_out, s);
  }
  for (const auto& [option, path] :
       {std::pair{"--stats", &options.stats}, std::pair{"--probe-out", &options.probe_out}}) {
    if (path->empty()) continue;
    if (fs::is_directory(*path, ec))
      return Status(StatusCode::kIoError, std::string(option) + " " + *path + ": is a directory");
    if (Status s = checkWritableDirectory(fs::path(*path).parent_path().string()); !s.ok())
      return named(option, *path, s);
  }
  return Status();
}

}  // namespace

Status scaleBakeEmitter(WalkSession& session, uint32_t emitter, float scale) {
  if (Status s = session.runtime->setBakedEmitterScale(emitter, scale); !s.ok()) return s;
  return session.renderer->setBakedEmitterScale(emitter, scale);
}

Expected<std::unique_ptr<WalkSession>> openSession(const WalkOptions& options) {
  auto session = std::make_unique<WalkSession>();
  WalkSession& s = *session;
  s.options = options;
  if (Status st = checkOutputPaths(options); !st.ok()) return st;
  Expected<Scene> scene = loadLevel(options.level);
  if (!scene.ok()) return scene.status();
  s.scene = std::move(scene).value();
  const std::string bake_path = (std::filesystem::path(options.bake_dir) / "bake.svit").string();
  Expected<BakeData> bake = readBakeFile(bake_path);
  if (!bake.ok()) return bake.status();
  s.bake = std::move(bake).value();
  if (!options.script.empty()) {
    Expected<WalkScript> script = readWalkScript(options.script, s.scene, s.bake);
    if (!script.ok()) return script.status();
    s.script = std::move(script).value();
  }
  Expected<int> camera =
      chooseSceneCamera(s.scene, options.level, options.camera, !s.script.camera.empty());
  if (!camera.ok()) return camera.status();
  s.scene_camera = *camera;
  s.fps = options.fps.value_or(s.script.fps.value_or(30.0f));
  s.frames = options.frames.value_or(s.script.frames.value_or(90));
  if (options.headless) {
    if (Status st = checkEventFrames(s.script, options.script, s.frames); !st.ok()) return st;
  }
  s.budget_ms = options.budget_ms.value_or(options.headless ? 0.0 : 8.0);
  s.view = options.view.value_or(ShadingView::kRuntime);
  if (!options.probe.empty()) {
    Expected<std::vector<ProbePoint>> points = readProbePoints(options.probe);
    if (!points.ok()) return points.status();
    s.probe_points = std::move(points).value();
  }
  s.baked_light_dimmer.assign(s.scene.lights.size(), 1.0f);
  s.baked_light_enabled.assign(s.scene.lights.size(), true);
  s.overview = levelOverview(s.scene);
  s.motion = std::make_unique<LevelMotion>(s.scene);

  Expected<std::unique_ptr<GlWindow>> window = GlWindow::create(
      options.width, options.height, !options.headless, "svit-walk " + options.level);
  if (!window.ok()) return window.status();
  s.window = std::move(window).value();
  Expected<GlContextInfo> gl = checkGlContext();
  if (!gl.ok()) return gl.status();
  s.gl_renderer = gl->renderer;
  RuntimeSettings runtime_settings;
  runtime_settings.delta_textures = false;  // SceneRenderer looks the deltas up per pixel
  runtime_settings.max_samples_per_frame = options.samples_per_frame.value_or(
      options.headless && !options.budget_ms ? kHeadlessSamplesPerFrame : 0);
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(s.scene, s.bake, options.bake_dir, runtime_settings);
  if (!runtime.ok()) return runtime.status();
  s.runtime = std::move(runtime).value();
  SceneRendererSettings settings;
  settings.width = options.width;
  settings.height = options.height;
  if (options.exposure) {  // --exposure: the same scale every frame, whatever the bake
    settings.exposure = *options.exposure;
    settings.auto_exposure = false;
  }
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(s.scene, s.bake, options.bake_dir, s.runtime.get(), settings);
  if (!renderer.ok()) return renderer.status();
  s.renderer = std::move(renderer).value();
  if (!options.headless || options.overlay) {
    Expected<std::unique_ptr<StatsOverlay>> overlay = StatsOverlay::create();
    if (!overlay.ok()) return overlay.status();
    s.overlay = std::move(overlay).value();
  }
  if (!options.frames_out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.frames_out, ec);
    if (ec)
      return Status(StatusCode::kIoError, options.frames_out + ": cannot create: " + ec.message());
  }
  return session;
}

Status applyEvent(WalkSession& session, const WalkEvent& event) {
  const std::string where = session.options.script + ": " + event.field + ": ";
  auto named = [&](const Status& s) { return s.ok() ? s : Status(s.code(), where + s.message()); };
  switch (event.kind) {
    case WalkEvent::Kind::kMove: {
      Trs trs = session.motion->localTrs(event.node);
      if (event.translation) trs.translation = *event.translation;
      if (event.rotation) trs.rotation = *event.rotation;
      if (event.scale) trs.scale = *event.scale;
      session.motion->moveNode(event.node, trs);
      return Status();
    }
    case WalkEvent::Kind::kLight: {
      const LightId id = session.runtime->lightForSceneLight(event.light);
      if (id == kInvalidId) {  // a baked light: scale its bake emitter
        if (event.enabled) session.baked_light_enabled[size_t(event.light)] = *event.enabled;
        if (event.dimmer) session.baked_light_dimmer[size_t(event.light)] = *event.dimmer;
        return named(scaleBakedLight(session, event.light));
      }
      if (event.enabled) {
        if (Status s = session.runtime->setLightEnabled(id, *event.enabled); !s.ok())
          return named(s);
      }
      if (event.dimmer) return named(session.runtime->setLightDimmer(id, *event.dimmer));
      return Status();
    }
    case WalkEvent::Kind::kBakedEmitter:
      return named(scaleBakeEmitter(session, event.emitter, event.scale_factor));
    case WalkEvent::Kind::kView: session.view = event.view; return Status();
  }
  return Status();
}

Expected<FrameStats> stepLighting(WalkSession& session, float t_s, const Camera& camera,
                                  float aspect) {
  session.motion->advance(t_s);
  if (Status s = session.motion->applyTo(*session.runtime); !s.ok()) return s;
  // The view the runtime ranks emitters for (importance caching).
  RuntimeView view;
  view.position = camera.position;
  view.look_at = camera.look_at;
  view.up = camera.up;
  view.yfov_rad = camera.yfov_rad;
  view.aspect = aspect;
  view.near_m = camera.near_m;
  if (Status s = session.runtime->setView(view); !s.ok()) return s;
  FrameStats stats = session.runtime->update(session.budget_ms);
  if (!stats.error.empty()) return Status(StatusCode::kInternal, "runtime update: " + stats.error);
  return stats;
}

Status writeOutputs(const WalkSession& session) {
  if (!session.options.probe_out.empty()) {
    std::vector<Rgb> values;
    values.reserve(session.probe_points.size());
    for (const ProbePoint& p : session.probe_points)
      values.push_back(session.runtime->irradianceAt(p.position, p.normal));
    if (Status s = writeIrradiance(session.options.probe_out, values); !s.ok()) return s;
  }
  if (!session.options.stats.empty()) {
    return session.stats.writeJson(session.options.stats, session.options.level,
                                   session.gl_renderer, session.runtime->resources(),
                                   session.renderer->resources());
  }
  return Status();
}

}  // namespace svit::walk

#include "walk_headless.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "walk_camera.h"

namespace svit::walk {
namespace {

// DIR/frame-NNNN.png (display colour) or .exr (linear radiance).
Status writeFrame(const WalkSession& session, int frame) {
  const bool exr = session.options.frames_format == FramesFormat::kExr;
  char name[32];
  std::snprintf(name, sizeof name, "frame-%04d.%s", frame, exr ? "exr" : "png");
  const std::string path = (std::filesystem::path(session.options.frames_out) / name).string();
  return exr ? session.renderer->writeExr(path) : session.renderer->writePng(path);
}

}  // namespace

Status runHeadless(WalkSession& session) {
  using Clock = std::chrono::steady_clock;
  for (int frame = 0; frame < session.frames; ++frame) {
    const std::string where = "frame " + std::to_string(frame) + ": ";
    const float t_s = float(frame) / session.fps;
    const Clock::time_point start = Clock::now();
    for (const WalkEvent& event : session.script.events) {
      if (event.frame != frame) continue;
      if (Status s = applyEvent(session, event); !s.ok()) return s;
    }
    const Camera camera =
        cameraAt(session.scene, session.overview, session.script.camera, session.scene_camera, t_s);
    const float aspect = float(session.renderer->width()) / float(session.renderer->height());
    Expected<FrameStats> lighting = stepLighting(session, t_s, camera, aspect);
    if (!lighting.ok())
      return Status(lighting.status().code(), where + lighting.status().message());
    Expected<RenderStats> render = session.renderer->render(camera, session.view);
    if (!render.ok()) return Status(render.status().code(), where + render.status().message());
    const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    const FrameRecord record{frame, double(t_s), *lighting, *render, frame_ms, session.view};
    if (session.overlay) {  // --overlay: drawn after the frame's timing ends, so not counted
      const Status s =
          session.overlay->draw(statsRows(record, ""), session.renderer->offscreenFramebuffer(),
                                session.renderer->width(), session.renderer->height());
      if (!s.ok()) return Status(s.code(), where + s.message());
    }
    if (!session.options.frames_out.empty()) {
      if (Status s = writeFrame(session, frame); !s.ok())
        return Status(s.code(), where + s.message());
    }
    session.stats.add(record);
  }
  return Status();
}

}  // namespace svit::walk

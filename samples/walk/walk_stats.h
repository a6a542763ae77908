#pragma once
// Per-frame timings of svit-walk by stage: recorded, written as JSON
// (--stats), summarised as a table on stdout.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "svit/runtime.h"
#include "svit/scene_renderer.h"
#include "svit/status.h"

namespace svit::walk {

/// One frame: the runtime's stages, the renderer's, and the whole frame
/// (placing objects + events + update + render; PNG writing excluded).
struct FrameRecord {
  int frame = 0;
  double t_s = 0;
  FrameStats runtime;
  RenderStats render;
  double frame_ms = 0;
  ShadingView view = ShadingView::kRuntime;
};

class WalkStats {
 public:
  void add(const FrameRecord& record) { frames_.push_back(record); }
  const std::vector<FrameRecord>& frames() const { return frames_; }

  /// The mean of frames [first, end): stage timings, and the work counters
  /// (emitters refreshed, maps, faces) rounded down; emitters pending,
  /// frame, t_s and view are the last frame's. A default record when the
  /// range is empty.
  FrameRecord meanSince(size_t first) const;

  /// Writes {"level", "renderer", "frames": [...], "summary": {"mean": {...},
  /// "max": {...}}, "resources": {"runtime": [...], "renderer": [...]}} to
  /// `path` via `path`.tmp and a rename; `resources` are what the runtime
  /// and the renderer hold at the end (Runtime/SceneRenderer::resources()).
  /// Errors name the path.
  Status writeJson(const std::string& path, const std::string& level, const std::string& renderer,
                   const std::vector<ResourceUse>& runtime_resources,
                   const std::vector<ResourceUse>& renderer_resources) const;

  /// A table of mean and max per stage, and totals of the work counters.
  void printTable(FILE* out) const;

 private:
  std::vector<FrameRecord> frames_;
};

}  // namespace svit::walk

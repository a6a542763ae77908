#pragma once
// svit-walk's on-screen statistics: a few rows of text (stb_easy_font's
// quads) on a semi-transparent dark box in the top-left corner, drawn with a
// tiny GL 4.5 core program (shaders/walk_overlay.*) over a finished frame:
// the window's (F1 toggles it) or the offscreen frame a PNG is written from
// (headless --overlay).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gl/gl_handle.h"
#include "svit/status.h"
#include "walk_stats.h"

namespace svit::walk {

/// One row: a label, and a value right-aligned in a second column (empty:
/// the label spans the row, wrapped at spaces where it is long).
struct OverlayRow {
  std::string label;
  std::string value;
};

/// The rows for `record` (typically a mean over recent frames; see
/// WalkStats::meanSince): frame time, the runtime's stages, shading time,
/// emitters refreshed and pending, index maps rendered, then `message`
/// (the last action) when it is not empty.
std::vector<OverlayRow> statsRows(const FrameRecord& record, const std::string& message);

class StatsOverlay {
 public:
  /// Links the overlay program. Needs a current GL 4.5 core context.
  /// Errors: the shaders do not compile or link (the driver's log).
  static Expected<std::unique_ptr<StatsOverlay>> create();
  ~StatsOverlay();
  StatsOverlay(const StatsOverlay&) = delete;
  StatsOverlay& operator=(const StatsOverlay&) = delete;

  /// Draws `rows` into the GL framebuffer `framebuffer` (0: the window's) of
  /// `width` x `height` pixels, top-left, text `scale` pixels per font unit
  /// (>= 1; 0 picks one from the height: 1 up to 539 rows, 2 up to 1079, ...).
  /// Leaves depth test, blending, culling, scissor, viewport, program, vertex
  /// array and framebuffer binding as it found them. Errors: a GL error.
  Status draw(const std::vector<OverlayRow>& rows, uint32_t framebuffer, int width, int height,
              int scale = 0);

 private:
  StatsOverlay() = default;
  gl::GlProgram program_;
  gl::GlVertexArray vao_;
  gl::GlBuffer buffer_;
  std::vector<float> vertices_;  // xy pixels, 6 per quad
  std::vector<char> scratch_;    // stb_easy_font_print's vertex output
};

}  // namespace svit::walk

// svit-walk's statistics overlay: stb_easy_font (Debian's libstb-dev, a
// header of static functions) turns text into axis-aligned quads in font
// units; they are scaled to pixels, split into triangles and drawn with
// shaders/walk_overlay.* over a dark, semi-transparent box so the text
// stays legible over bright walls and lamps.

#include "walk_overlay.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <string_view>

#include "svit/scene_renderer.h"
#include "walk_script.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"  // the header's helpers we do not call
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace svit::walk {
namespace {

// stb_easy_font: a line is 12 font units apart, letters about 7 units tall.
constexpr int kLineUnits = 12;
constexpr int kMarginUnits = 4;  // box edge to text, and screen edge to box
constexpr int kColumnGapUnits = 12;
// stb_easy_font_print writes 4 vertices x 16 bytes per quad; its header
// expects ~270 bytes per character on average. Twice that, per row.
constexpr size_t kBytesPerChar = 540;
constexpr float kBoxColour[4] = {0.0f, 0.0f, 0.0f, 0.6f};
constexpr float kTextColour[4] = {1.0f, 1.0f, 0.85f, 1.0f};

std::string format(const char* pattern, double value) {
  char text[32];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

gl::GlShader compile(GLenum stage, std::string_view source, std::string& log) {
  gl::GlShader owned(glCreateShader(stage));
  const GLuint shader = owned.id();
  const char* text = source.data();
  const GLint length = GLint(source.size());
  glShaderSource(shader, 1, &text, &length);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char buffer[1024] = {};
    glGetShaderInfoLog(shader, sizeof buffer, nullptr, buffer);
    log = buffer;
  }
  return owned;
}

int textWidth(const std::string& text) {
  std::string copy = text;  // stb_easy_font takes char*
  return stb_easy_font_width(copy.data());
}

// Breaks `text` at spaces into lines of at most `max_units` font units (a
// word longer than that stands alone on its line).
std::vector<std::string> wrap(const std::string& text, int max_units) {
  std::vector<std::string> lines;
  std::string line;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    const std::string longer = line.empty() ? word : line + " " + word;
    if (!line.empty() && textWidth(longer) > max_units) {
      lines.push_back(line);
      line = word;
    } else {
      line = longer;
    }
    start = end + 1;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// The rows as lines in font units: labels from x = 0, values right-aligned
// to the widest label + gap + widest value; rows without a value (a
// message) wrapped at that width or, when wider, at the frame's.
struct OverlayLayout {
  std::vector<OverlayRow> lines;
  int columns_width = 0;  // font units
  int content_width = 0;  // font units
};

OverlayLayout layOut(const std::vector<OverlayRow>& rows, int width, int scale) {
  int label_width = 0, value_width = 0;
  for (const OverlayRow& row : rows) {
    if (row.value.empty()) continue;
    label_width = std::max(label_width, textWidth(row.label));
    value_width = std::max(value_width, textWidth(row.value));
  }
  OverlayLayout out;
  const int columns_width = label_width + kColumnGapUnits + value_width;
  out.columns_width = columns_width;
  const int frame_units = std::max(1, width / scale - 4 * kMarginUnits);
  std::vector<OverlayRow>& lines = out.lines;
  for (const OverlayRow& row : rows) {
    if (!row.value.empty()) {
      lines.push_back(row);
      continue;
    }
    for (std::string& line :
         wrap(row.label, std::max(columns_width, std::min(frame_units, 2 * columns_width)))) {
      lines.push_back({std::move(line), ""});
    }
  }
  int content_width = columns_width;
  for (const OverlayRow& line : lines) {
    if (line.value.empty()) content_width = std::max(content_width, textWidth(line.label));
  }
  out.content_width = content_width;
  return out;
}

// Vertices of the box (drawn first) and of the text after it.
struct OverlayVertices {
  size_t box = 0, text = 0;
};

// The box as two triangles, then the text's quads as two triangles each,
// into `vertices` (xy pixels, `s` pixels per font unit); `scratch` takes
// stb_easy_font_print's output.
OverlayVertices buildVertices(const OverlayLayout& layout, float s, std::vector<float>& vertices,
                              std::vector<char>& scratch) {
  const std::vector<OverlayRow>& lines = layout.lines;
  const int content_height = kLineUnits * int(lines.size());
  const float origin = float(kMarginUnits) * 2.0f * s;  // screen edge + box margin, pixels
  vertices.clear();
  auto quad = [&](float x0, float y0, float x1, float y1) {
    vertices.insert(vertices.end(), {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1});
  };
  const float box0 = float(kMarginUnits) * s;
  quad(box0, box0, origin + float(layout.content_width + kMarginUnits) * s,
       origin + float(content_height + kMarginUnits / 2) * s);
  const size_t box_vertices = vertices.size() / 2;
  for (size_t i = 0; i < lines.size(); ++i) {
    const float y = float(kLineUnits * int(i));
    auto print = [&](const std::string& text, float x) {
      std::string copy = text;
      scratch.assign(copy.size() * kBytesPerChar + 64, 0);
      const int quads =
          stb_easy_font_print(x, y, copy.data(), nullptr, scratch.data(), int(scratch.size()));
      // Per vertex: x, y, z (float) and RGBA8: 16 bytes; 4 vertices a quad.
      for (int q = 0; q < quads; ++q) {
        const float* v0 = reinterpret_cast<const float*>(scratch.data() + size_t(q) * 64);
        const float* v2 = reinterpret_cast<const float*>(scratch.data() + size_t(q) * 64 + 32);
        quad(origin + v0[0] * s, origin + v0[1] * s, origin + v2[0] * s, origin + v2[1] * s);
      }
    };
    print(lines[i].label, 0.0f);
    if (!lines[i].value.empty())
      print(lines[i].value, float(layout.columns_width - textWidth(lines[i].value)));
  }
  return {box_vertices, vertices.size() / 2 - box_vertices};
}

// Draws the box and then the text into `framebuffer`, keeping the caller's
// state: framebuffer, viewport, program, vertex array and the enables.
void drawKeepingState(const OverlayVertices& counts, const std::vector<float>& vertices,
                      GLuint program, GLuint vao, GLuint buffer, uint32_t framebuffer, int width,
                      int height) {
  GLint previous_framebuffer = 0, previous_program = 0, previous_vao = 0, viewport[4] = {};
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_framebuffer);
  glGetIntegerv(GL_CURRENT_PROGRAM, &previous_program);
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &previous_vao);
  glGetIntegerv(GL_VIEWPORT, viewport);
  const GLboolean depth = glIsEnabled(GL_DEPTH_TEST), blend = glIsEnabled(GL_BLEND),
                  cull = glIsEnabled(GL_CULL_FACE), scissor = glIsEnabled(GL_SCISSOR_TEST);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_BLEND);
  // keep the target's alpha
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glNamedBufferData(buffer, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(),
                    GL_STREAM_DRAW);
  glUseProgram(program);
  glBindVertexArray(vao);
  glUniform2f(0, float(width), float(height));
  glUniform4fv(1, 1, kBoxColour);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(counts.box));
  glUniform4fv(1, 1, kTextColour);
  glDrawArrays(GL_TRIANGLES, GLint(counts.box), GLsizei(counts.text));
  glBindVertexArray(GLuint(previous_vao));
  glUseProgram(GLuint(previous_program));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous_framebuffer));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  depth ? glEnable(GL_DEPTH_TEST) : glDisable(GL_DEPTH_TEST);
  blend ? glEnable(GL_BLEND) : glDisable(GL_BLEND);
  cull ? glEnable(GL_CULL_FACE) : glDisable(GL_CULL_FACE);
  scissor ? glEnable(GL_SCISSOR_TEST) : glDisable(GL_SCISSOR_TEST);
}

}  // namespace

std::vector<OverlayRow> statsRows(const FrameRecord& r, const std::string& message) {
  const char* ms = "%.1f ms";
  std::vector<OverlayRow> rows = {
      {std::string("svit-walk, ") + viewName(r.view) + " view", ""},
      {"frame", format(ms, r.frame_ms)},
      {"runtime update", format(ms, r.runtime.total_ms)},
      {"  index maps", format(ms, r.runtime.maps_ms)},
      {"  reduction", format(ms, r.runtime.reduction_ms)},
      {"  bounces", format(ms, r.runtime.bounce_ms)},
      {"  upload", format(ms, r.runtime.upload_ms)},
      {"shading", format(ms, r.render.shading_ms)},
      {"emitters refreshed", format("%.0f", r.runtime.emitters_refreshed)},
      {"emitters pending", format("%.0f", r.runtime.emitters_pending)},
      {"maps rendered", format("%.0f", r.runtime.samples_rendered) +
                            format(" (%.0f faces)", r.runtime.faces_rendered)},
  };
  if (!message.empty()) rows.push_back({message, ""});
  return rows;
}

Expected<std::unique_ptr<StatsOverlay>> StatsOverlay::create() {
  std::unique_ptr<StatsOverlay> overlay(new StatsOverlay());
  std::string log;
  const std::string_view vert = shadingSource("walk_overlay.vert"),
                         frag = shadingSource("walk_overlay.frag");
  if (vert.empty() || frag.empty())
    return Status(StatusCode::kInternal, "walk_overlay.vert/.frag not embedded");
  gl::GlShader vs = compile(GL_VERTEX_SHADER, vert, log);
  if (!log.empty()) return Status(StatusCode::kInternal, "walk_overlay.vert: " + log);
  gl::GlShader fs = compile(GL_FRAGMENT_SHADER, frag, log);
  if (!log.empty()) return Status(StatusCode::kInternal, "walk_overlay.frag: " + log);
  overlay->program_ = gl::GlProgram(glCreateProgram());
  const GLuint program = overlay->program_.id();
  glAttachShader(program, vs.id());
  glAttachShader(program, fs.id());
  glLinkProgram(program);
  vs.reset();
  fs.reset();
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char buffer[1024] = {};
    glGetProgramInfoLog(program, sizeof buffer, nullptr, buffer);
    return Status(StatusCode::kInternal, std::string("walk_overlay program: ") + buffer);
  }
  overlay->buffer_ = gl::createGlBuffer();
  overlay->vao_ = gl::createGlVertexArray();
  const GLuint vao = overlay->vao_.id();
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 0, 0);
  glVertexArrayVertexBuffer(vao, 0, overlay->buffer_.id(), 0, 2 * sizeof(float));
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    return Status(StatusCode::kInternal, "walk overlay: GL error " + std::to_string(error));
  return overlay;
}

StatsOverlay::~StatsOverlay() = default;

Status StatsOverlay::draw(const std::vector<OverlayRow>& rows, uint32_t framebuffer, int width,
                          int height, int scale) {
  if (rows.empty() || width < 1 || height < 1) return Status();
  if (scale < 1) scale = 1 + height / 540;
  const OverlayLayout layout = layOut(rows, width, scale);
  const OverlayVertices counts = buildVertices(layout, float(scale), vertices_, scratch_);
  drawKeepingState(counts, vertices_, program_.id(), vao_.id(), buffer_.id(), framebuffer, width,
                   height);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    return Status(StatusCode::kInternal, "walk overlay: GL error " + std::to_string(error));
  return Status();
}

}  // namespace svit::walk

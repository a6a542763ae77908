#include "walk_args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "walk_script.h"

namespace svit::walk {
namespace {

bool parseInt(const char* text, long min, long max, int& out) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno != 0 || v < min || v > max) return false;
  out = int(v);
  return true;
}

bool parseDouble(const char* text, double min, double max, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || v < min || v > max) return false;
  out = v;
  return true;
}

// A multiplier of radiance: finite and > 0 also once narrowed to float
// (1e-50 would become 0, 1e39 infinity).
bool parseExposure(const char* text, float& out) {
  double e = 0;
  if (!parseDouble(text, 0, std::numeric_limits<float>::max(), e) || !(float(e) > 0)) return false;
  out = float(e);
  return true;
}

std::optional<FramesFormat> parseFramesFormat(const std::string& name) {
  if (name == "png") return FramesFormat::kPng;
  if (name == "exr") return FramesFormat::kExr;
  return std::nullopt;
}

// "--exposure needs ..." naming the value given, when there was one.
std::string badValue(const std::string& arg, const char* value, const std::string& needs) {
  return arg + " needs " + needs + (value != nullptr ? " (got '" + std::string(value) + "')" : "");
}

}  // namespace

void printUsage(FILE* out) {
  std::fprintf(
      out,
      "usage: svit-walk LEVEL --bake OUT [--headless] [--script S.json] [--frames N]\n"
      "                 [--frames-out DIR] [--stats FILE] [--probe POINTS --probe-out FILE]\n"
      "                 [--width W --height H] [--view baked|runtime|delta] [--budget-ms B]\n"
      "                 [--samples-per-frame N] [--fps F]\n"
      "                 [--overlay] [--exposure E] [--frames-format png|exr]\n"
      "  LEVEL            a .gltf/.glb or level .json\n"
      "  --bake OUT       the bake directory (OUT/bake.svit) written by svit-bake for LEVEL\n"
      "  --headless       no window: render N frames of simulated time (frame / fps)\n"
      "  --script S.json  camera keys and per-frame events (samples/walk/README.md)\n"
      "  --camera NAME    look from the level's glTF camera NAME (default: the level's\n"
      "                   camera path, else its first glTF camera, else an overview)\n"
      "  --frames N       frames to render headless (default: the script's, else 90)\n"
      "  --frames-out DIR write DIR/frame-0000.png ... (headless)\n"
      "  --frames-format png|exr  png (default): display colour; exr: DIR/frame-0000.exr ...\n"
      "                   with the linear radiance (cd/m2, before exposure)\n"
      "  --stats FILE     per-frame timings by stage as JSON\n"
      "  --probe POINTS   lines 'x y z nx ny nz'; with --probe-out FILE, write the runtime's\n"
      "                   irradiance 'r g b' (lux) per point after the last frame\n"
      "  --width W --height H  frame size in pixels (default 640 x 360)\n"
      "  --view V         baked, runtime (default) or delta\n"
      "  --budget-ms B    runtime update budget per frame, ms (0 = no time limit; default\n"
      "                   0 headless, 8 in a window)\n"
      "  --samples-per-frame N  point samples (index maps) per frame, 0 = no limit (default\n"
      "                   32 headless unless --budget-ms is given: reproducible frames)\n"
      "  --fps F          simulated frames per second (default: the script's, else 30)\n"
      "  --overlay        headless: draw the statistics overlay on the frames (a window\n"
      "                   shows it from the start; F1 toggles it)\n"
      "  --exposure E     fixed exposure (finite, > 0) instead of auto exposure\n"
      "exit: 0 ok, 1 bad input (level, bake, script, points), 2 bad usage\n");
}

namespace {

// What the options given together must satisfy; empty when they do.
std::string combinationError(const WalkOptions& o) {
  if (o.level.empty()) return "no LEVEL given";
  if (o.bake_dir.empty()) return "--bake OUT is required";
  if (o.probe.empty() != o.probe_out.empty()) return "--probe and --probe-out go together";
  if (!o.headless && (o.frames || !o.frames_out.empty()))
    return "--frames and --frames-out need --headless";
  return "";
}

// The field an option taking a path (or, --camera, a name) sets; null for
// any other option.
std::string* textOption(const std::string& arg, WalkOptions& o) {
  if (arg == "--bake") return &o.bake_dir;
  if (arg == "--script") return &o.script;
  if (arg == "--frames-out") return &o.frames_out;
  if (arg == "--stats") return &o.stats;
  if (arg == "--probe") return &o.probe;
  if (arg == "--probe-out") return &o.probe_out;
  if (arg == "--camera") return &o.camera;
  return nullptr;
}

}  // namespace

ParsedArgs parseWalkArgs(int argc, const char* const* argv) {
  ParsedArgs parsed;
  WalkOptions& o = parsed.options;
  auto fail = [&](const std::string& message) {
    parsed.error = message;
    return parsed;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    // Options that take a value.
    auto value = [&](const char*& out) {
      if (i + 1 >= argc) return false;
      out = argv[++i];
      return true;
    };
    const char* v = nullptr;
    if (arg == "--help" || arg == "-h") {
      parsed.help = true;
      return parsed;
    } else if (arg == "--headless") {
      o.headless = true;
    } else if (arg == "--overlay") {
      o.overlay = true;
    } else if (std::string* target = textOption(arg, o)) {
      if (!value(v) || *v == '\0')
        return fail(arg + (arg == "--camera" ? " needs a camera name" : " needs a path"));
      *target = v;
    } else if (arg == "--frames") {
      int n = 0;
      if (!value(v) || !parseInt(v, 1, 1000000, n))
        return fail("--frames needs an integer in [1, 1000000]");
      o.frames = n;
    } else if (arg == "--width" || arg == "--height") {
      int n = 0;
      if (!value(v) || !parseInt(v, 16, 8192, n))
        return fail(arg + " needs an integer in [16, 8192]");
      (arg == "--width" ? o.width : o.height) = n;
    } else if (arg == "--view") {
      if (!value(v) || !parseView(v)) return fail("--view needs baked, runtime or delta");
      o.view = parseView(v);
    } else if (arg == "--budget-ms") {
      double b = 0;
      if (!value(v) || !parseDouble(v, 0, 1e6, b))
        return fail("--budget-ms needs a number in [0, 1e6]");
      o.budget_ms = b;
    } else if (arg == "--samples-per-frame") {
      int n = 0;
      if (!value(v) || !parseInt(v, 0, 1000000, n))
        return fail(badValue(arg, v, "an integer in [0, 1000000]"));
      o.samples_per_frame = n;
    } else if (arg == "--fps") {
      double f = 0;
      if (!value(v) || !parseDouble(v, 1e-3, 1000, f))
        return fail("--fps needs a number in (0, 1000]");
      o.fps = float(f);
    } else if (arg == "--exposure") {
      float e = 0;
      if (!value(v) || !parseExposure(v, e)) return fail(badValue(arg, v, "a finite number > 0"));
      o.exposure = e;
    } else if (arg == "--frames-format") {
      if (!value(v) || !parseFramesFormat(v)) return fail(badValue(arg, v, "png or exr"));
      o.frames_format = *parseFramesFormat(v);
    } else if (!arg.empty() && arg[0] == '-') {
      return fail("unknown option '" + arg + "'");
    } else if (o.level.empty()) {
      o.level = arg;
    } else {
      return fail("unexpected argument '" + arg + "'");
    }
  }
  if (std::string error = combinationError(o); !error.empty()) return fail(error);
  return parsed;
}

}  // namespace svit::walk

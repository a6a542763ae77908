#pragma once
// svit-walk's command line (docs/architecture.md "Command-line contracts").

#include <cstdio>
#include <optional>
#include <string>

#include "svit/scene_renderer.h"

namespace svit::walk {

/// What headless frames are written as (--frames-format).
enum class FramesFormat {
  kPng,  ///< DIR/frame-NNNN.png: the display colour (8-bit sRGB, tone mapped)
  kExr,  ///< DIR/frame-NNNN.exr: the linear radiance (fp32 RGB, cd/m2, before exposure)
};

struct WalkOptions {
  std::string level;     ///< LEVEL: .gltf/.glb or level .json
  std::string bake_dir;  ///< --bake OUT: the directory holding bake.svit
  bool headless = false;
  std::string script;         ///< --script S.json, empty: none
  std::string camera;         ///< --camera NAME: a glTF camera of the level, empty: the default
  std::optional<int> frames;  ///< --frames N (headless), else the script's or 90
  std::string frames_out;     ///< --frames-out DIR (headless), empty: no frames written
  FramesFormat frames_format = FramesFormat::kPng;  ///< --frames-format png|exr
  std::string stats;                                ///< --stats FILE, empty: none
  std::string probe;                                ///< --probe POINTS
  std::string probe_out;                            ///< --probe-out FILE
  int width = 640, height = 360;
  std::optional<ShadingView> view;  ///< --view, default runtime
  /// --budget-ms; default 0 (no time limit) headless, 8 in a window
  std::optional<double> budget_ms;
  /// --samples-per-frame N (RuntimeSettings::max_samples_per_frame, 0 = no
  /// limit); default kHeadlessSamplesPerFrame headless unless --budget-ms is
  /// given, else 0.
  std::optional<int> samples_per_frame;
  std::optional<float> fps;  ///< --fps; default the script's, else 30
  bool overlay = false;      ///< --overlay: statistics drawn on the headless PNG frames
  /// --exposure E: fixed (finite, > 0), auto exposure off; default auto
  std::optional<float> exposure;
};

/// The headless default: a deterministic budget in point samples, so every
/// frame is reproducible and a level walks in minutes (settling fully would
/// render every out-of-date emitter's maps each frame: on a large level,
/// minutes a frame).
inline constexpr int kHeadlessSamplesPerFrame = 32;

/// What parsing found: options, a request for help, or a usage error.
struct ParsedArgs {
  WalkOptions options;
  bool help = false;
  std::string error;  ///< non-empty: bad usage (exit 2), says what is wrong
};

ParsedArgs parseWalkArgs(int argc, const char* const* argv);

void printUsage(FILE* out);

}  // namespace svit::walk

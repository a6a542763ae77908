#include "walk_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "walk_script.h"

namespace svit::walk {
namespace {

// The stages a frame is split into, in the order a frame runs them.
struct Stage {
  const char* name;
  double (*of)(const FrameRecord&);
};
constexpr Stage kStages[] = {
    {"maps_ms", [](const FrameRecord& r) { return r.runtime.maps_ms; }},
    {"reduction_ms", [](const FrameRecord& r) { return r.runtime.reduction_ms; }},
    {"bounce_ms", [](const FrameRecord& r) { return r.runtime.bounce_ms; }},
    {"upload_ms", [](const FrameRecord& r) { return r.runtime.upload_ms; }},
    {"runtime_ms", [](const FrameRecord& r) { return r.runtime.total_ms; }},
    {"shading_ms", [](const FrameRecord& r) { return r.render.shading_ms; }},
    {"frame_ms", [](const FrameRecord& r) { return r.frame_ms; }},
};

// JSON has no NaN or infinity; a non-finite timing would be a bug upstream,
// written as null so the file stays valid and the reader sees it.
nlohmann::json finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

Status WalkStats::writeJson(const std::string& path, const std::string& level, const std::string& renderer) const {
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameRecord& r : frames_) {
    nlohmann::json f;
    f["frame"] = r.frame;
    f["t_s"] = finite(r.t_s);
    for (const Stage& stage : kStages) f[stage.name] = finite(stage.of(r));
    f["emitters_refreshed"] = r.runtime.emitters_refreshed;
    f["emitters_pending"] = r.runtime.emitters_pending;
    f["samples"] = r.runtime.samples_rendered;
    f["faces"] = r.runtime.faces_rendered;
    f["texels_reduced"] = r.runtime.texels_reduced;
    f["bounce_rounds"] = r.runtime.bounce_rounds;
    f["unshot_share"] = finite(r.runtime.unshot_share);
    f["idle"] = r.runtime.idle;
    f["draw_calls"] = r.render.draw_calls;
    f["shadow_maps_rendered"] = r.render.shadow_maps_rendered;
    f["view"] = viewName(r.view);
    frames.push_back(std::move(f));
  }
  nlohmann::json mean = nlohmann::json::object(), max = nlohmann::json::object();
  for (const Stage& stage : kStages) {
    double sum = 0, peak = 0;
    for (const FrameRecord& r : frames_) {
      sum += stage.of(r);
      peak = std::max(peak, stage.of(r));
    }
    mean[stage.name] = finite(frames_.empty() ? 0.0 : sum / double(frames_.size()));
    max[stage.name] = finite(peak);
  }
  nlohmann::json root;
  root["level"] = level;
  root["renderer"] = renderer;
  root["frames"] = std::move(frames);
  root["summary"] = {{"frames", frames_.size()}, {"mean", mean}, {"max", max}};

  const std::string tmp = path + ".tmp";
  {
    std::ofstream file(tmp);
    file << root.dump(1) << "\n";
    if (!file) return Status(StatusCode::kIoError, tmp + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kIoError, path + ": cannot rename from " + tmp + ": " + ec.message());
  return Status();
}

void WalkStats::printTable(FILE* out) const {
  std::fprintf(out, "%-13s %10s %10s\n", "stage", "mean ms", "max ms");
  for (const Stage& stage : kStages) {
    double sum = 0, peak = 0;
    for (const FrameRecord& r : frames_) {
      sum += stage.of(r);
      peak = std::max(peak, stage.of(r));
    }
    std::fprintf(out, "%-13s %10.2f %10.2f\n", stage.name, frames_.empty() ? 0.0 : sum / double(frames_.size()), peak);
  }
  uint64_t emitters = 0, samples = 0, faces = 0, shadow_maps = 0, idle = 0;
  for (const FrameRecord& r : frames_) {
    emitters += r.runtime.emitters_refreshed;
    samples += r.runtime.samples_rendered;
    faces += r.runtime.faces_rendered;
    shadow_maps += r.render.shadow_maps_rendered;
    idle += r.runtime.idle ? 1 : 0;
  }
  std::fprintf(out,
               "%zu frames: %llu emitters refreshed, %llu samples (%llu map faces), %llu light shadow maps, "
               "%llu idle frames\n",
               frames_.size(), (unsigned long long)emitters, (unsigned long long)samples, (unsigned long long)faces,
               (unsigned long long)shadow_maps, (unsigned long long)idle);
}

}  // namespace svit::walk

#include "walk_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "scene/file_output.h"
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
nlohmann::json finite(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

// Emitters pending is a state, not work done: the last frame's stands.
FrameRecord WalkStats::meanSince(size_t first) const {
  if (first >= frames_.size()) return FrameRecord{};
  FrameRecord mean = frames_.back();
  const double n = double(frames_.size() - first);
  double sums[10] = {};
  for (size_t i = first; i < frames_.size(); ++i) {
    const FrameRecord& r = frames_[i];
    const double values[10] = {r.runtime.maps_ms,
                               r.runtime.reduction_ms,
                               r.runtime.bounce_ms,
                               r.runtime.upload_ms,
                               r.runtime.total_ms,
                               r.render.shading_ms,
                               r.frame_ms,
                               double(r.runtime.emitters_refreshed),
                               double(r.runtime.samples_rendered),
                               double(r.runtime.faces_rendered)};
    for (int k = 0; k < 10; ++k) sums[k] += values[k];
  }
  mean.runtime.maps_ms = sums[0] / n;
  mean.runtime.reduction_ms = sums[1] / n;
  mean.runtime.bounce_ms = sums[2] / n;
  mean.runtime.upload_ms = sums[3] / n;
  mean.runtime.total_ms = sums[4] / n;
  mean.render.shading_ms = sums[5] / n;
  mean.frame_ms = sums[6] / n;
  mean.runtime.emitters_refreshed = uint32_t(sums[7] / n);
  mean.runtime.samples_rendered = uint32_t(sums[8] / n);
  mean.runtime.faces_rendered = uint32_t(sums[9] / n);
  return mean;
}

Status WalkStats::writeJson(const std::string& path, const std::string& level,
                            const std::string& renderer,
                            const std::vector<ResourceUse>& runtime_resources,
                            const std::vector<ResourceUse>& renderer_resources) const {
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameRecord& r : frames_) {
    nlohmann::json f;
    f["frame"] = r.frame;
    f["t_s"] = finite(r.t_s);
    for (const Stage& stage : kStages) f[stage.name] = finite(stage.of(r));
    f["emitters_refreshed"] = r.runtime.emitters_refreshed;
    f["emitters_pending"] = r.runtime.emitters_pending;
    // Which emitters refreshed and why (importance caching), by reason.
    nlohmann::json reasons = nlohmann::json::object();
    for (const EmitterRefresh& refresh : r.runtime.refreshes) {
      const char* name = refreshReasonName(refresh.reason);
      reasons[name] = reasons.value(name, 0) + 1;
    }
    f["refresh_reasons"] = std::move(reasons);
    f["visible_patches"] = r.runtime.visible_patches;
    f["view_ms"] = finite(r.runtime.view_ms);
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
  auto resources = [](const std::vector<ResourceUse>& uses) {
    nlohmann::json out = nlohmann::json::array();
    for (const ResourceUse& u : uses) {
      out.push_back({{"name", u.name},
                     {"allocated", u.allocated},
                     {"gl_objects", u.gl_objects},
                     {"gpu_bytes", u.gpu_bytes},
                     {"cpu_bytes", u.cpu_bytes},
                     {"reason", u.reason}});
    }
    return out;
  };
  root["resources"] = {{"runtime", resources(runtime_resources)},
                       {"renderer", resources(renderer_resources)}};

  const std::string text = root.dump(1) + "\n";
  return writeFileReplacing(path, text.data(), text.size());
}

void WalkStats::printTable(FILE* out) const {
  std::fprintf(out, "%-13s %10s %10s\n", "stage", "mean ms", "max ms");
  for (const Stage& stage : kStages) {
    double sum = 0, peak = 0;
    for (const FrameRecord& r : frames_) {
      sum += stage.of(r);
      peak = std::max(peak, stage.of(r));
    }
    std::fprintf(out, "%-13s %10.2f %10.2f\n", stage.name,
                 frames_.empty() ? 0.0 : sum / double(frames_.size()), peak);
  }
  uint64_t emitters = 0, samples = 0, faces = 0, shadow_maps = 0, idle = 0;
  for (const FrameRecord& r : frames_) {
    emitters += r.runtime.emitters_refreshed;
    samples += r.runtime.samples_rendered;
    faces += r.runtime.faces_rendered;
    shadow_maps += r.render.shadow_maps_rendered;
    idle += r.runtime.idle ? 1 : 0;
  }
  std::fprintf(
      out,
      "%zu frames: %llu emitters refreshed, %llu samples (%llu map faces), %llu light shadow maps, "
      "%llu idle frames\n",
      frames_.size(), (unsigned long long)emitters, (unsigned long long)samples,
      (unsigned long long)faces, (unsigned long long)shadow_maps, (unsigned long long)idle);
}

}  // namespace svit::walk

#include "runtime_checks.h"

#include <cmath>

#include "glm_interop.h"
#include "numeric.h"

namespace svit {

Status settingError(const std::string& name, double value, const std::string& range) {
  return Status(StatusCode::kInvalidInput, "svit runtime: setting " + name + " = " +
                                               std::to_string(value) + " is out of range (" +
                                               range + ")");
}

namespace {

Status checkMapSettings(const RuntimeSettings& s) {
  if (s.map_resolution < 16 || s.map_resolution > 2048)
    return settingError("map_resolution", s.map_resolution, "16..2048");
  if (s.target_patches < 16 || s.target_patches > 1 << 20)
    return settingError("target_patches", s.target_patches, "16..1048576");
  if (s.target_shooters < 1 || s.target_shooters > s.target_patches) {
    return settingError("target_shooters", s.target_shooters, "1..target_patches");
  }
  if (s.min_samples_per_emitter < 1)
    return settingError("min_samples_per_emitter", s.min_samples_per_emitter, ">= 1");
  if (s.max_samples_per_emitter < s.min_samples_per_emitter || s.max_samples_per_emitter > 1024) {
    return settingError("max_samples_per_emitter", s.max_samples_per_emitter,
                        "min_samples_per_emitter..1024");
  }
  if (!(s.secondary_emitter_share > 0 && s.secondary_emitter_share <= 1)) {
    return settingError("secondary_emitter_share", s.secondary_emitter_share, "(0, 1]");
  }
  return Status();
}

Status checkSolveSettings(const RuntimeSettings& s) {
  if (s.max_bounces < 0 || s.max_bounces > 64)
    return settingError("max_bounces", s.max_bounces, "0..64");
  if (!(s.bounce_stop_share >= 0 && s.bounce_stop_share < 1)) {
    return settingError("bounce_stop_share", s.bounce_stop_share, "[0, 1)");
  }
  if (!(s.temporal_blend > 0 && s.temporal_blend <= 1))
    return settingError("temporal_blend", s.temporal_blend, "(0, 1]");
  if (s.view_pass_width < 16 || s.view_pass_width > 1024)
    return settingError("view_pass_width", s.view_pass_width, "16..1024");
  if (s.max_refresh_interval < 1 || s.max_refresh_interval > 1024) {
    return settingError("max_refresh_interval", s.max_refresh_interval, "1..1024");
  }
  if (s.max_samples_per_frame < 0)
    return settingError("max_samples_per_frame", s.max_samples_per_frame, ">= 0");
  return Status();
}

float length(const Vec3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

}  // namespace

Status checkSettings(const RuntimeSettings& s) {
  if (Status status = checkMapSettings(s); !status.ok()) return status;
  return checkSolveSettings(s);
}

Status checkLight(const Light& light, const std::string& what) {
  if (light.type == LightType::kDirectional) {
    return Status(StatusCode::kInvalidInput,
                  what + ": a directional runtime light is not supported (the sun is baked)");
  }
  if (!finite(light.position) || !finite(light.direction) || !finite(light.intensity) ||
      !finite(light.color)) {
    return Status(StatusCode::kInvalidInput, what + ": a value is not finite");
  }
  if (light.intensity < 0 || light.color.r < 0 || light.color.g < 0 || light.color.b < 0) {
    return Status(StatusCode::kInvalidInput, what + ": negative intensity or colour");
  }
  // The largest float below pi/2: a cone of a whole half-space.
  constexpr float kMaxOuterCone = 1.5707964f;
  if (light.type == LightType::kSpot &&
      !(light.inner_cone_rad >= 0 && light.inner_cone_rad < light.outer_cone_rad &&
        light.outer_cone_rad <= kMaxOuterCone)) {
    return Status(StatusCode::kInvalidInput, what + ": spot cone needs 0 <= inner < outer <= pi/2");
  }
  if (light.type == LightType::kSpot && !(length(light.direction) > 0)) {
    return Status(StatusCode::kInvalidInput, what + ": spot direction is zero");
  }
  return Status();
}

Status checkMesh(const DynamicMesh& mesh) {
  const std::string what = "svit runtime: object '" + mesh.name + "'";
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
    return Status(StatusCode::kInvalidInput, what + ": needs a non-empty multiple of 3 indices");
  }
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      return Status(StatusCode::kInvalidInput, what + ": index " + std::to_string(i) + " = " +
                                                   std::to_string(mesh.indices[i]) +
                                                   " >= vertex count " +
                                                   std::to_string(mesh.positions.size()));
    }
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i]))
      return Status(StatusCode::kInvalidInput,
                    what + ": position " + std::to_string(i) + " is not finite");
  }
  const Rgb& a = mesh.albedo;
  if (!(a.r >= 0 && a.r < 1 && a.g >= 0 && a.g < 1 && a.b >= 0 && a.b < 1)) {
    return Status(StatusCode::kInvalidInput, what + ": albedo must lie in [0, 1)");
  }
  const Rgb& e = mesh.emission;
  if (!(e.r >= 0 && e.g >= 0 && e.b >= 0 && finite(e))) {
    return Status(StatusCode::kInvalidInput, what + ": emission must be finite and >= 0");
  }
  return Status();
}

Status checkView(const RuntimeView& view) {
  const float values[] = {view.position.x, view.position.y, view.position.z, view.look_at.x,
                          view.look_at.y,  view.look_at.z,  view.up.x,       view.up.y,
                          view.up.z,       view.yfov_rad,   view.aspect,     view.near_m};
  for (float v : values) {
    if (!finite(v))
      return Status(StatusCode::kInvalidInput, "svit runtime: setView: the view is not finite");
  }
  const glm::vec3 forward = toGlm(view.look_at) - toGlm(view.position);
  if (!(glm::length(forward) > 0))
    return Status(StatusCode::kInvalidInput, "svit runtime: setView: position equals look_at");
  if (!(glm::length(glm::cross(glm::normalize(forward), toGlm(view.up))) > 1e-6f)) {
    return Status(StatusCode::kInvalidInput,
                  "svit runtime: setView: up is zero or along the view direction");
  }
  if (!(view.yfov_rad > 0 && view.yfov_rad < float(kPi))) {
    return Status(
        StatusCode::kInvalidInput,
        "svit runtime: setView: yfov_rad " + std::to_string(view.yfov_rad) + " is outside (0, pi)");
  }
  if (!(view.aspect > 0) || !(view.near_m > 0)) {
    return Status(StatusCode::kInvalidInput,
                  "svit runtime: setView: aspect and near_m must be positive");
  }
  return Status();
}

}  // namespace svit

#include "runtime_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "scene/glm_interop.h"
#include "scene/numeric.h"

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

// A value as messages show it: 6 significant digits, "nan", "inf".
std::string str(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}
std::string str(const Vec3& v) { return "(" + str(v.x) + ", " + str(v.y) + ", " + str(v.z) + ")"; }
std::string str(const Rgb& c) { return "(" + str(c.r) + ", " + str(c.g) + ", " + str(c.b) + ")"; }

}  // namespace

Status checkSettings(const RuntimeSettings& s) {
  if (Status status = checkMapSettings(s); !status.ok()) return status;
  return checkSolveSettings(s);
}

Status checkLight(const Light& light, const std::string& what) {
  auto error = [&](const std::string& why) {
    return Status(StatusCode::kInvalidInput, what + ": " + why);
  };
  if (light.type == LightType::kDirectional)
    return error("a directional runtime light is not supported (the sun is baked)");
  if (Status s = checkWorldPoint(light.position, what + ": position"); !s.ok()) return s;
  if (!finite(light.direction))
    return error("direction " + str(light.direction) + " is not finite");
  if (!finite(light.intensity) || light.intensity < 0)
    return error("intensity " + str(light.intensity) + " must be finite and >= 0");
  if (!finite(light.color) || light.color.r < 0 || light.color.g < 0 || light.color.b < 0)
    return error("colour " + str(light.color) + " must be finite and >= 0");
  const float brightest = light.intensity * std::max({light.color.r, light.color.g, light.color.b});
  if (!(brightest <= kMaxLightValue))
    return error("intensity x colour " + str(brightest) + " exceeds " + str(kMaxLightValue) +
                 " cd");
  // The largest float below pi/2: a cone of a whole half-space.
  constexpr float kMaxOuterCone = 1.5707964f;
  if (light.type == LightType::kSpot &&
      !(light.inner_cone_rad >= 0 && light.inner_cone_rad < light.outer_cone_rad &&
        light.outer_cone_rad <= kMaxOuterCone)) {
    return error("spot cone " + str(light.inner_cone_rad) + "/" + str(light.outer_cone_rad) +
                 " needs 0 <= inner < outer <= pi/2");
  }
  if (light.type == LightType::kSpot && !(length(light.direction) > 0))
    return error("spot direction is zero");
  return Status();
}

Status checkMesh(const DynamicMesh& mesh) {
  const std::string what = "svit runtime: object '" + mesh.name + "'";
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
    return Status(StatusCode::kInvalidInput, what +
                                                 ": needs a non-empty multiple of 3 indices (has " +
                                                 std::to_string(mesh.indices.size()) + ")");
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
      return Status(StatusCode::kInvalidInput, what + ": position " + std::to_string(i) + " " +
                                                   str(mesh.positions[i]) + " is not finite");
  }
  const Rgb& a = mesh.albedo;
  if (!(a.r >= 0 && a.r < 1 && a.g >= 0 && a.g < 1 && a.b >= 0 && a.b < 1)) {
    return Status(StatusCode::kInvalidInput, what + ": albedo " + str(a) + " must lie in [0, 1)");
  }
  const Rgb& e = mesh.emission;
  if (!(e.r >= 0 && e.g >= 0 && e.b >= 0 && e.r <= kMaxLightValue && e.g <= kMaxLightValue &&
        e.b <= kMaxLightValue)) {
    return Status(StatusCode::kInvalidInput, what + ": emission " + str(e) + " must lie in [0, " +
                                                 str(kMaxLightValue) + "] cd/m2");
  }
  return Status();
}

Status checkTransform(const Mat4& m, const std::string& what) {
  for (size_t i = 0; i < 16; ++i) {
    if (!finite(m.m[i])) {
      return Status(StatusCode::kInvalidInput, what + ": transform element m[" + std::to_string(i) +
                                                   "] = " + str(m.m[i]) + " is not finite");
    }
  }
  if (m.m[3] != 0 || m.m[7] != 0 || m.m[11] != 0 || m.m[15] != 1) {
    return Status(StatusCode::kInvalidInput,
                  what + ": transform is not affine (its last row is " + str(m.m[3]) + " " +
                      str(m.m[7]) + " " + str(m.m[11]) + " " + str(m.m[15]) + ", not 0 0 0 1)");
  }
  return Status();
}

Status checkWorldPoint(const Vec3& p, const std::string& what) {
  if (!finite(p)) return Status(StatusCode::kInvalidInput, what + " " + str(p) + " is not finite");
  if (!(std::abs(p.x) <= kWorldLimitM && std::abs(p.y) <= kWorldLimitM &&
        std::abs(p.z) <= kWorldLimitM)) {
    return Status(StatusCode::kInvalidInput,
                  what + " " + str(p) + " is beyond the +-" + str(kWorldLimitM) + " m world");
  }
  return Status();
}

Status checkPlacement(std::span<const Vec3> object_positions, const Mat4& m,
                      const std::string& what) {
  if (Status s = checkTransform(m, what); !s.ok()) return s;
  for (size_t i = 0; i < object_positions.size(); ++i) {
    const Vec3& p = object_positions[i];
    // Object space has the world's bounds too: a collapsed transform would
    // otherwise take 1e30 m positions that any later placement overflows.
    if (Status s = checkWorldPoint(p, what + ": position " + std::to_string(i)); !s.ok()) return s;
    // In double: a 1e20 scale must be reported, not overflow on the way.
    Vec3 world;
    float* out[3] = {&world.x, &world.y, &world.z};
    for (int r = 0; r < 3; ++r) {
      const double w = double(m.m[r]) * p.x + double(m.m[4 + r]) * p.y + double(m.m[8 + r]) * p.z +
                       double(m.m[12 + r]);
      *out[r] = std::abs(w) <= kWorldLimitM ? float(w) : std::numeric_limits<float>::infinity();
    }
    if (!(std::abs(world.x) <= kWorldLimitM && std::abs(world.y) <= kWorldLimitM &&
          std::abs(world.z) <= kWorldLimitM)) {
      return Status(StatusCode::kInvalidInput,
                    what + ": the transform puts position " + std::to_string(i) + " " + str(p) +
                        " beyond the +-" + str(kWorldLimitM) + " m world");
    }
  }
  return Status();
}

Status checkScale(float scale, const std::string& what) {
  if (!(scale >= 0 && scale <= kMaxScale)) {
    return Status(StatusCode::kInvalidInput,
                  what + " " + str(scale) + " must lie in [0, " + str(kMaxScale) + "]");
  }
  return Status();
}

Status checkUpdateBudget(double budget_ms) {
  if (!(budget_ms >= 0)) {
    return Status(StatusCode::kInvalidInput, "svit runtime: update: budget_ms " + str(budget_ms) +
                                                 " must be >= 0 (0: no limit)");
  }
  return Status();
}

Status checkView(const RuntimeView& view) {
  auto error = [](const std::string& why) {
    return Status(StatusCode::kInvalidInput, "svit runtime: setView: " + why);
  };
  if (!finite(view.position)) return error("position " + str(view.position) + " is not finite");
  if (!finite(view.look_at)) return error("look_at " + str(view.look_at) + " is not finite");
  if (!finite(view.up)) return error("up " + str(view.up) + " is not finite");
  const glm::vec3 forward = toGlm(view.look_at) - toGlm(view.position);
  if (!(glm::length(forward) > 0))
    return error("look_at " + str(view.look_at) + " is the position");
  if (!(glm::length(glm::cross(glm::normalize(forward), toGlm(view.up))) > 1e-6f))
    return error("up " + str(view.up) + " is zero or along the view direction");
  if (!(view.yfov_rad > 0 && view.yfov_rad < float(kPi)))
    return error("yfov_rad " + str(view.yfov_rad) + " is outside (0, pi)");
  if (!(view.aspect > 0)) return error("aspect " + str(view.aspect) + " must be > 0");
  if (!(view.near_m > 0)) return error("near_m " + str(view.near_m) + " must be > 0");
  return Status();
}

}  // namespace svit

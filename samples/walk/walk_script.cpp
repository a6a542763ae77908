// Strict reading of svit-walk scripts: every field is checked for type,
// range and finiteness, unknown fields are errors, and every name resolves
// against the level, so a typo fails before the first frame instead of
// silently doing nothing.

#include "walk_script.h"

#include <cmath>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

namespace svit::walk {
namespace {

using Json = nlohmann::json;

struct ScriptReader {
  std::string path;
  const Scene& scene;
  const BakeData& bake;

  Status error(const std::string& field, const std::string& problem) const {
    return Status(StatusCode::kInvalidInput, path + ": " + field + ": " + problem);
  }

  Status checkKeys(const Json& j, const std::string& field,
                   const std::set<std::string>& allowed) const {
    if (!j.is_object()) return error(field, "must be a JSON object");
    for (const auto& item : j.items()) {
      if (allowed.count(item.key())) continue;
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      return error(field.empty() ? item.key() : field + "." + item.key(),
                   "unknown field (expected one of: " + list + ")");
    }
    return Status();
  }

  Status number(const Json& j, const std::string& field, float& out) const {
    if (!j.is_number()) return error(field, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38) return error(field, "must be finite");
    out = float(v);
    return Status();
  }

  Status nonNegative(const Json& j, const std::string& field, float& out) const {
    if (Status s = number(j, field, out); !s.ok()) return s;
    return out >= 0 ? Status() : error(field, std::to_string(out) + " is negative");
  }

  Status integer(const Json& j, const std::string& field, int& out) const {
    if (!j.is_number_integer()) return error(field, "must be an integer");
    const long long v = j.get<long long>();
    if (v < 0 || v > 100000000)
      return error(field, std::to_string(v) + " is out of range [0, 1e8]");
    out = int(v);
    return Status();
  }

  Status floats(const Json& j, const std::string& field, size_t count, float* out) const {
    if (!j.is_array() || j.size() != count)
      return error(field, "must be an array of " + std::to_string(count) + " numbers");
    for (size_t i = 0; i < count; ++i) {
      if (Status s = number(j[i], field + "[" + std::to_string(i) + "]", out[i]); !s.ok()) return s;
    }
    return Status();
  }

  Status vec3(const Json& j, const std::string& field, Vec3& out) const {
    float v[3];
    if (Status s = floats(j, field, 3, v); !s.ok()) return s;
    out = {v[0], v[1], v[2]};
    return Status();
  }

  Status camera(const Json& j, WalkScript& script) const {
    if (!j.is_array() || j.empty()) return error("camera", "must be a non-empty array of keys");
    for (size_t k = 0; k < j.size(); ++k) {
      const std::string field = "camera[" + std::to_string(k) + "]";
      if (Status s = checkKeys(j[k], field, {"t_s", "position", "look_at", "yfov_rad"}); !s.ok())
        return s;
      CameraKey key;
      if (!script.camera.empty()) key.yfov_rad = script.camera.back().yfov_rad;
      for (const char* required : {"t_s", "position", "look_at"}) {
        if (!j[k].contains(required)) return error(field + "." + required, "is required");
      }
      if (Status s = nonNegative(j[k]["t_s"], field + ".t_s", key.t_s); !s.ok()) return s;
      if (!script.camera.empty() && !(key.t_s > script.camera.back().t_s))
        return error(field + ".t_s", "must increase");
      if (Status s = vec3(j[k]["position"], field + ".position", key.position); !s.ok()) return s;
      if (Status s = vec3(j[k]["look_at"], field + ".look_at", key.look_at); !s.ok()) return s;
      if (j[k].contains("yfov_rad")) {
        if (Status s = number(j[k]["yfov_rad"], field + ".yfov_rad", key.yfov_rad); !s.ok())
          return s;
        if (!(key.yfov_rad > 0.01f && key.yfov_rad < 3.1f))
          return error(field + ".yfov_rad", "must be in (0.01, 3.1)");
      }
      script.camera.push_back(key);
    }
    return Status();
  }

  Status move(const Json& j, const std::string& field, WalkEvent& event) const {
    if (Status s = checkKeys(j, field, {"node", "translation", "rotation", "scale"}); !s.ok())
      return s;
    if (!j.contains("node") || !j["node"].is_string())
      return error(field + ".node", "must be a node name");
    const std::string name = j["node"].get<std::string>();
    event.node = scene.findNode(name);
    if (event.node < 0) return error(field + ".node", "no node '" + name + "'");
    if (!scene.nodes[size_t(event.node)].dynamic) {
      return error(field + ".node",
                   "node '" + name + "' is static (baked); only dynamic nodes move");
    }
    if (j.contains("translation")) {
      Vec3 t;
      if (Status s = vec3(j["translation"], field + ".translation", t); !s.ok()) return s;
      event.translation = t;
    }
    if (j.contains("rotation")) {
      float q[4];
      if (Status s = floats(j["rotation"], field + ".rotation", 4, q); !s.ok()) return s;
      const float length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(length > 1e-6f))
        return error(field + ".rotation", "quaternion (x, y, z, w) has zero length");
      event.rotation = Quat{q[0] / length, q[1] / length, q[2] / length, q[3] / length};
    }
    if (j.contains("scale")) {
      Vec3 s3;
      if (Status s = vec3(j["scale"], field + ".scale", s3); !s.ok()) return s;
      event.scale = s3;
    }
    return Status();
  }

  Status light(const Json& j, const std::string& field, WalkEvent& event) const {
    if (Status s = checkKeys(j, field, {"name", "enabled", "dimmer"}); !s.ok()) return s;
    if (!j.contains("name") || !j["name"].is_string())
      return error(field + ".name", "must be a light name");
    const std::string name = j["name"].get<std::string>();
    for (size_t l = 0; l < scene.lights.size() && event.light < 0; ++l) {
      if (scene.lights[l].name == name) event.light = int(l);
    }
    if (event.light < 0) return error(field + ".name", "no light '" + name + "'");
    if (!scene.lights[size_t(event.light)].dynamic) {
      bool baked_emitter = false;
      for (const BakeEmitter& e : bake.emitters) {
        baked_emitter = baked_emitter ||
                        (e.kind == BakeEmitter::Kind::kLight && e.index == uint32_t(event.light));
      }
      if (!baked_emitter) {
        return error(field + ".name",
                     "light '" + name + "' is baked and the bake has no emitter for it");
      }
    }
    if (j.contains("enabled")) {
      if (!j["enabled"].is_boolean()) return error(field + ".enabled", "must be true or false");
      event.enabled = j["enabled"].get<bool>();
    }
    if (j.contains("dimmer")) {
      float d = 0;
      if (Status s = nonNegative(j["dimmer"], field + ".dimmer", d); !s.ok()) return s;
      event.dimmer = d;
    }
    if (!event.enabled && !event.dimmer) return error(field, "needs 'enabled' or 'dimmer'");
    return Status();
  }

  Status bakedEmitter(const Json& j, const std::string& field, WalkEvent& event) const {
    if (Status s = checkKeys(j, field, {"index", "scale"}); !s.ok()) return s;
    if (!j.contains("index")) return error(field + ".index", "is required");
    int index = 0;
    if (Status s = integer(j["index"], field + ".index", index); !s.ok()) return s;
    if (size_t(index) >= bake.emitters.size()) {
      return error(field + ".index", std::to_string(index) + " >= emitter count " +
                                         std::to_string(bake.emitters.size()) + " of the bake");
    }
    event.emitter = uint32_t(index);
    if (!j.contains("scale")) return error(field + ".scale", "is required");
    return nonNegative(j["scale"], field + ".scale", event.scale_factor);
  }

  Status events(const Json& j, WalkScript& script) const {
    if (!j.is_array()) return error("events", "must be an array");
    for (size_t e = 0; e < j.size(); ++e) {
      const std::string field = "events[" + std::to_string(e) + "]";
      if (Status s = checkKeys(j[e], field, {"frame", "move", "light", "baked_emitter", "view"});
          !s.ok())
        return s;
      WalkEvent event;
      event.field = field;
      if (!j[e].contains("frame")) return error(field + ".frame", "is required");
      if (Status s = integer(j[e]["frame"], field + ".frame", event.frame); !s.ok()) return s;
      int kinds = 0;
      for (const char* kind : {"move", "light", "baked_emitter", "view"})
        kinds += j[e].contains(kind) ? 1 : 0;
      if (kinds != 1)
        return error(field, "needs exactly one of 'move', 'light', 'baked_emitter', 'view'");
      Status s;
      if (j[e].contains("move")) {
        event.kind = WalkEvent::Kind::kMove;
        s = move(j[e]["move"], field + ".move", event);
      } else if (j[e].contains("light")) {
        event.kind = WalkEvent::Kind::kLight;
        s = light(j[e]["light"], field + ".light", event);
      } else if (j[e].contains("baked_emitter")) {
        event.kind = WalkEvent::Kind::kBakedEmitter;
        s = bakedEmitter(j[e]["baked_emitter"], field + ".baked_emitter", event);
      } else {
        event.kind = WalkEvent::Kind::kView;
        const Json& v = j[e]["view"];
        const std::optional<ShadingView> view =
            v.is_string() ? parseView(v.get<std::string>()) : std::nullopt;
        if (!view)
          s = error(field + ".view", "must be \"baked\", \"runtime\" or \"delta\"");
        else
          event.view = *view;
      }
      if (!s.ok()) return s;
      script.events.push_back(std::move(event));
    }
    return Status();
  }

  Expected<WalkScript> read(const Json& j) const {
    if (Status s = checkKeys(j, "script", {"fps", "frames", "camera", "events"}); !s.ok()) return s;
    WalkScript script;
    if (j.contains("fps")) {
      float fps = 0;
      if (Status s = number(j["fps"], "fps", fps); !s.ok()) return s;
      if (!(fps > 0 && fps <= 1000)) return error("fps", "must be in (0, 1000]");
      script.fps = fps;
    }
    if (j.contains("frames")) {
      int frames = 0;
      if (Status s = integer(j["frames"], "frames", frames); !s.ok()) return s;
      if (frames < 1) return error("frames", "must be >= 1");
      script.frames = frames;
    }
    if (j.contains("camera")) {
      if (Status s = camera(j["camera"], script); !s.ok()) return s;
    }
    if (j.contains("events")) {
      if (Status s = events(j["events"], script); !s.ok()) return s;
    }
    return script;
  }
};

}  // namespace

std::optional<ShadingView> parseView(const std::string& name) {
  if (name == "baked") return ShadingView::kBakedOnly;
  if (name == "runtime") return ShadingView::kRuntime;
  if (name == "delta") return ShadingView::kPatchDelta;
  return std::nullopt;
}

const char* viewName(ShadingView view) {
  switch (view) {
    case ShadingView::kBakedOnly: return "baked";
    case ShadingView::kRuntime: return "runtime";
    case ShadingView::kPatchDelta: return "delta";
  }
  return "?";
}

Expected<WalkScript> readWalkScript(const std::string& path, const Scene& scene,
                                    const BakeData& bake) {
  std::ifstream file(path);
  if (!file) return Status(StatusCode::kNotFound, path + ": cannot open");
  Json j;
  try {
    file >> j;
  } catch (const Json::exception& e) {
    return Status(StatusCode::kInvalidInput, path + ": not valid JSON: " + e.what());
  }
  return ScriptReader{path, scene, bake}.read(j);
}

Status checkEventFrames(const WalkScript& script, const std::string& path, int frames) {
  for (const WalkEvent& event : script.events) {
    if (event.frame >= frames) {
      return Status(StatusCode::kInvalidInput,
                    path + ": " + event.field + ".frame: " + std::to_string(event.frame) +
                        " is past the last frame " + std::to_string(frames - 1));
    }
  }
  return Status();
}

}  // namespace svit::walk

// glTF nodes (hierarchy, local transforms, extras.svit.dynamic) and
// KHR_lights_punctual lights. Lights are read from the extension's JSON
// value, not tinygltf's parsed copy, because tinygltf silently keeps the
// default intensity when the value is not a number.

#include <cmath>
#include <limits>

#include <tiny_gltf.h>

#include "glm_interop.h"
#include "gltf_import_context.h"
#include "numeric.h"
#include "transforms.h"

namespace svit::gltf {
namespace {

Status invalid(std::string message) {
  return Status(StatusCode::kInvalidInput, std::move(message));
}

Status readDoubles(const std::vector<double>& values, size_t expected, const std::string& what,
                   double* out) {
  if (values.size() != expected) {
    return invalid(what + " has " + std::to_string(values.size()) + " values, expected " +
                   std::to_string(expected));
  }
  for (size_t i = 0; i < expected; ++i) {
    if (!std::isfinite(values[i])) {
      return invalid(what + "[" + std::to_string(i) + "] = " + std::to_string(values[i]) +
                     " is not finite");
    }
    out[i] = values[i];
  }
  return Status();
}

Status readLocalTransform(const tinygltf::Node& source, const std::string& what, Node& node) {
  if (!source.matrix.empty()) {
    double m[16];
    if (Status s = readDoubles(source.matrix, 16, what + ": matrix", m); !s.ok()) return s;
    for (int i = 0; i < 16; ++i) node.parent_from_node.m[size_t(i)] = float(m[i]);
    node.has_trs = false;
    return Status();
  }
  double t[3] = {0, 0, 0}, r[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
  if (!source.translation.empty()) {
    if (Status st = readDoubles(source.translation, 3, what + ": translation", t); !st.ok())
      return st;
  }
  if (!source.rotation.empty()) {
    if (Status st = readDoubles(source.rotation, 4, what + ": rotation", r); !st.ok()) return st;
    const double length = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    if (!(length > 1e-6)) return invalid(what + ": rotation quaternion has zero length");
    for (double& c : r) c /= length;  // exporters write 6-digit quaternions
  }
  if (!source.scale.empty()) {
    if (Status st = readDoubles(source.scale, 3, what + ": scale", s); !st.ok()) return st;
  }
  node.translation = {float(t[0]), float(t[1]), float(t[2])};
  node.rotation = {float(r[0]), float(r[1]), float(r[2]), float(r[3])};
  node.scale = {float(s[0]), float(s[1]), float(s[2])};
  node.parent_from_node =
      fromGlm(composeTrs(toGlm(node.translation), toGlm(node.rotation), toGlm(node.scale)));
  return Status();
}

Status readDynamicMark(const tinygltf::Node& source, const std::string& what, bool& dynamic) {
  if (!source.extras.IsObject() || !source.extras.Has("svit")) return Status();
  const tinygltf::Value& svit_extras = source.extras.Get("svit");
  if (!svit_extras.IsObject() || !svit_extras.Has("dynamic")) return Status();
  const tinygltf::Value& mark = svit_extras.Get("dynamic");
  if (!mark.IsBool()) return invalid(what + ": extras.svit.dynamic must be true or false");
  dynamic = mark.Get<bool>();
  return Status();
}

// Reads a number member of a light; `present` false when absent.
Status lightNumber(const tinygltf::Value& object, const char* key, const std::string& what,
                   double fallback, double& out) {
  out = fallback;
  if (!object.Has(key)) return Status();
  const tinygltf::Value& v = object.Get(key);
  if (!v.IsNumber()) return invalid(what + ": " + key + " is not a number");
  out = v.GetNumberAsDouble();
  // Values beyond float range turn into infinity when stored as float.
  if (!std::isfinite(out) || std::abs(out) > double(std::numeric_limits<float>::max())) {
    return invalid(what + ": " + key + " " + std::to_string(out) +
                   " is not finite (as a 32-bit float)");
  }
  return Status();
}

Status readLight(const tinygltf::Value& object, const std::string& what, Light& light) {
  if (!object.IsObject()) return invalid(what + ": is not a JSON object");
  const std::string type = object.Has("type") && object.Get("type").IsString()
                               ? object.Get("type").Get<std::string>()
                               : "";
  if (type == "point") {
    light.type = LightType::kPoint;
  } else if (type == "spot") {
    light.type = LightType::kSpot;
  } else if (type == "directional") {
    light.type = LightType::kDirectional;
  } else {
    return invalid(what + ": type '" + type + "' is not point, spot or directional");
  }
  if (object.Has("name") && object.Get("name").IsString())
    light.name = object.Get("name").Get<std::string>();
  double intensity = 1.0;
  if (Status s = lightNumber(object, "intensity", what, 1.0, intensity); !s.ok()) return s;
  if (intensity < 0)
    return invalid(what + ": intensity " + std::to_string(intensity) + " is negative");
  light.intensity = float(intensity);
  double range = 0.0;
  if (Status s = lightNumber(object, "range", what, 0.0, range); !s.ok()) return s;
  if (range < 0) return invalid(what + ": range " + std::to_string(range) + " is negative");
  light.range_m = float(range);
  if (object.Has("color")) {
    const tinygltf::Value& color = object.Get("color");
    if (!color.IsArray() || color.ArrayLen() != 3)
      return invalid(what + ": color must have 3 numbers");
    float rgb[3];
    for (int i = 0; i < 3; ++i) {
      const tinygltf::Value& c = color.Get(i);
      const double v = c.IsNumber() ? c.GetNumberAsDouble() : -1.0;
      if (!std::isfinite(v) || v < 0) {
        return invalid(what + ": color[" + std::to_string(i) + "] must be a finite number >= 0");
      }
      rgb[i] = float(v);
    }
    light.color = {rgb[0], rgb[1], rgb[2]};
  }
  if (light.type == LightType::kSpot) {
    if (!object.Has("spot") || !object.Get("spot").IsObject()) {
      return invalid(what + ": spot light without a 'spot' object");
    }
    double inner = 0, outer = kPi / 4;  // glTF default
    const tinygltf::Value& spot = object.Get("spot");
    if (Status s = lightNumber(spot, "innerConeAngle", what + ": spot", 0.0, inner); !s.ok())
      return s;
    if (Status s = lightNumber(spot, "outerConeAngle", what + ": spot", outer, outer); !s.ok())
      return s;
    if (!(inner >= 0 && inner < outer && outer <= kPi / 2)) {
      return invalid(what + ": spot cone angles inner " + std::to_string(inner) + ", outer " +
                     std::to_string(outer) + " need 0 <= inner < outer <= pi/2");
    }
    light.inner_cone_rad = float(inner);
    light.outer_cone_rad = float(outer);
  }
  return Status();
}

// Light definitions of KHR_lights_punctual, placed by the nodes that use them.
Status readLightDefinitions(const tinygltf::Model& model, const std::string& path,
                            std::vector<Light>& definitions) {
  auto lights_ext = model.extensions.find("KHR_lights_punctual");
  if (lights_ext == model.extensions.end() || !lights_ext->second.Has("lights")) return Status();
  const tinygltf::Value& lights = lights_ext->second.Get("lights");
  if (!lights.IsArray()) return invalid(path + ": KHR_lights_punctual.lights is not an array");
  for (size_t i = 0; i < lights.ArrayLen(); ++i) {
    const tinygltf::Value& object = lights.Get(int(i));
    std::string what = path + ": light " + std::to_string(i);
    if (object.IsObject() && object.Has("name") && object.Get("name").IsString()) {
      what += " '" + object.Get("name").Get<std::string>() + "'";
    }
    Light light;
    if (Status s = readLight(object, what, light); !s.ok()) return s;
    if (light.name.empty()) light.name = "light " + std::to_string(i);
    definitions.push_back(light);
  }
  return Status();
}

// The light node `i` places, if any, appended to the scene's lights.
Status placeNodeLight(const tinygltf::Node& source, size_t i, const std::string& what,
                      const std::vector<Light>& definitions, Scene& scene) {
  auto ext = source.extensions.find("KHR_lights_punctual");
  if (ext == source.extensions.end() || !ext->second.Has("light")) return Status();
  const tinygltf::Value& index = ext->second.Get("light");
  const int light_index = index.IsInt() ? index.Get<int>() : -1;
  if (light_index < 0 || size_t(light_index) >= definitions.size()) {
    return invalid(what + ": KHR_lights_punctual light " + std::to_string(light_index) +
                   " does not exist (file has " + std::to_string(definitions.size()) + ")");
  }
  Light light = definitions[size_t(light_index)];
  light.node = int(i);
  scene.lights.push_back(light);
  return Status();
}

Status readNode(const tinygltf::Model& model, size_t i, const std::string& path,
                const std::vector<Light>& definitions, Scene& scene) {
  const tinygltf::Node& source = model.nodes[i];
  const std::string what = path + ": " + nodeLabel(model, int(i));
  Node& node = scene.nodes[i];
  node.name = source.name;
  if (source.mesh >= 0 && size_t(source.mesh) >= model.meshes.size()) {
    return invalid(what + ": mesh " + std::to_string(source.mesh) + " does not exist");
  }
  node.mesh = source.mesh;
  if (Status s = readLocalTransform(source, what, node); !s.ok()) return s;
  if (Status s = readDynamicMark(source, what, node.dynamic); !s.ok()) return s;
  for (int child : source.children) {
    if (child < 0 || size_t(child) >= model.nodes.size() || size_t(child) == i) {
      return invalid(what + ": child " + std::to_string(child) + " is not another node");
    }
    node.children.push_back(child);
  }
  return placeNodeLight(source, i, what, definitions, scene);
}

// Sets every node's parent; a node listed as the child of two is an error.
Status linkParents(const tinygltf::Model& model, const std::string& path, Scene& scene) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    for (int child : scene.nodes[i].children) {
      Node& c = scene.nodes[size_t(child)];
      if (c.parent >= 0) {
        return invalid(path + ": " + nodeLabel(model, child) + " has two parents (" +
                       nodeLabel(model, c.parent) + " and " + nodeLabel(model, int(i)) + ")");
      }
      c.parent = int(i);
    }
  }
  return Status();
}

// With at most one parent each, a cycle is a chain that never reaches a root.
Status checkNoCycles(const tinygltf::Model& model, const std::string& path, const Scene& scene) {
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    int n = int(i);
    size_t steps = 0;
    while (n >= 0 && steps <= scene.nodes.size()) {
      n = scene.nodes[size_t(n)].parent;
      ++steps;
    }
    if (n >= 0) return invalid(path + ": " + nodeLabel(model, int(i)) + " is part of a cycle");
  }
  return Status();
}

// The roots of the active glTF scene, or every parentless node when the file has no scene.
Status findSceneRoots(const tinygltf::Model& model, const std::string& path, const Scene& scene,
                      std::vector<int>& scene_roots) {
  scene_roots.clear();
  const int active = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
  if (active < 0) {
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
      if (scene.nodes[i].parent < 0) scene_roots.push_back(int(i));
    }
    return Status();
  }
  if (size_t(active) >= model.scenes.size()) {
    return invalid(path + ": scene " + std::to_string(active) + " does not exist");
  }
  for (int root : model.scenes[size_t(active)].nodes) {
    if (root < 0 || size_t(root) >= scene.nodes.size()) {
      return invalid(path + ": scene " + std::to_string(active) + ": node " + std::to_string(root) +
                     " does not exist");
    }
    if (scene.nodes[size_t(root)].parent >= 0) {
      return invalid(path + ": scene " + std::to_string(active) + ": " + nodeLabel(model, root) +
                     " is not a root node");
    }
    scene_roots.push_back(root);
  }
  return Status();
}

}  // namespace

Status importNodesAndLights(ImportContext& context, std::vector<int>& scene_roots) {
  const tinygltf::Model& model = context.model;
  Scene& scene = context.scene;
  const std::string& path = context.path;
  std::vector<Light> definitions;
  if (Status s = readLightDefinitions(model, path, definitions); !s.ok()) return s;
  scene.nodes.resize(model.nodes.size());
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (Status s = readNode(model, i, path, definitions, scene); !s.ok()) return s;
  }
  if (Status s = linkParents(model, path, scene); !s.ok()) return s;
  if (Status s = checkNoCycles(model, path, scene); !s.ok()) return s;
  return findSceneRoots(model, path, scene, scene_roots);
}

}  // namespace svit::gltf

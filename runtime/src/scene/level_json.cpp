// level.json: a glTF plus sun, sky, extra lights, primitive objects, excluded
// and dynamic nodes, object paths and camera paths (docs/level-format.md).
// Strict: unknown fields and values of the wrong type or range are errors
// naming the field, since a typo that is silently ignored costs a level
// designer an overnight bake.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "glm_interop.h"
#include "numeric.h"
#include "scene_finalize.h"
#include "svit/level.h"
#include "transforms.h"

namespace svit {
namespace {

using Json = nlohmann::json;

// Sphere tessellation of level objects: `segments` around the equator and
// segments / 2 from pole to pole.
constexpr int kDefaultSphereSegments = 24;
constexpr int kMinSphereSegments = 4;
constexpr int kMaxSphereSegments = 256;

// Appends triangle (a, b, c) of a convex mesh centred on the origin, wound
// counter-clockwise seen from outside (glTF's front face).
void addOutwardTriangle(Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  const glm::vec3 pa = toGlm(mesh.positions[a]), pb = toGlm(mesh.positions[b]),
                  pc = toGlm(mesh.positions[c]);
  const bool outward = glm::dot(glm::cross(pb - pa, pc - pa), pa + pb + pc) > 0;
  mesh.indices.insert(mesh.indices.end(), {a, outward ? b : c, outward ? c : b});
}

// A UV sphere of `radius` metres with smooth normals; poles on +-Y.
void buildSphere(float radius, int segments, Mesh& mesh) {
  const int rings = segments / 2;
  mesh.positions.push_back({0, radius, 0});
  mesh.normals.push_back({0, 1, 0});
  for (int k = 1; k < rings; ++k) {
    const double polar = kPi * k / rings;
    for (int i = 0; i < segments; ++i) {
      const double azimuth = 2 * kPi * i / segments;
      const Vec3 n{float(std::sin(polar) * std::cos(azimuth)), float(std::cos(polar)),
                   float(std::sin(polar) * std::sin(azimuth))};
      mesh.normals.push_back(n);
      mesh.positions.push_back({radius * n.x, radius * n.y, radius * n.z});
    }
  }
  const uint32_t south = uint32_t(mesh.positions.size());
  mesh.positions.push_back({0, -radius, 0});
  mesh.normals.push_back({0, -1, 0});
  const auto ring = [&](int k, int i) { return uint32_t(1 + (k - 1) * segments + (i % segments)); };
  for (int i = 0; i < segments; ++i) {
    addOutwardTriangle(mesh, 0, ring(1, i), ring(1, i + 1));
    for (int k = 1; k + 1 < rings; ++k) {
      addOutwardTriangle(mesh, ring(k, i), ring(k + 1, i), ring(k + 1, i + 1));
      addOutwardTriangle(mesh, ring(k, i), ring(k + 1, i + 1), ring(k, i + 1));
    }
    addOutwardTriangle(mesh, south, ring(rings - 1, i), ring(rings - 1, i + 1));
  }
}

// An axis-aligned box of `size` metres centred on the origin, flat normals.
void buildBox(const Vec3& size, Mesh& mesh) {
  const glm::vec3 half = 0.5f * toGlm(size);
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 normal(0);
      normal[axis] = sign;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const uint32_t first = uint32_t(mesh.positions.size());
      for (int corner = 0; corner < 4; ++corner) {
        glm::vec3 p = normal * half;
        p[u] = (corner == 1 || corner == 2 ? 1.0f : -1.0f) * half[u];
        p[v] = (corner >= 2 ? 1.0f : -1.0f) * half[v];
        mesh.positions.push_back(fromGlm(p));
        mesh.normals.push_back(fromGlm(normal));
      }
      addOutwardTriangle(mesh, first, first + 1, first + 2);
      addOutwardTriangle(mesh, first, first + 2, first + 3);
    }
  }
}

// Takes `node` and its subtree out of the level: finalizeScene never reaches
// it, so it has no instance and lights on it are dropped.
void detachNode(Scene& scene, std::vector<int>& roots, int node) {
  Node& n = scene.nodes[size_t(node)];
  std::vector<int>& siblings = n.parent >= 0 ? scene.nodes[size_t(n.parent)].children : roots;
  siblings.erase(std::remove(siblings.begin(), siblings.end(), node), siblings.end());
  n.parent = -1;
}

// Carries the level path so every error names file and field.
struct LevelReader {
  std::string path;
  size_t gltf_nodes = 0;       ///< nodes of the glTF; objects and hung lights come after them
  std::vector<char> excluded;  ///< per node: named in `exclude` (its subtree is out too)

  Status error(const std::string& field, const std::string& problem) const {
    return Status(StatusCode::kInvalidInput, path + ": " + field + ": " + problem);
  }

  Status checkKeys(const Json& object, const std::string& field,
                   const std::set<std::string>& allowed) const {
    if (!object.is_object()) return error(field.empty() ? "level" : field, "must be a JSON object");
    for (const auto& item : object.items()) {
      if (!allowed.count(item.key())) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        return error(field.empty() ? item.key() : field + "." + item.key(),
                     "unknown field (expected one of: " + list + ")");
      }
    }
    return Status();
  }

  Status number(const Json& value, const std::string& field, double& out) const {
    if (!value.is_number()) return error(field, "must be a number");
    out = value.get<double>();
    if (!std::isfinite(out) || std::abs(out) > double(std::numeric_limits<float>::max())) {
      return error(field, "is not finite (as a 32-bit float)");
    }
    return Status();
  }

  Status nonNegative(const Json& value, const std::string& field, float& out) const {
    double v = 0;
    if (Status s = number(value, field, v); !s.ok()) return s;
    if (v < 0) return error(field, std::to_string(v) + " is negative");
    out = float(v);
    return Status();
  }

  Status vector(const Json& value, const std::string& field, size_t n, float* out) const {
    if (!value.is_array() || value.size() != n) {
      return error(field, "must be an array of " + std::to_string(n) + " numbers");
    }
    for (size_t i = 0; i < n; ++i) {
      double v = 0;
      if (Status s = number(value[i], field + "[" + std::to_string(i) + "]", v); !s.ok()) return s;
      out[i] = float(v);
    }
    return Status();
  }

  Status vec3(const Json& value, const std::string& field, Vec3& out) const {
    float v[3];
    if (Status s = vector(value, field, 3, v); !s.ok()) return s;
    out = {v[0], v[1], v[2]};
    return Status();
  }

  Status direction(const Json& value, const std::string& field, Vec3& out) const {
    if (Status s = vec3(value, field, out); !s.ok()) return s;
    const double length =
        std::sqrt(double(out.x) * out.x + double(out.y) * out.y + double(out.z) * out.z);
    if (!(length > 1e-12)) return error(field, "has zero length");
    out = {float(out.x / length), float(out.y / length), float(out.z / length)};
    return Status();
  }

  // A colour or luminance: one number (grey) or [r, g, b], each >= 0.
  Status rgb(const Json& value, const std::string& field, Rgb& out) const {
    if (value.is_number()) {
      float grey = 0;
      if (Status s = nonNegative(value, field, grey); !s.ok()) return s;
      out = {grey, grey, grey};
      return Status();
    }
    float v[3];
    if (Status s = vector(value, field, 3, v); !s.ok()) return s;
    for (int i = 0; i < 3; ++i) {
      if (v[i] < 0) return error(field + "[" + std::to_string(i) + "]", "is negative");
    }
    out = {v[0], v[1], v[2]};
    return Status();
  }

  Status quat(const Json& value, const std::string& field, Quat& out) const {
    float v[4];
    if (Status s = vector(value, field, 4, v); !s.ok()) return s;
    const double length = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] +
                                    double(v[2]) * v[2] + double(v[3]) * v[3]);
    if (!(length > 1e-6)) return error(field, "quaternion has zero length");
    out = {float(v[0] / length), float(v[1] / length), float(v[2] / length), float(v[3] / length)};
    return Status();
  }

  Status boolean(const Json& value, const std::string& field, bool& out) const {
    if (!value.is_boolean()) return error(field, "must be true or false");
    out = value.get<bool>();
    return Status();
  }

  Status string(const Json& value, const std::string& field, std::string& out) const {
    if (!value.is_string()) return error(field, "must be a string");
    out = value.get<std::string>();
    return Status();
  }

  // A node named by a string (the first node of that name, in file order) or
  // by its index in the glTF's `nodes` array (for files whose nodes have no
  // names). Nodes left out by `exclude` cannot be named.
  Status nodeByName(const Json& value, const std::string& field, const Scene& scene,
                    int& node) const {
    const std::string file = std::filesystem::path(scene.gltf_path).filename().string();
    if (value.is_number_integer()) {
      const bool in_range = value.is_number_unsigned() && value.get<uint64_t>() < gltf_nodes;
      if (!in_range) {
        return Status(StatusCode::kNotFound, path + ": " + field + ": no node " + value.dump() +
                                                 " in " + file + " (it has " +
                                                 std::to_string(gltf_nodes) + " nodes)");
      }
      node = int(value.get<uint64_t>());
    } else {
      if (!value.is_string()) return error(field, "must be a node name or a node index");
      const std::string name = value.get<std::string>();
      node = scene.findNode(name);
      if (node < 0) {
        return Status(StatusCode::kNotFound,
                      path + ": " + field + ": no node named '" + name + "' in " + file);
      }
    }
    for (int n = node; n >= 0; n = scene.nodes[size_t(n)].parent) {
      if (size_t(n) < excluded.size() && excluded[size_t(n)]) {
        return error(field, "node " + value.dump() + " is left out by 'exclude'");
      }
    }
    return Status();
  }

  Status readSun(const Json& j, Sun& sun) const {
    if (Status s = checkKeys(
            j, "sun", {"direction_to_sun", "illuminance_lux", "angular_radius_rad", "color"});
        !s.ok())
      return s;
    if (!j.contains("direction_to_sun")) return error("sun.direction_to_sun", "is required");
    if (!j.contains("illuminance_lux")) return error("sun.illuminance_lux", "is required");
    if (Status s = direction(j["direction_to_sun"], "sun.direction_to_sun", sun.direction_to_sun);
        !s.ok())
      return s;
    if (Status s = nonNegative(j["illuminance_lux"], "sun.illuminance_lux", sun.illuminance_lux);
        !s.ok())
      return s;
    if (j.contains("angular_radius_rad")) {
      if (Status s = nonNegative(j["angular_radius_rad"], "sun.angular_radius_rad",
                                 sun.angular_radius_rad);
          !s.ok())
        return s;
      if (sun.angular_radius_rad > 0.5f) return error("sun.angular_radius_rad", "must be <= 0.5");
    }
    if (j.contains("color")) {
      if (Status s = rgb(j["color"], "sun.color", sun.color); !s.ok()) return s;
    }
    sun.enabled = true;
    return Status();
  }

  Status readSky(const Json& j, Sky& sky) const {
    if (Status s = checkKeys(
            j, "sky", {"model", "zenith_luminance", "horizon_luminance", "ground_luminance"});
        !s.ok())
      return s;
    std::string model;
    if (!j.contains("model"))
      return error("sky.model", "is required (\"uniform\" or \"gradient\")");
    if (Status s = string(j["model"], "sky.model", model); !s.ok()) return s;
    if (model == "uniform") {
      sky.model = SkyModel::kUniform;
      if (j.contains("horizon_luminance") || j.contains("ground_luminance")) {
        return error("sky", "a uniform sky has only zenith_luminance");
      }
    } else if (model == "gradient") {
      sky.model = SkyModel::kGradient;
    } else {
      return error("sky.model", "'" + model + "' is not \"uniform\" or \"gradient\"");
    }
    if (!j.contains("zenith_luminance")) return error("sky.zenith_luminance", "is required");
    if (Status s = rgb(j["zenith_luminance"], "sky.zenith_luminance", sky.zenith_luminance);
        !s.ok())
      return s;
    sky.horizon_luminance = sky.zenith_luminance;
    if (j.contains("horizon_luminance")) {
      if (Status s = rgb(j["horizon_luminance"], "sky.horizon_luminance", sky.horizon_luminance);
          !s.ok())
        return s;
    }
    if (j.contains("ground_luminance")) {
      if (Status s = rgb(j["ground_luminance"], "sky.ground_luminance", sky.ground_luminance);
          !s.ok())
        return s;
    }
    return Status();
  }

  // The light's type, and that exactly the keys of that type are given.
  Status readLightType(const Json& j, const std::string& field, Light& light) const {
    std::string type;
    if (!j.contains("type")) return error(field + ".type", "is required");
    if (Status s = string(j["type"], field + ".type", type); !s.ok()) return s;
    std::set<std::string> required, forbidden;
    if (type == "point") {
      light.type = LightType::kPoint;
      required = {"position", "intensity_cd"};
      forbidden = {"direction", "illuminance_lux", "inner_cone_rad", "outer_cone_rad"};
    } else if (type == "spot") {
      light.type = LightType::kSpot;
      required = {"position", "direction", "intensity_cd"};
      forbidden = {"illuminance_lux"};
    } else if (type == "directional") {
      light.type = LightType::kDirectional;
      required = {"direction", "illuminance_lux"};
      forbidden = {"position", "intensity_cd", "range_m", "inner_cone_rad", "outer_cone_rad"};
    } else {
      return error(field + ".type", "'" + type + "' is not point, spot or directional");
    }
    for (const std::string& key : required) {
      if (!j.contains(key)) return error(field + "." + key, "is required for a " + type + " light");
    }
    for (const std::string& key : forbidden) {
      if (j.contains(key))
        return error(field + "." + key, "does not apply to a " + type + " light");
    }
    return Status();
  }

  Status readSpotCone(const Json& j, const std::string& field, Light& light) const {
    if (j.contains("inner_cone_rad")) {
      if (Status s =
              nonNegative(j["inner_cone_rad"], field + ".inner_cone_rad", light.inner_cone_rad);
          !s.ok())
        return s;
    }
    if (j.contains("outer_cone_rad")) {
      if (Status s =
              nonNegative(j["outer_cone_rad"], field + ".outer_cone_rad", light.outer_cone_rad);
          !s.ok())
        return s;
    }
    if (!(light.inner_cone_rad < light.outer_cone_rad && light.outer_cone_rad <= float(kPi / 2))) {
      return error(field, "spot cone angles need 0 <= inner_cone_rad < outer_cone_rad <= pi/2");
    }
    return Status();
  }

  // Name, place, colour, intensity and range, as far as given.
  Status readLightValues(const Json& j, const std::string& field, Light& light) const {
    light.name = field;
    if (j.contains("name")) {
      if (Status s = string(j["name"], field + ".name", light.name); !s.ok()) return s;
    }
    if (j.contains("position")) {
      if (Status s = vec3(j["position"], field + ".position", light.position); !s.ok()) return s;
    }
    if (j.contains("direction")) {
      if (Status s = direction(j["direction"], field + ".direction", light.direction); !s.ok())
        return s;
    }
    if (j.contains("color")) {
      if (Status s = rgb(j["color"], field + ".color", light.color); !s.ok()) return s;
    }
    const char* intensity_key =
        light.type == LightType::kDirectional ? "illuminance_lux" : "intensity_cd";
    if (Status s = nonNegative(j[intensity_key], field + "." + intensity_key, light.intensity);
        !s.ok())
      return s;
    if (j.contains("range_m")) {
      if (Status s = nonNegative(j["range_m"], field + ".range_m", light.range_m); !s.ok())
        return s;
    }
    return Status();
  }

  Status readLight(const Json& j, const std::string& field, Scene& scene, Light& light) const {
    if (Status s = checkKeys(
            j, field,
            {"name", "type", "position", "direction", "color", "intensity_cd", "illuminance_lux",
             "range_m", "inner_cone_rad", "outer_cone_rad", "dynamic", "node"});
        !s.ok()) {
      return s;
    }
    if (Status s = readLightType(j, field, light); !s.ok()) return s;
    if (Status s = readLightValues(j, field, light); !s.ok()) return s;
    if (light.type == LightType::kSpot) {
      if (Status s = readSpotCone(j, field, light); !s.ok()) return s;
    }
    if (j.contains("dynamic")) {
      if (Status s = boolean(j["dynamic"], field + ".dynamic", light.dynamic); !s.ok()) return s;
    }
    if (j.contains("node")) {
      int parent = -1;
      if (Status s = nodeByName(j["node"], field + ".node", scene, parent); !s.ok()) return s;
      hangOnNode(scene, parent, light);
    }
    return Status();
  }

  // Hangs `light` on a new child of `parent` placed at the light's position
  // and turned so that its -Z axis (the way glTF lights shine) is the
  // light's direction; finalizeScene then places it in the world, and moves
  // it with the parent.
  static void hangOnNode(Scene& scene, int parent, Light& light) {
    const Vec3 d = light.direction;
    // Shortest rotation from (0, 0, -1) to d: (axis (0,0,-1) x d, 1 + cos).
    glm::quat q(1.0f + -d.z, d.y, -d.x, 0.0f);      // glm order: w, x, y, z
    if (!(q.w > 1e-6f)) q = glm::quat(0, 1, 0, 0);  // d = +Z: half a turn about X
    q = glm::normalize(q);
    Node node;
    node.name = light.name;
    node.parent = parent;
    node.translation = light.position;
    node.rotation = fromGlm(q);
    node.parent_from_node = fromGlm(composeTrs(toGlm(node.translation), q, glm::vec3(1)));
    light.node = int(scene.nodes.size());
    scene.nodes[size_t(parent)].children.push_back(light.node);
    scene.nodes.push_back(std::move(node));
  }

  // A primitive prop (docs/level-format.md "objects"): appends a mesh, its
  // material and a root node holding it.
  Status readObject(const Json& j, const std::string& field, Scene& scene, int& node_out) const {
    if (Status s =
            checkKeys(j, field,
                      {"name", "shape", "radius_m", "size_m", "segments", "albedo",
                       "emissive_luminance", "double_sided", "translation", "rotation", "dynamic"});
        !s.ok()) {
      return s;
    }
    std::string name, shape;
    if (Status s = readObjectName(j, field, scene, name); !s.ok()) return s;
    if (Status s = readObjectShape(j, field, shape); !s.ok()) return s;
    Material material;
    if (Status s = readObjectMaterial(j, field, name, material); !s.ok()) return s;
    Mesh mesh;
    mesh.name = name;
    if (Status s = buildObjectMesh(j, field, shape, mesh); !s.ok()) return s;
    const uint32_t material_index = uint32_t(scene.materials.size());
    const size_t triangles = mesh.triangleCount();
    mesh.triangle_material.assign(triangles, material_index);
    mesh.triangle_albedo.assign(triangles, material.base_color);
    mesh.triangle_emission.assign(triangles, material.emissive_luminance);
    for (size_t t = 0; t < triangles; ++t) mesh.triangle_source.push_back({0, uint32_t(t)});
    Node node;
    if (Status s = readObjectNode(j, field, name, node); !s.ok()) return s;
    node.mesh = int(scene.meshes.size());
    scene.materials.push_back(std::move(material));
    scene.meshes.push_back(std::move(mesh));
    node_out = int(scene.nodes.size());
    scene.nodes.push_back(std::move(node));
    return Status();
  }

  Status readObjectName(const Json& j, const std::string& field, const Scene& scene,
                        std::string& name) const {
    if (!j.contains("name"))
      return error(field + ".name", "is required (paths name the object by it)");
    if (Status s = string(j["name"], field + ".name", name); !s.ok()) return s;
    if (name.empty()) return error(field + ".name", "must not be empty");
    if (scene.findNode(name) >= 0)
      return error(field + ".name", "a node named '" + name + "' already exists");
    return Status();
  }

  // "sphere" or "box", with the size fields that shape takes and no others.
  Status readObjectShape(const Json& j, const std::string& field, std::string& shape) const {
    if (!j.contains("shape")) return error(field + ".shape", "is required (\"sphere\" or \"box\")");
    if (Status s = string(j["shape"], field + ".shape", shape); !s.ok()) return s;
    std::set<std::string> required, forbidden;
    if (shape == "sphere") {
      required = {"radius_m"};
      forbidden = {"size_m"};
    } else if (shape == "box") {
      required = {"size_m"};
      forbidden = {"radius_m", "segments"};
    } else {
      return error(field + ".shape", "'" + shape + "' is not \"sphere\" or \"box\"");
    }
    for (const std::string& key : required) {
      if (!j.contains(key)) return error(field + "." + key, "is required for a " + shape);
    }
    for (const std::string& key : forbidden) {
      if (j.contains(key)) return error(field + "." + key, "does not apply to a " + shape);
    }
    return Status();
  }

  Status readObjectMaterial(const Json& j, const std::string& field, const std::string& name,
                            Material& material) const {
    material.name = name;
    material.base_color = {0.8f, 0.8f, 0.8f};
    if (j.contains("albedo")) {
      if (Status s = rgb(j["albedo"], field + ".albedo", material.base_color); !s.ok()) return s;
      const float c[3] = {material.base_color.r, material.base_color.g, material.base_color.b};
      for (int i = 0; i < 3; ++i) {
        if (c[i] > 1)
          return error(field + ".albedo",
                       "must be <= 1 (a surface reflects at most what it receives)");
      }
    }
    if (j.contains("emissive_luminance")) {
      if (Status s = rgb(j["emissive_luminance"], field + ".emissive_luminance",
                         material.emissive_luminance);
          !s.ok())
        return s;
    }
    if (j.contains("double_sided")) {
      if (Status s = boolean(j["double_sided"], field + ".double_sided", material.double_sided);
          !s.ok())
        return s;
    }
    return Status();
  }

  Status buildObjectMesh(const Json& j, const std::string& field, const std::string& shape,
                         Mesh& mesh) const {
    if (shape == "sphere") {
      float radius = 0;
      if (Status s = positiveLength(j["radius_m"], field + ".radius_m", radius); !s.ok()) return s;
      int segments = kDefaultSphereSegments;
      if (Status s = sphereSegments(j, field, segments); !s.ok()) return s;
      buildSphere(radius, segments, mesh);
      return Status();
    }
    Vec3 size{};
    if (Status s = boxSize(j["size_m"], field + ".size_m", size); !s.ok()) return s;
    buildBox(size, mesh);
    return Status();
  }

  Status sphereSegments(const Json& j, const std::string& field, int& segments) const {
    if (!j.contains("segments")) return Status();
    const Json& v = j["segments"];
    if (!v.is_number_integer()) return error(field + ".segments", "must be an integer");
    if (!v.is_number_unsigned() || v.get<uint64_t>() < uint64_t(kMinSphereSegments) ||
        v.get<uint64_t>() > uint64_t(kMaxSphereSegments)) {
      return error(field + ".segments", v.dump() + " is outside [" +
                                            std::to_string(kMinSphereSegments) + ", " +
                                            std::to_string(kMaxSphereSegments) + "]");
    }
    segments = int(v.get<uint64_t>());
    return Status();
  }

  // One edge for a cube, or three.
  Status boxSize(const Json& value, const std::string& field, Vec3& size) const {
    if (value.is_number()) {
      float edge = 0;
      if (Status s = positiveLength(value, field, edge); !s.ok()) return s;
      size = {edge, edge, edge};
      return Status();
    }
    if (Status s = vec3(value, field, size); !s.ok()) return s;
    const float e[3] = {size.x, size.y, size.z};
    for (int i = 0; i < 3; ++i) {
      if (!(e[i] > 0)) return error(field + "[" + std::to_string(i) + "]", "must be > 0");
    }
    return Status();
  }

  Status readObjectNode(const Json& j, const std::string& field, const std::string& name,
                        Node& node) const {
    node.name = name;
    if (j.contains("translation")) {
      if (Status s = vec3(j["translation"], field + ".translation", node.translation); !s.ok())
        return s;
    }
    if (j.contains("rotation")) {
      if (Status s = quat(j["rotation"], field + ".rotation", node.rotation); !s.ok()) return s;
    }
    if (j.contains("dynamic")) {
      if (Status s = boolean(j["dynamic"], field + ".dynamic", node.dynamic); !s.ok()) return s;
    }
    node.parent_from_node =
        fromGlm(composeTrs(toGlm(node.translation), toGlm(node.rotation), glm::vec3(1)));
    return Status();
  }

  // A length > 0 that stays finite as a float.
  Status positiveLength(const Json& value, const std::string& field, float& out) const {
    double v = 0;
    if (Status s = number(value, field, v); !s.ok()) return s;
    if (!(v > 0)) return error(field, "must be > 0");
    out = float(v);
    if (!(out > 0)) return error(field, "must be > 0 as a 32-bit float");
    return Status();
  }

  Status readPath(const Json& j, const std::string& field, Scene& scene,
                  ObjectPath& path_out) const {
    if (Status s = checkKeys(j, field, {"node", "loop", "keys", "animation"}); !s.ok()) return s;
    if (!j.contains("node")) return error(field + ".node", "is required");
    if (Status s = nodeByName(j["node"], field + ".node", scene, path_out.node); !s.ok()) return s;
    if (j.contains("loop")) {
      if (Status s = boolean(j["loop"], field + ".loop", path_out.loop); !s.ok()) return s;
    }
    if (j.contains("keys") == j.contains("animation")) {
      return error(field, "needs exactly one of 'keys' and 'animation'");
    }
    if (j.contains("animation")) {
      const Json& a = j["animation"];
      if (a.is_number_integer()) {
        const long index = a.get<long>();
        if (index < 0 || size_t(index) >= scene.animations.size()) {
          return error(field + ".animation", "index " + std::to_string(index) +
                                                 " does not exist (the glTF has " +
                                                 std::to_string(scene.animations.size()) + ")");
        }
        path_out.animation = int(index);
      } else {
        std::string name;
        if (Status s = string(a, field + ".animation", name); !s.ok()) return s;
        for (size_t i = 0; i < scene.animations.size(); ++i) {
          if (scene.animations[i].name == name) path_out.animation = int(i);
        }
        if (path_out.animation < 0)
          return error(field + ".animation", "no animation named '" + name + "'");
      }
    } else {
      const Json& keys = j["keys"];
      if (!keys.is_array() || keys.empty())
        return error(field + ".keys", "must be a non-empty array");
      const Node& node = scene.nodes[size_t(path_out.node)];
      for (size_t k = 0; k < keys.size(); ++k) {
        const std::string key_field = field + ".keys[" + std::to_string(k) + "]";
        if (Status s = checkKeys(keys[k], key_field, {"t_s", "translation", "rotation", "scale"});
            !s.ok())
          return s;
        PathKey key{0, node.translation, node.rotation, node.scale};
        if (!keys[k].contains("t_s")) return error(key_field + ".t_s", "is required");
        double t = 0;
        if (Status s = number(keys[k]["t_s"], key_field + ".t_s", t); !s.ok()) return s;
        key.t_s = float(t);
        if (k > 0 && !(key.t_s > path_out.keys.back().t_s))
          return error(key_field + ".t_s", "must increase");
        if (keys[k].contains("translation")) {
          if (Status s = vec3(keys[k]["translation"], key_field + ".translation", key.translation);
              !s.ok())
            return s;
        }
        if (keys[k].contains("rotation")) {
          if (Status s = quat(keys[k]["rotation"], key_field + ".rotation", key.rotation); !s.ok())
            return s;
        }
        if (keys[k].contains("scale")) {
          if (Status s = vec3(keys[k]["scale"], key_field + ".scale", key.scale); !s.ok()) return s;
        }
        path_out.keys.push_back(key);
      }
    }
    // A node with a path moves: the path marks it dynamic.
    scene.nodes[size_t(path_out.node)].dynamic = true;
    return Status();
  }

  Status readCameraPath(const Json& j, const std::string& field, CameraPath& camera) const {
    if (Status s = checkKeys(j, field, {"name", "loop", "keys"}); !s.ok()) return s;
    camera.name = field;
    if (j.contains("name")) {
      if (Status s = string(j["name"], field + ".name", camera.name); !s.ok()) return s;
    }
    if (j.contains("loop")) {
      if (Status s = boolean(j["loop"], field + ".loop", camera.loop); !s.ok()) return s;
    }
    if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty()) {
      return error(field + ".keys", "must be a non-empty array");
    }
    const Json& keys = j["keys"];
    for (size_t k = 0; k < keys.size(); ++k) {
      const std::string key_field = field + ".keys[" + std::to_string(k) + "]";
      if (Status s = checkKeys(keys[k], key_field, {"t_s", "position", "look_at", "yfov_rad"});
          !s.ok())
        return s;
      CameraKey key;
      for (const char* required : {"t_s", "position", "look_at"}) {
        if (!keys[k].contains(required)) return error(key_field + "." + required, "is required");
      }
      double t = 0;
      if (Status s = number(keys[k]["t_s"], key_field + ".t_s", t); !s.ok()) return s;
      key.t_s = float(t);
      if (k > 0 && !(key.t_s > camera.keys.back().t_s))
        return error(key_field + ".t_s", "must increase");
      if (Status s = vec3(keys[k]["position"], key_field + ".position", key.position); !s.ok())
        return s;
      if (Status s = vec3(keys[k]["look_at"], key_field + ".look_at", key.look_at); !s.ok())
        return s;
      if (key.position.x == key.look_at.x && key.position.y == key.look_at.y &&
          key.position.z == key.look_at.z) {
        return error(key_field + ".look_at", "equals position: no view direction");
      }
      if (keys[k].contains("yfov_rad")) {
        double fov = 0;
        if (Status s = number(keys[k]["yfov_rad"], key_field + ".yfov_rad", fov); !s.ok()) return s;
        if (!(fov > 0 && fov < kPi)) return error(key_field + ".yfov_rad", "must be in (0, pi)");
        key.yfov_rad = float(fov);
      } else if (k > 0) {
        key.yfov_rad = camera.keys.back().yfov_rad;
      }
      camera.keys.push_back(key);
    }
    return Status();
  }
};

Expected<Json> readLevelRoot(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status(StatusCode::kNotFound, path + ": file not found");
  std::ifstream file(path, std::ios::binary);
  if (!file || std::filesystem::is_directory(path, ec)) {
    return Status(StatusCode::kIoError, path + ": cannot open for reading");
  }
  std::stringstream text;
  text << file.rdbuf();
  Json root;
  try {
    root = Json::parse(text.str());
  } catch (const Json::exception& e) {
    return Status(StatusCode::kInvalidInput, path + ": not valid JSON: " + e.what());
  }
  return root;
}

// The level's glTF, not yet finalized: the level adds to it first.
Expected<Scene> importLevelGltf(const Json& root, const std::string& path,
                                const LoadOptions& options, LevelReader& reader,
                                std::vector<int>& roots) {
  if (!root.contains("gltf"))
    return reader.error("gltf", "is required (the glTF file of the level)");
  std::string gltf;
  if (Status s = reader.string(root["gltf"], "gltf", gltf); !s.ok()) return s;
  const std::string gltf_path =
      (std::filesystem::path(path).parent_path() / gltf).lexically_normal().string();
  Expected<Scene> imported = importGltfUnfinalized(gltf_path, options, roots);
  if (!imported.ok()) {
    return Status(imported.status().code(), path + ": gltf: " + imported.status().message());
  }
  Scene scene = std::move(imported).value();
  scene.source_path = path;
  scene.gltf_path = gltf_path;
  reader.gltf_nodes = scene.nodes.size();
  return scene;
}

// Calls read(element, "<key>[i]") for each element of the array root[key], if present.
template <typename ReadElement>
Status forEachElement(const Json& root, const char* key, const LevelReader& reader,
                      const std::string& not_array, ReadElement read) {
  if (!root.contains(key)) return Status();
  if (!root[key].is_array()) return reader.error(key, not_array);
  for (size_t i = 0; i < root[key].size(); ++i) {
    if (Status s = read(root[key][i], std::string(key) + "[" + std::to_string(i) + "]"); !s.ok())
      return s;
  }
  return Status();
}

Status readExclusions(const Json& root, LevelReader& reader, Scene& scene,
                      std::vector<int>& roots) {
  if (!root.contains("exclude")) return Status();
  std::vector<int> nodes;
  const Status listed =
      forEachElement(root, "exclude", reader, "must be an array of node names or indices",
                     [&](const Json& element, const std::string& field) {
                       int node = -1;
                       if (Status s = reader.nodeByName(element, field, scene, node); !s.ok())
                         return s;
                       nodes.push_back(node);
                       return Status();
                     });
  if (!listed.ok()) return listed;
  reader.excluded.assign(scene.nodes.size(), 0);
  for (int node : nodes) {
    reader.excluded[size_t(node)] = 1;
    detachNode(scene, roots, node);
  }
  return Status();
}

Status readObjects(const Json& root, const LevelReader& reader, Scene& scene,
                   std::vector<int>& roots) {
  return forEachElement(root, "objects", reader, "must be an array",
                        [&](const Json& element, const std::string& field) {
                          int node = -1;
                          if (Status s = reader.readObject(element, field, scene, node); !s.ok())
                            return s;
                          roots.push_back(node);
                          return Status();
                        });
}

Status readSunAndSky(const Json& root, const LevelReader& reader, Scene& scene) {
  if (root.contains("sun")) {
    if (Status s = reader.readSun(root["sun"], scene.sun); !s.ok()) return s;
  }
  if (root.contains("sky")) {
    if (Status s = reader.readSky(root["sky"], scene.sky); !s.ok()) return s;
  }
  return Status();
}

Status readLights(const Json& root, const LevelReader& reader, Scene& scene) {
  return forEachElement(root, "lights", reader, "must be an array",
                        [&](const Json& element, const std::string& field) {
                          Light light;
                          if (Status s = reader.readLight(element, field, scene, light); !s.ok())
                            return s;
                          scene.lights.push_back(light);
                          return Status();
                        });
}

Status readDynamicNodes(const Json& root, const LevelReader& reader, Scene& scene) {
  return forEachElement(root, "dynamic", reader, "must be an array of node names",
                        [&](const Json& element, const std::string& field) {
                          int node = -1;
                          if (Status s = reader.nodeByName(element, field, scene, node); !s.ok())
                            return s;
                          scene.nodes[size_t(node)].dynamic = true;
                          return Status();
                        });
}

Status readPaths(const Json& root, const LevelReader& reader, Scene& scene) {
  const Status object_paths =
      forEachElement(root, "paths", reader, "must be an array",
                     [&](const Json& element, const std::string& field) {
                       ObjectPath object_path;
                       if (Status s = reader.readPath(element, field, scene, object_path); !s.ok())
                         return s;
                       scene.object_paths.push_back(std::move(object_path));
                       return Status();
                     });
  if (!object_paths.ok()) return object_paths;
  return forEachElement(root, "camera_paths", reader, "must be an array",
                        [&](const Json& element, const std::string& field) {
                          CameraPath camera;
                          if (Status s = reader.readCameraPath(element, field, camera); !s.ok())
                            return s;
                          scene.camera_paths.push_back(std::move(camera));
                          return Status();
                        });
}

Expected<Scene> loadLevelJson(const std::string& path, const LoadOptions& options) {
  Expected<Json> parsed = readLevelRoot(path);
  if (!parsed.ok()) return parsed.status();
  const Json& root = parsed.value();
  LevelReader reader{path, 0, {}};
  if (Status s = reader.checkKeys(root, "",
                                  {"gltf", "description", "sun", "sky", "exclude", "objects",
                                   "lights", "dynamic", "paths", "camera_paths"});
      !s.ok()) {
    return s;
  }
  std::vector<int> roots;
  Expected<Scene> imported = importLevelGltf(root, path, options, reader, roots);
  if (!imported.ok()) return imported.status();
  Scene scene = std::move(imported).value();
  if (root.contains("description") && !root["description"].is_string()) {
    return reader.error("description", "must be a string");
  }
  // Exclusions first: nothing later may name an excluded node. Objects
  // next, so that lights, dynamic and paths may name them.
  if (Status s = readExclusions(root, reader, scene, roots); !s.ok()) return s;
  if (Status s = readObjects(root, reader, scene, roots); !s.ok()) return s;
  if (Status s = readSunAndSky(root, reader, scene); !s.ok()) return s;
  if (Status s = readLights(root, reader, scene); !s.ok()) return s;
  if (Status s = readDynamicNodes(root, reader, scene); !s.ok()) return s;
  if (Status s = readPaths(root, reader, scene); !s.ok()) return s;
  // finalizeScene names the glTF; the level file is what the user loaded
  // and what made it so (an `exclude` that leaves no triangles: found by
  // fuzz_level_json's check that every error names the file).
  if (Status s = finalizeScene(scene, roots); !s.ok())
    return Status(s.code(), path + ": " + s.message());
  return scene;
}

// One level.json object read alone from `text` by `read`.
template <typename Value, typename Read>
Expected<Value> parseLevelObject(const std::string& text, const std::string& origin, Read read) {
  const Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded()) {
    return Status(StatusCode::kInvalidInput, origin + ": not valid JSON: '" + text + "'");
  }
  LevelReader reader;
  reader.path = origin;
  Value value;
  if (Status s = read(reader, j, value); !s.ok()) return s;
  return value;
}

}  // namespace

Expected<Sun> parseSunJson(const std::string& text, const std::string& origin) {
  return parseLevelObject<Sun>(
      text, origin,
      [](const LevelReader& reader, const Json& j, Sun& sun) { return reader.readSun(j, sun); });
}

Expected<Sky> parseSkyJson(const std::string& text, const std::string& origin) {
  return parseLevelObject<Sky>(
      text, origin,
      [](const LevelReader& reader, const Json& j, Sky& sky) { return reader.readSky(j, sky); });
}

Expected<Scene> loadLevel(const std::string& path, const LoadOptions& options) {
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension == ".json" || extension == ".JSON") return loadLevelJson(path, options);
  if (extension == ".gltf" || extension == ".glb" || extension == ".GLTF" || extension == ".GLB") {
    return loadGltf(path, options);
  }
  return Status(StatusCode::kInvalidInput,
                path + ": unknown level type '" + extension + "' (expected .gltf, .glb or .json)");
}

}  // namespace svit

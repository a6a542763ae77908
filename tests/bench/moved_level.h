#pragma once
// A level with one of its dynamic objects made static at another place (what
// a bake of "the object moved" is compared with), and probe points on the
// floor around an object (bench_runtime_error).

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/cornell_probes.h"
#include "svit/level.h"

namespace svit::test {

/// Writes `work_dir`/`name`.json: the level at `level_path` with `node` (a
/// glTF node or a level.json object) static at `translation`/`rotation`
/// (its local TRS: the benchmarked nodes are roots). A glTF node is moved in
/// a rewritten glTF next to it. Its path and `dynamic` entry are dropped;
/// every other dynamic node stays dynamic, or with `every_object_static`
/// is made static where the level puts it (a reference for a picture that
/// shows them all). Returns the level's path.
inline std::string writeLevelWithNodeStatic(const std::string& level_path, const std::string& node,
                                            Vec3 translation, Quat rotation,
                                            const std::string& work_dir, const std::string& name,
                                            bool every_object_static = false) {
  namespace fs = std::filesystem;
  nlohmann::json level = nlohmann::json::parse(std::ifstream(level_path));
  const fs::path gltf =
      (fs::path(level_path).parent_path() / level["gltf"].get<std::string>()).lexically_normal();
  level["gltf"] = fs::absolute(gltf).string();
  fs::create_directories(work_dir);
  bool found = false;
  if (level.contains("objects")) {
    for (nlohmann::json& object : level["objects"]) {
      if (object.value("name", "") != node) continue;
      object["translation"] = {translation.x, translation.y, translation.z};
      object["rotation"] = {rotation.x, rotation.y, rotation.z, rotation.w};
      object.erase("dynamic");
      found = true;
    }
    if (every_object_static) {
      for (nlohmann::json& object : level["objects"]) object.erase("dynamic");
    }
  }
  if (!found || every_object_static) {  // move it (and clear dynamic marks) in a copy of the glTF
    Expected<Scene> scene = loadGltf(gltf.string());
    SVIT_SETUP_CHECK(scene.ok(), scene.status().message());
    const int index = scene->findNode(node);
    SVIT_SETUP_CHECK(found || index >= 0, "no node " + node);
    if (!found) {
      Node& n = scene->nodes[size_t(index)];
      n.translation = translation;
      n.rotation = rotation;
      n.has_trs = true;
      n.dynamic = false;
    }
    for (size_t i = 0; i < scene->nodes.size(); ++i) {
      if (every_object_static) scene->nodes[i].dynamic = false;
    }
    for (Instance& instance : scene->instances) {
      if (instance.node == index || every_object_static) instance.dynamic = false;
    }
    const std::string moved_gltf = work_dir + "/" + name + ".gltf";
    SVIT_SETUP_CHECK(writeGltf(*scene, moved_gltf).ok(), moved_gltf);
    level["gltf"] = fs::absolute(moved_gltf).string();
  }
  if (level.contains("dynamic")) {
    nlohmann::json kept = nlohmann::json::array();
    for (const nlohmann::json& d : level["dynamic"]) {
      if (!every_object_static && !(d.is_string() && d.get<std::string>() == node))
        kept.push_back(d);
    }
    level["dynamic"] = kept;
  }
  if (level.contains("paths")) {
    nlohmann::json kept = nlohmann::json::array();
    for (const nlohmann::json& p : level["paths"]) {
      if (!every_object_static && !(p["node"].is_string() && p["node"].get<std::string>() == node))
        kept.push_back(p);
    }
    level["paths"] = kept;
  }
  const std::string out = work_dir + "/" + name + ".json";
  std::ofstream(out) << level.dump(1) << "\n";
  return out;
}

/// An n x n grid of upward probes on the floor (the lowest point of the
/// objects) over the objects' bounds widened by `margin_m`, minus points
/// within 5 cm (across) of a triangle that touches the floor (a leg, a box's
/// base, a ball's underside: floor texels there are covered).
inline std::vector<Probe> floorProbes(const std::vector<std::vector<Vec3>>& objects, float margin_m,
                                      int n) {
  Aabb all;
  for (const std::vector<Vec3>& positions : objects) {
    const Aabb box = boundsOf(positions);
    all.min = {std::min(all.min.x, box.min.x), std::min(all.min.y, box.min.y),
               std::min(all.min.z, box.min.z)};
    all.max = {std::max(all.max.x, box.max.x), std::max(all.max.y, box.max.y),
               std::max(all.max.z, box.max.z)};
  }
  std::vector<Aabb> footprints;
  for (const std::vector<Vec3>& positions : objects) {
    for (size_t t = 0; t + 2 < positions.size(); t += 3) {
      const Aabb tri = boundsOf({positions[t], positions[t + 1], positions[t + 2]});
      if (tri.min.y < all.min.y + 0.1f) footprints.push_back(tri);
    }
  }
  std::vector<Probe> probes;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const float x = all.min.x - margin_m +
                      (all.max.x - all.min.x + 2 * margin_m) * (float(i) + 0.5f) / float(n);
      const float z = all.min.z - margin_m +
                      (all.max.z - all.min.z + 2 * margin_m) * (float(j) + 0.5f) / float(n);
      const bool covered = std::any_of(footprints.begin(), footprints.end(), [&](const Aabb& b) {
        return x > b.min.x - 0.05f && x < b.max.x + 0.05f && z > b.min.z - 0.05f &&
               z < b.max.z + 0.05f;
      });
      if (!covered) probes.push_back({{x, all.min.y, z}, {0, 1, 0}});
    }
  }
  return probes;
}

}  // namespace svit::test

#pragma once
// Helpers of the SceneRenderer tests: low-quality bakes shared across test
// processes, the levels' cameras, and pixel probes of rendered frames.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "svit/bake_file.h"
#include "svit/baker/bake.h"
#include "svit/level.h"
#include "svit/scene_renderer.h"

namespace svit::render_test {

namespace fs = std::filesystem;

struct BakedLevel {
  Scene scene;
  BakeData bake;
  std::string dir;
};

inline std::string hex(uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// The test binary's build (its file's write time): a bake cached by an
// older build of the baker is not reused.
inline std::string buildStamp() {
  std::error_code error;
  const auto written = fs::last_write_time("/proc/self/exe", error);
  return error ? "0" : hex(uint64_t(written.time_since_epoch().count()));
}

// Bakes `level_path` quickly (few passes), once per level content and test
// build across test processes (CTest runs every TEST in its own process):
// the bake goes to a directory named after the level hash and the build
// and is reused while it reads back with the same hash. bakeLevel swaps
// its output in atomically, so processes racing on a bake leave a whole one.
/// How a test bakes a level: different seeds give independent references
/// (their difference is the bakes' noise floor). A pass count, never a time
/// budget: the same bake on every machine, however loaded (a budget gave CI
/// fewer lighting passes than a developer's machine, and a noisier reference).
struct TestBake {
  uint64_t seed = 1;
  double quality = 1;
  uint32_t passes = 1;
  bool shadow_masks = true;  ///< BakeOptions::shadow_masks
  bool operator<(const TestBake& o) const {
    return std::tie(seed, quality, passes, shadow_masks) <
           std::tie(o.seed, o.quality, o.passes, o.shadow_masks);
  }
};

inline const BakedLevel& bakedLevel(const std::string& level_path, const TestBake& how = {}) {
  static std::map<std::pair<std::string, TestBake>, BakedLevel> cache;
  auto it = cache.find({level_path, how});
  if (it != cache.end()) return it->second;
  BakedLevel level;
  Expected<Scene> scene = loadLevel(level_path);
  EXPECT_TRUE(scene.ok()) << scene.status().message();
  if (!scene.ok()) return cache[{level_path, how}];
  level.scene = std::move(scene).value();
  const uint64_t hash = hashLevel(level.scene);
  const std::string name = hex(hash) + "-s" + std::to_string(how.seed) + "-q" +
                           std::to_string(int(how.quality * 1000)) + "-p" +
                           std::to_string(how.passes) + (how.shadow_masks ? "-masks" : "-nomasks") +
                           "-b" + buildStamp();
  level.dir = (fs::temp_directory_path() / "svit_scene_renderer_test" / name).string();
  Expected<BakeData> bake = readBakeFile(level.dir + "/bake.svit");
  if (!bake.ok() || bake->level_hash != hash) {
    fs::create_directories(fs::path(level.dir).parent_path());
    baker::BakeOptions options;
    options.level_path = level_path;
    options.out_dir = level.dir;
    options.quality = how.quality;
    options.passes = how.passes;
    options.seed = how.seed;
    options.shadow_masks = how.shadow_masks;
    Expected<baker::BakeResult> result = baker::bakeLevel(options, nullptr, nullptr);
    EXPECT_TRUE(result.ok()) << result.status().message();
    bake = readBakeFile(level.dir + "/bake.svit");
  }
  EXPECT_TRUE(bake.ok()) << bake.status().message();
  if (bake.ok()) level.bake = std::move(bake).value();
  return cache[{level_path, how}] = std::move(level);
}

inline std::string cornellLevel() {
  return std::string(SVIT_SOURCE_DIR) + "/samples/levels/cornell/level.json";
}
inline std::string cornellGltf() { return SVIT_CORNELL_GLTF; }

// The Cornell box with two runtime lights: a point lamp above the short box
// (0.33, 1.2, 0.38), 2 cd, and a narrow spot at (0.5, 1.5, 0) aimed at the
// back wall (z = -1.04), 5 cd, cone 0.2/0.3 rad. All static, or with the
// node `dynamic_node` (e.g. "tallBox") dynamic.
inline std::string cornellWithRuntimeLights(const std::string& dynamic_node = "") {
  const std::string name =
      dynamic_node.empty() ? "cornell_runtime_lights" : "cornell_runtime_lights_" + dynamic_node;
  const fs::path path = fs::temp_directory_path() / "svit_scene_renderer_test" / (name + ".json");
  fs::create_directories(path.parent_path());
  const std::string dynamic =
      dynamic_node.empty() ? "" : R"("dynamic": [")" + dynamic_node + R"("],)";
  std::ofstream(path) << R"({"gltf": ")" << cornellGltf() << R"(", )" << dynamic << R"(
  "lights": [
    {"name": "lamp", "type": "point", "position": [0.33, 1.2, 0.38], "color": [1, 1, 1], "intensity_cd": 2,
     "dynamic": true},
    {"name": "spot", "type": "spot", "position": [0.5, 1.5, 0.0], "direction": [0, 0, -1], "color": [1, 1, 1],
     "intensity_cd": 5, "inner_cone_rad": 0.2, "outer_cone_rad": 0.3, "dynamic": true}]})";
  return path.string();
}

inline Camera cameraOf(const Scene& scene) {
  Camera camera;
  const CameraKey& key = scene.camera_paths.at(0).keys.at(0);
  camera.position = key.position;
  camera.look_at = key.look_at;
  camera.yfov_rad = key.yfov_rad;
  return camera;
}

inline Camera cornellFrontCamera() {
  Camera camera;
  camera.position = {0, 1.0f, 3.4f};
  camera.look_at = {0, 1.0f, 0};
  camera.yfov_rad = 0.69f;
  return camera;
}

struct Pixel {
  double r = 0, g = 0, b = 0;
  double luminance() const { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
};

// Mean 8-bit colour of a (2h+1)^2 box around (x, y), clipped to the image.
inline Pixel boxMean(const std::vector<uint8_t>& rgb, int width, int height, int x, int y,
                     int h = 4) {
  Pixel sum;
  int count = 0;
  for (int j = std::max(0, y - h); j <= std::min(height - 1, y + h); ++j) {
    for (int i = std::max(0, x - h); i <= std::min(width - 1, x + h); ++i) {
      const uint8_t* p = &rgb[(size_t(j) * size_t(width) + size_t(i)) * 3];
      sum.r += p[0], sum.g += p[1], sum.b += p[2];
      ++count;
    }
  }
  if (count > 0) sum.r /= count, sum.g /= count, sum.b /= count;
  return sum;
}

// Where a world point lands in the image (rows top first), as render() projects.
inline glm::ivec2 project(const Camera& c, int width, int height, const glm::vec3& p) {
  const glm::mat4 clip_from_world =
      glm::perspective(c.yfov_rad, float(width) / float(height), c.near_m, c.far_m) *
      glm::lookAt(glm::vec3(c.position.x, c.position.y, c.position.z),
                  glm::vec3(c.look_at.x, c.look_at.y, c.look_at.z),
                  glm::vec3(c.up.x, c.up.y, c.up.z));
  const glm::vec4 clip = clip_from_world * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {int(std::lround((ndc.x * 0.5f + 0.5f) * float(width) - 0.5f)),
          int(std::lround((0.5f - ndc.y * 0.5f) * float(height) - 0.5f))};
}

// World-space centre of the named node's mesh.
inline glm::vec3 nodeCentre(const Scene& scene, const std::string& name) {
  const int node = scene.findNode(name);
  EXPECT_GE(node, 0) << name;
  for (const Instance& instance : scene.instances) {
    if (instance.node != node) continue;
    const Mesh& mesh = scene.meshes[size_t(instance.mesh)];
    glm::vec3 lo(1e30f), hi(-1e30f);
    glm::mat4 m;
    for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = instance.world_from_object.m[size_t(k)];
    for (const Vec3& p : mesh.positions) {
      const glm::vec3 w = glm::vec3(m * glm::vec4(p.x, p.y, p.z, 1.0f));
      lo = glm::min(lo, w), hi = glm::max(hi, w);
    }
    return 0.5f * (lo + hi);
  }
  ADD_FAILURE() << "no instance of node " << name;
  return glm::vec3(0);
}

inline std::string pngPath(const std::string& name) {
  return (fs::temp_directory_path() / name).string();
}

inline int maxChannelDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int worst = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
  return worst;
}

}  // namespace svit::render_test

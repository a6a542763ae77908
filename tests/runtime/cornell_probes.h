#pragma once
// Probe points on the Cornell box's floor and walls, and the comparisons the
// runtime tests and benchmark make against bakes (shared by both).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "runtime_test_util.h"
#include "svit/baked_surfaces.h"
#include "svit/level.h"
#include "svit/runtime.h"

namespace svit::test {

inline Mat4 fromGlmMat(const glm::mat4& m) {
  Mat4 out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) out.m[size_t(c * 4 + r)] = m[c][r];
  }
  return out;
}

/// World transform T * R of a root node placed at `t`, turned by `q`.
inline Mat4 placeAt(Vec3 t, Quat q) {
  return fromGlmMat(glm::translate(glm::mat4(1), glm::vec3(t.x, t.y, t.z)) *
                    glm::mat4_cast(glm::quat(q.w, q.x, q.y, q.z)));
}

// Brings the runtime to rest: updates without a budget until nothing is left.
inline bool settle(Runtime& runtime, int max_frames = 12) {
  for (int i = 0; i < max_frames; ++i) {
    const FrameStats stats = runtime.update(0);
    if (!stats.error.empty()) return false;
    if (stats.idle) return true;
  }
  return true;
}

struct Probe {
  Vec3 p, n;
};

inline Aabb boundsOf(const std::vector<Vec3>& points) {
  Aabb box;
  for (const Vec3& p : points) {
    box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
    box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
  }
  return box;
}

inline bool near(const Aabb& box, const Vec3& p, float margin) {
  return p.x > box.min.x - margin && p.x < box.max.x + margin && p.y > box.min.y - margin &&
         p.y < box.max.y + margin && p.z > box.min.z - margin && p.z < box.max.z + margin;
}

// Points on the floor and the three walls of the Cornell box, kept 5 cm
// clear of the boxes (at both places of the tall one).
inline std::vector<Probe> cornellProbes(const std::vector<Aabb>& keep_clear) {
  std::vector<Probe> probes;
  auto add = [&](Vec3 p, Vec3 n) {
    for (const Aabb& box : keep_clear) {
      if (near(box, p, 0.05f)) return;
    }
    probes.push_back({p, n});
  };
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 7; ++j) {
      const float u = -0.85f + 1.7f * float(i) / 6, v = -0.85f + 1.7f * float(j) / 6;
      add({u, 0.0f, v}, {0, 1, 0});  // floor
      if (i % 2 == 0 && j % 2 == 0) {
        const float h = 0.15f + 1.7f * float(j) / 6;
        add({u, h, -1.02f}, {0, 0, 1});  // back wall
        add({-0.99f, h, v}, {1, 0, 0});  // left (red) wall
        add({0.98f, h, v}, {-1, 0, 0});  // right (green) wall
      }
    }
  }
  return probes;
}

/// RMS difference of luminance over the points, relative to the mean
/// reference luminance (so a deep shadow's small absolute error does not
/// count as a large one); `worst` gets the largest |difference| / mean.
inline double normalizedRms(const std::vector<Rgb>& got, const std::vector<Rgb>& reference,
                            double* worst = nullptr) {
  double sum = 0, mean = 0, largest = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    const double d = double(luminance(got[i])) - luminance(reference[i]);
    sum += d * d;
    mean += luminance(reference[i]);
    largest = std::max(largest, std::abs(d));
  }
  mean /= double(got.size());
  if (worst) *worst = largest / mean;
  return std::sqrt(sum / double(got.size())) / mean;
}

inline std::vector<Rgb> bakedAt(const test::BakedLevel& level, const std::vector<Probe>& probes) {
  Expected<BakedSurfaces> surfaces = BakedSurfaces::build(level.scene, level.bake);
  SVIT_SETUP_CHECK(surfaces.ok(), "");
  Expected<std::vector<LightmapImage>> pages = readLightmapPages(level.bake, level.dir);
  SVIT_SETUP_CHECK(pages.ok(), "");
  std::vector<Rgb> out;
  for (const Probe& probe : probes) {
    const std::optional<SurfaceHit> hit = surfaces->nearest(probe.p, probe.n);
    out.push_back(hit ? (*pages)[hit->page].sampleBilinear(hit->uv) : Rgb{});
  }
  return out;
}

inline std::vector<Rgb> runtimeAt(const Runtime& runtime, const std::vector<Probe>& probes) {
  std::vector<Rgb> out;
  for (const Probe& probe : probes) out.push_back(runtime.irradianceAt(probe.p, probe.n));
  return out;
}

// The Cornell box with its tall box static at `world_from_object`.
inline std::string writeCornellWithBoxAt(const glm::mat4& world_from_object,
                                         const std::string& name) {
  Expected<Scene> scene = loadLevel(test::cornellGltf());
  SVIT_SETUP_CHECK(scene.ok(), "");
  const int node = scene->findNode("tallBox");
  Node& n = scene->nodes[size_t(node)];
  glm::vec3 t = glm::vec3(world_from_object[3]);
  glm::quat q = glm::quat_cast(glm::mat3(world_from_object));
  n.translation = {t.x, t.y, t.z};
  n.rotation = {q.x, q.y, q.z, q.w};
  n.has_trs = true;
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("svit_cornell_" + name + "_" + std::to_string(::getpid())))
                              .string();
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/cornell.gltf";
  SVIT_SETUP_CHECK(writeGltf(*scene, path).ok(), "");
  return path;
}

}  // namespace svit::test

#include "walk_camera.h"

#include <algorithm>
#include <cmath>

#include "walk_animation.h"
#include "walk_math.h"

namespace svit::walk {
namespace {

Camera fromKey(const CameraKey& key, float near_m, float far_m) {
  Camera c;
  c.position = key.position;
  c.look_at = key.look_at;
  c.yfov_rad = key.yfov_rad;
  c.near_m = near_m;
  c.far_m = far_m;
  return c;
}

// A glTF camera with its own planes; an infinite one ends where the
// overview's far plane does.
Camera fromSceneCamera(const SceneCamera& camera, float far_m) {
  Camera c;
  c.position = camera.position;
  c.look_at = fromGlm(toGlm(camera.position) + toGlm(camera.forward));
  c.up = camera.up;
  c.yfov_rad = camera.yfov_rad;
  c.near_m = camera.near_m;
  c.far_m = camera.far_m > 0 ? camera.far_m : std::max(far_m, 100.0f * camera.near_m);
  return c;
}

}  // namespace

Expected<int> chooseSceneCamera(const Scene& scene, const std::string& level,
                                const std::string& name, bool script_has_camera) {
  if (name.empty()) {
    return scene.camera_paths.empty() && !scene.cameras.empty() ? 0 : -1;
  }
  if (script_has_camera) {
    return Status(StatusCode::kInvalidInput,
                  "--camera '" + name + "': the script's camera keys place the camera too");
  }
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    if (scene.cameras[i].name == name) return int(i);
    names += (names.empty() ? "'" : ", '") + scene.cameras[i].name + "'";
  }
  return Status(StatusCode::kInvalidInput,
                "--camera '" + name + "': " + level + " has no camera called that (" +
                    (names.empty() ? "it has no glTF cameras" : "its cameras: " + names) + ")");
}

Camera levelOverview(const Scene& scene) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const Instance& instance : scene.instances) {
    const glm::mat4 world = toGlm(instance.world_from_object);
    for (const Vec3& p : scene.meshes[size_t(instance.mesh)].positions) {
      const glm::vec3 w = glm::vec3(world * glm::vec4(toGlm(p), 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
  if (lo.x > hi.x) lo = hi = glm::vec3(0);
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 0.1f);
  Camera c;
  c.look_at = fromGlm(centre);
  // Far enough back that a sphere round the box fits the 60 degree view.
  c.position = fromGlm(centre + glm::vec3(0, 0.3f * radius, radius / std::sin(0.5f * c.yfov_rad)));
  // Near and far planes from the level's size: a 1e-3 of the viewing
  // distance keeps 24-bit depth precise; far reaches well past the level.
  const float reach = glm::length(toGlm(c.position) - centre);
  c.near_m = std::clamp(reach * 1e-3f, 1e-3f, 0.1f);
  c.far_m = std::max(reach * 4.0f, 10.0f);
  return c;
}

Camera cameraAt(const Scene& scene, const Camera& overview, std::span<const CameraKey> script_keys,
                int scene_camera, float t_s) {
  if (!script_keys.empty()) {
    return fromKey(sampleCameraKeys(script_keys, t_s, false), overview.near_m, overview.far_m);
  }
  if (scene_camera >= 0)
    return fromSceneCamera(scene.cameras[size_t(scene_camera)], overview.far_m);
  if (!scene.camera_paths.empty() && !scene.camera_paths[0].keys.empty()) {
    const CameraPath& path = scene.camera_paths[0];
    return fromKey(sampleCameraKeys(path.keys, t_s, path.loop), overview.near_m, overview.far_m);
  }
  return overview;
}

FlyCamera FlyCamera::lookingLike(const Camera& camera) {
  FlyCamera fly;
  fly.position = camera.position;
  glm::vec3 d = toGlm(camera.look_at) - toGlm(camera.position);
  if (!(glm::length(d) > 0)) d = glm::vec3(0, 0, -1);
  d = glm::normalize(d);
  fly.yaw_rad = std::atan2(-d.x, -d.z);
  fly.pitch_rad = std::asin(std::clamp(d.y, -1.0f, 1.0f));
  fly.yfov_rad = camera.yfov_rad;
  fly.near_m = camera.near_m;
  fly.far_m = camera.far_m;
  return fly;
}

Vec3 FlyCamera::forward() const {
  const float p = std::clamp(pitch_rad, -1.5f, 1.5f);
  return {-std::sin(yaw_rad) * std::cos(p), std::sin(p), -std::cos(yaw_rad) * std::cos(p)};
}

Vec3 FlyCamera::right() const { return {std::cos(yaw_rad), 0, -std::sin(yaw_rad)}; }

Camera FlyCamera::camera() const {
  Camera c;
  c.position = position;
  c.look_at = fromGlm(toGlm(position) + toGlm(forward()));
  c.yfov_rad = yfov_rad;
  c.near_m = near_m;
  c.far_m = far_m;
  return c;
}

}  // namespace svit::walk

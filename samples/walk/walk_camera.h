#pragma once
// Where svit-walk looks from: the script's camera keys, else the glTF camera
// chosen (--camera NAME), else the level's first camera path, else its first
// glTF camera, else a view of the whole level; and the free-flying camera of
// the window mode.

#include <span>
#include <string>

#include "svit/scene.h"
#include "svit/scene_renderer.h"

namespace svit::walk {

/// A camera that sees the level's bounding box from +Z (levels without a
/// camera path), with near and far planes that suit the level's size (every
/// camera of cameraAt() takes its planes from it). Walks every vertex: call once.
Camera levelOverview(const Scene& scene);

/// The Scene::cameras index to look from: the camera called `name` when
/// given, else the first glTF camera of a level without a camera path, else
/// -1. Errors (kInvalidInput, naming `level`): no camera called `name` (the
/// message lists those there are); `name` given with a script that has
/// camera keys of its own.
Expected<int> chooseSceneCamera(const Scene& scene, const std::string& level,
                                const std::string& name, bool script_has_camera);

/// The camera at global time `t_s`: `script_keys` when non-empty (never
/// looping), else Scene::cameras[scene_camera] when >= 0, else the level's
/// first camera path, else `overview`.
Camera cameraAt(const Scene& scene, const Camera& overview, std::span<const CameraKey> script_keys,
                int scene_camera, float t_s);

/// A first-person camera: position, yaw about +Y and pitch, in radians.
struct FlyCamera {
  Vec3 position{0, 0, 0};
  float yaw_rad = 0;    ///< 0 looks down -Z
  float pitch_rad = 0;  ///< clamped to (-1.5, 1.5)
  float yfov_rad = 1.0471975512f;
  float near_m = 0.05f, far_m = 1000.0f;

  static FlyCamera lookingLike(const Camera& camera);
  Camera camera() const;
  Vec3 forward() const;  ///< unit view direction
  Vec3 right() const;    ///< unit, horizontal
};

}  // namespace svit::walk

#pragma once
// svit-walk scripts (samples/walk/README.md "Scripts"): a camera path and
// per-frame events (move a node, switch or dim a light, scale a baked
// emitter, change the view), validated strictly against the level and bake.

#include <optional>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/scene.h"
#include "svit/scene_renderer.h"
#include "svit/status.h"
#include "walk_animation.h"

namespace svit::walk {

/// One scripted change, applied before the frame `frame` is updated.
struct WalkEvent {
  enum class Kind { kMove, kLight, kBakedEmitter, kView };
  Kind kind = Kind::kMove;
  int frame = 0;
  std::string field;  ///< "events[3]", for messages
  // kMove: the node and its new local transform (fields not given keep the
  // node's pose at that frame).
  int node = -1;
  std::optional<Vec3> translation;
  std::optional<Quat> rotation;
  std::optional<Vec3> scale;
  // kLight: Scene::lights index; what changes.
  int light = -1;
  std::optional<bool> enabled;
  std::optional<float> dimmer;
  // kBakedEmitter: BakeData::emitters index and its scale (>= 0).
  uint32_t emitter = 0;
  float scale_factor = 1;
  // kView
  ShadingView view = ShadingView::kRuntime;
};

struct WalkScript {
  std::optional<float> fps;       ///< frames per second, > 0
  std::optional<int> frames;      ///< frame count, >= 1
  std::vector<CameraKey> camera;  ///< empty: the level's camera path
  std::vector<WalkEvent> events;  ///< in file order
};

/// Reads and validates `path` against `scene` and `bake`. Errors name the
/// file and field: `s.json: events[3].light.name: no light 'lamp9'`;
/// unknown fields, wrong types, non-finite numbers, unknown nodes (or
/// nodes that are not dynamic), unknown lights, emitter indices out of range.
Expected<WalkScript> readWalkScript(const std::string& path, const Scene& scene,
                                    const BakeData& bake);

/// Checks every event's frame lies in [0, frames): `s.json: events[2].frame: 120 is past the last
/// frame 89`.
Status checkEventFrames(const WalkScript& script, const std::string& path, int frames);

/// "baked", "runtime" or "delta" -> the view; nullopt for anything else.
std::optional<ShadingView> parseView(const std::string& name);
const char* viewName(ShadingView view);

}  // namespace svit::walk

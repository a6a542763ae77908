// The smallest game loop that uses svit: load a level and its bake, open a
// (hidden) window with a GL 4.5 core context, make svit's Runtime and
// SceneRenderer, move a dynamic object every frame, update, render, and save
// the last frame. Uses only the installed package's public headers.
//
// usage: svit-integration-example LEVEL BAKE_DIR OUT.png [FRAMES]
// Exit 0 ok, 1 failure, 2 bad usage.

#include <GLFW/glfw3.h>

#include <cmath>
#include <numbers>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "svit/bake_file.h"
#include "svit/level.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "svit-integration-example: %s\n", message.c_str());
  return 1;
}

// The level's first camera key, or a view from +Z of the origin.
svit::Camera startCamera(const svit::Scene& scene) {
  svit::Camera camera;
  camera.position = {0, 1, 3.5f};
  camera.look_at = {0, 1, 0};
  if (!scene.camera_paths.empty() && !scene.camera_paths[0].keys.empty()) {
    const svit::CameraKey& key = scene.camera_paths[0].keys[0];
    camera.position = key.position;
    camera.look_at = key.look_at;
    camera.yfov_rad = key.yfov_rad;
  }
  return camera;
}

// The game owns the window and the GL context; svit only uses it. Hidden,
// GL 4.5 core, made current; null (and `error` set) on failure.
GLFWwindow* openHiddenWindow(std::string& error) {
  if (glfwInit() != GLFW_TRUE) {
    error = "cannot initialise GLFW (no display? run under xvfb-run -a)";
    return nullptr;
  }
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(640, 360, "svit integration", nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    error = "cannot create an OpenGL 4.5 core context";
    return nullptr;
  }
  glfwMakeContextCurrent(window);
  return window;
}

// The object the game moves: the level's first dynamic object, if any.
struct MovedObject {
  bool present = false;
  svit::ObjectId id = 0;
  svit::Mat4 rest;  // its world transform as the level places it
};

svit::Status findMovedObject(svit::Runtime& runtime, MovedObject& object) {
  const std::vector<svit::ObjectId> objects = runtime.objects();
  if (objects.empty()) return svit::Status();
  svit::Expected<svit::ObjectInfo> info = runtime.objectInfo(objects[0]);
  if (!info.ok()) return info.status();
  object = {true, objects[0], info->world_from_object};
  std::printf("moving '%s'\n", info->name.c_str());
  return svit::Status();
}

// The game loop: move, update the lighting, render; prints each frame's times.
svit::Status runFrames(svit::Runtime& runtime, svit::SceneRenderer& renderer,
                       const MovedObject& object, const svit::Camera& camera, int frames,
                       double& runtime_ms, double& shading_ms) {
  for (int frame = 0; frame < frames; ++frame) {
    if (object.present) {
      // Slide the object 20 cm along x and back over the run.
      const float offset_m =
          0.2f * std::sin(std::numbers::pi_v<float> * float(frame) / float(frames));
      svit::Mat4 moved = object.rest;
      moved.m[12] += offset_m;  // column 3, row 0: translation x
      if (svit::Status s = runtime.setObjectTransform(object.id, moved); !s.ok()) return s;
    }
    const svit::FrameStats lighting = runtime.update(/*budget_ms=*/0);
    if (!lighting.error.empty())
      return svit::Status(svit::StatusCode::kInternal, "update: " + lighting.error);
    svit::Expected<svit::RenderStats> shading =
        renderer.render(camera, svit::ShadingView::kRuntime);
    if (!shading.ok()) return shading.status();
    glfwPollEvents();
    runtime_ms += lighting.total_ms;
    shading_ms += shading->shading_ms;
    std::printf(
        "frame %d: runtime %.2f ms (maps %.2f, reduction %.2f, bounce %.2f), %u emitters "
        "refreshed, "
        "shading %.2f ms\n",
        frame, lighting.total_ms, lighting.maps_ms, lighting.reduction_ms, lighting.bounce_ms,
        lighting.emitters_refreshed, shading->shading_ms);
  }
  return svit::Status();
}

// svit's runtime (lighting) and renderer (shading), made once per level, the
// game loop, and the last frame as a picture. Exit status of the program.
int runGame(const svit::Scene& scene, const svit::BakeData& bake, const std::string& bake_dir,
            const std::string& png_path, int frames) {
  svit::RuntimeSettings runtime_settings;
  // SceneRenderer interpolates the patch delta buffer instead
  runtime_settings.delta_textures = false;
  svit::Expected<std::unique_ptr<svit::Runtime>> runtime =
      svit::Runtime::create(scene, bake, bake_dir, runtime_settings);
  if (!runtime.ok()) return fail(runtime.status().message());
  svit::SceneRendererSettings settings;
  settings.width = 640;
  settings.height = 360;
  svit::Expected<std::unique_ptr<svit::SceneRenderer>> renderer =
      svit::SceneRenderer::create(scene, bake, bake_dir, runtime->get(), settings);
  if (!renderer.ok()) return fail(renderer.status().message());
  MovedObject object;
  if (svit::Status s = findMovedObject(**runtime, object); !s.ok()) return fail(s.message());
  double runtime_ms = 0, shading_ms = 0;
  if (svit::Status s = runFrames(**runtime, **renderer, object, startCamera(scene), frames,
                                 runtime_ms, shading_ms);
      !s.ok()) {
    return fail(s.message());
  }
  if (svit::Status s = (*renderer)->writePng(png_path); !s.ok()) return fail(s.message());
  std::printf("%d frames: mean runtime %.2f ms, mean shading %.2f ms; wrote %s\n", frames,
              runtime_ms / frames, shading_ms / frames, png_path.c_str());
  return 0;
}  // renderer and runtime go before the context

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::fprintf(stderr, "usage: svit-integration-example LEVEL BAKE_DIR OUT.png [FRAMES]\n");
    return 2;
  }
  const std::string level_path = argv[1], bake_dir = argv[2], png_path = argv[3];
  const int frames = argc == 5 ? std::atoi(argv[4]) : 10;
  if (frames < 1) return fail("FRAMES must be a positive integer");

  // The level and its bake (no GL needed yet).
  svit::Expected<svit::Scene> scene = svit::loadLevel(level_path);
  if (!scene.ok()) return fail(scene.status().message());
  svit::Expected<svit::BakeData> bake = svit::readBakeFile(bake_dir + "/bake.svit");
  if (!bake.ok()) return fail(bake.status().message());

  std::string error;
  GLFWwindow* window = openHiddenWindow(error);
  if (window == nullptr) return fail(error);
  const int status = runGame(*scene, *bake, bake_dir, png_path, frames);
  glfwMakeContextCurrent(nullptr);
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

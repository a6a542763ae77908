// The smallest game loop that uses svit: load a level and its bake, open a
// (hidden) window with a GL 4.5 core context, make svit's Runtime and
// SceneRenderer, move a dynamic object every frame, update, render, and save
// the last frame. Uses only the installed package's public headers.
//
// usage: svit-integration-example LEVEL BAKE_DIR OUT.png [FRAMES]
// Exit 0 ok, 1 failure, 2 bad usage.

#include <GLFW/glfw3.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::fprintf(stderr, "usage: svit-integration-example LEVEL BAKE_DIR OUT.png [FRAMES]\n");
    return 2;
  }
  const std::string level_path = argv[1], bake_dir = argv[2], png_path = argv[3];
  const int frames = argc == 5 ? std::atoi(argv[4]) : 10;
  if (frames < 1) return fail("FRAMES must be a positive integer");

  // 1. The level and its bake (no GL needed yet).
  svit::Expected<svit::Scene> scene = svit::loadLevel(level_path);
  if (!scene.ok()) return fail(scene.status().message());
  svit::Expected<svit::BakeData> bake = svit::readBakeFile(bake_dir + "/bake.svit");
  if (!bake.ok()) return fail(bake.status().message());

  // 2. The game owns the window and the GL context; svit only uses it.
  if (glfwInit() != GLFW_TRUE) return fail("cannot initialise GLFW (no display? run under xvfb-run -a)");
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(640, 360, "svit integration", nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    return fail("cannot create an OpenGL 4.5 core context");
  }
  glfwMakeContextCurrent(window);
  int status = 0;
  {
    // 3. svit's runtime (lighting) and renderer (shading), made once per level.
    svit::RuntimeSettings runtime_settings;
    runtime_settings.delta_textures = false;  // SceneRenderer interpolates the patch delta buffer instead
    svit::Expected<std::unique_ptr<svit::Runtime>> runtime =
        svit::Runtime::create(*scene, *bake, bake_dir, runtime_settings);
    if (!runtime.ok()) return fail(runtime.status().message());
    svit::SceneRendererSettings settings;
    settings.width = 640;
    settings.height = 360;
    svit::Expected<std::unique_ptr<svit::SceneRenderer>> renderer =
        svit::SceneRenderer::create(*scene, *bake, bake_dir, runtime->get(), settings);
    if (!renderer.ok()) return fail(renderer.status().message());

    // The object the game moves: the level's first dynamic object, if any.
    const std::vector<svit::ObjectId> objects = (*runtime)->objects();
    svit::Mat4 rest;
    if (!objects.empty()) {
      svit::Expected<svit::ObjectInfo> info = (*runtime)->objectInfo(objects[0]);
      if (!info.ok()) return fail(info.status().message());
      rest = info->world_from_object;
      std::printf("moving '%s'\n", info->name.c_str());
    }
    const svit::Camera camera = startCamera(*scene);

    // 4. The game loop: move, update the lighting, render.
    double runtime_ms = 0, shading_ms = 0;
    for (int frame = 0; frame < frames; ++frame) {
      if (!objects.empty()) {
        // Slide the object 20 cm along x and back over the run.
        const float offset_m = 0.2f * std::sin(3.14159265f * float(frame) / float(frames));
        svit::Mat4 moved = rest;
        moved.m[12] += offset_m;  // column 3, row 0: translation x
        if (svit::Status s = (*runtime)->setObjectTransform(objects[0], moved); !s.ok()) return fail(s.message());
      }
      const svit::FrameStats lighting = (*runtime)->update(/*budget_ms=*/0);
      if (!lighting.error.empty()) return fail("update: " + lighting.error);
      svit::Expected<svit::RenderStats> shading = (*renderer)->render(camera, svit::ShadingView::kRuntime);
      if (!shading.ok()) return fail(shading.status().message());
      glfwPollEvents();
      runtime_ms += lighting.total_ms;
      shading_ms += shading->shading_ms;
      std::printf("frame %d: runtime %.2f ms (maps %.2f, reduction %.2f, bounce %.2f), %u emitters refreshed, "
                  "shading %.2f ms\n",
                  frame, lighting.total_ms, lighting.maps_ms, lighting.reduction_ms, lighting.bounce_ms,
                  lighting.emitters_refreshed, shading->shading_ms);
    }

    // 5. The last frame as a picture.
    if (svit::Status s = (*renderer)->writePng(png_path); !s.ok()) {
      status = fail(s.message());
    } else {
      std::printf("%d frames: mean runtime %.2f ms, mean shading %.2f ms; wrote %s\n", frames,
                  runtime_ms / frames, shading_ms / frames, png_path.c_str());
    }
  }  // renderer and runtime go before the context
  glfwMakeContextCurrent(nullptr);
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

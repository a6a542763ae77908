// Loads a level through the installed svit package and prints its triangle
// count; with the GL runtime, also checks it refuses to run without a context.
#include <cstdio>

#include "svit/level.h"
#include "svit/scene_summary.h"
#ifdef CONSUMER_HAS_RUNTIME
#include "svit/gl_context.h"
#endif

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  svit::Expected<svit::Scene> scene = svit::loadLevel(argv[1]);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().message().c_str());
    return 1;
  }
  const svit::SceneSummary summary = svit::summarize(*scene);
  std::printf("triangles %zu\n", summary.static_triangles + summary.dynamic_triangles);
#ifdef CONSUMER_HAS_RUNTIME
  if (svit::checkGlContext().ok()) return 3;  // no context was made current
  std::printf("runtime linked\n");
#endif
  return 0;
}

// svit-info LEVEL [--json]: loads a level and prints what it holds.
// Exit codes (docs/architecture.md "Command-line contracts"): 0 ok, 1 bad input, 2 bad usage.

#include <cstdio>
#include <cstring>
#include <string>

#include "svit/level.h"
#include "svit/scene_summary.h"

namespace {

void usage(FILE* out) {
  std::fprintf(out,
               "usage: svit-info LEVEL [--json]\n"
               "  LEVEL   a .gltf, .glb or level .json\n"
               "  --json  print the summary as JSON\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string level;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0) {
      json = true;
    } else if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (argv[i][0] == '-' || !level.empty()) {
      std::fprintf(stderr, "svit-info: unexpected argument '%s'\n", argv[i]);
      usage(stderr);
      return 2;
    } else {
      level = argv[i];
    }
  }
  if (level.empty()) {
    usage(stderr);
    return 2;
  }
  svit::Expected<svit::Scene> scene = svit::loadLevel(level);
  if (!scene.ok()) {
    std::fprintf(stderr, "svit-info: %s\n", scene.status().message().c_str());
    return 1;
  }
  const svit::SceneSummary summary = svit::summarize(*scene);
  const std::string text =
      json ? svit::summaryToJson(level, summary) : svit::summaryToText(level, summary);
  std::fputs(text.c_str(), stdout);
  return 0;
}

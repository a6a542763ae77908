// svit-walk LEVEL --bake OUT [--headless] [--script S.json] [--frames N]
// [--frames-out DIR] [--stats FILE] [--probe POINTS --probe-out FILE] ...:
// the sample walkthrough (docs/architecture.md "Command-line contracts",
// samples/walk/README.md). Exit 0 ok, 1 bad input, 2 bad usage.

#include <csignal>
#include <cstdio>

#include "walk_args.h"
#include "walk_headless.h"
#include "walk_session.h"
#include "walk_window.h"

int main(int argc, char** argv) {
  using namespace svit::walk;
  const ParsedArgs args = parseWalkArgs(argc, argv);
  if (args.help) {
    printUsage(stdout);
    return 0;
  }
  if (!args.error.empty()) {
    std::fprintf(stderr, "svit-walk: %s\n", args.error.c_str());
    printUsage(stderr);
    return 2;
  }
  // Past `ulimit -f` SIGXFSZ would kill silently; ignored, the frame or
  // stats write fails with EFBIG and says which file.
  std::signal(SIGXFSZ, SIG_IGN);
  svit::Expected<std::unique_ptr<WalkSession>> session = openSession(args.options);
  if (!session.ok()) {
    std::fprintf(stderr, "svit-walk: %s\n", session.status().message().c_str());
    return 1;
  }
  WalkSession& s = **session;
  const svit::Status run = args.options.headless ? runHeadless(s) : runWindow(s);
  if (!run.ok()) {
    std::fprintf(stderr, "svit-walk: %s\n", run.message().c_str());
    return 1;
  }
  if (const svit::Status written = writeOutputs(s); !written.ok()) {
    std::fprintf(stderr, "svit-walk: %s\n", written.message().c_str());
    return 1;
  }
  std::printf("%s on %s, %s view, %zu frames\n", args.options.level.c_str(), s.gl_renderer.c_str(),
              viewName(s.view), s.stats.frames().size());
  s.stats.printTable(stdout);
  return 0;
}

// svit-bake LEVEL -o OUT [--seed N] [--time SECONDS] [--quality Q]
//   [--texels-per-m T] [--threads N] [--reference REF_OUT] [--quiet]
// Exit codes (docs/architecture.md "Command-line contracts"): 0 ok, 1 bad
// input or an output that cannot be written (full disk, `ulimit -f`), 2 bad
// usage, 3 cancelled.

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "svit/baker/bake.h"

namespace {

std::atomic<bool> g_cancel{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler stores into it");

void onSignal(int) { g_cancel.store(true); }

void usage(FILE* out) {
  std::fprintf(
      out,
      "usage: svit-bake LEVEL -o OUT [--seed N] [--time SECONDS] [--quality Q]\n"
      "                 [--texels-per-m T] [--threads N] [--reference REF_OUT] [--quiet]\n"
      "  LEVEL            a .gltf, .glb or level .json\n"
      "  -o OUT           output directory: bake.svit, lightmap-*.exr, report.json\n"
      "  --seed N         random seed (default 1); same seed, same bytes\n"
      "  --time SECONDS   wall-time budget for the whole bake\n"
      "  --quality Q      in (0, 1], default 0.5: error target and lighting passes\n"
      "  --texels-per-m T lightmap density (default: about 256k texels for the level)\n"
      "  --threads N      worker threads (default: all cores); results do not depend on it\n"
      "  --reference DIR  a previous bake of the same level to measure the true error against\n"
      "  --quiet          print nothing but errors\n"
      "Ctrl-C or SIGTERM cancels (exit 3) and leaves OUT as it was; a kill or a full\n"
      "disk leaves it the previous bake or the whole new one.\n");
}

bool parseNumber(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0';
}

int badUsage(const std::string& message) {
  std::fprintf(stderr, "svit-bake: %s\n", message.c_str());
  usage(stderr);
  return 2;
}

// Fills `options` and `quiet` from the command line; returns the exit code
// when the tool should stop now (help, bad usage), -1 to go on.
int parseArguments(int argc, char** argv, svit::baker::BakeOptions& options, bool& quiet) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](double& out) {
      if (i + 1 >= argc) return false;
      return parseNumber(argv[++i], out);
    };
    double number = 0;
    if (arg == "-h" || arg == "--help") {
      usage(stdout);
      return 0;
    } else if (arg == "-o") {
      if (i + 1 >= argc) return badUsage("-o needs a directory");
      options.out_dir = argv[++i];
    } else if (arg == "--seed") {
      if (!value(number) || number < 0 || number != std::floor(number))
        return badUsage("--seed needs a whole number >= 0");
      options.seed = uint64_t(number);
    } else if (arg == "--time") {
      if (!value(number)) return badUsage("--time needs a number of seconds");
      options.time_budget_s = number;
    } else if (arg == "--quality") {
      if (!value(number)) return badUsage("--quality needs a number in (0, 1]");
      options.quality = number;
    } else if (arg == "--texels-per-m") {
      if (!value(number) || !(number > 0)) return badUsage("--texels-per-m needs a number > 0");
      options.texels_per_m = number;
    } else if (arg == "--threads") {
      if (!value(number) || number != std::floor(number))
        return badUsage("--threads needs a whole number");
      options.threads = int(number);
    } else if (arg == "--reference") {
      if (i + 1 >= argc) return badUsage("--reference needs a bake directory");
      options.reference_dir = argv[++i];
    } else if (arg == "--quiet") {
      quiet = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return badUsage("unknown option '" + arg + "'");
    } else if (options.level_path.empty()) {
      options.level_path = arg;
    } else {
      return badUsage("unexpected argument '" + arg + "'");
    }
  }
  if (svit::Status s = svit::baker::validateBakeOptions(options); !s.ok())
    return badUsage(s.message());
  return -1;
}

void installCancelHandlers() {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// What killed bakes left beside OUT (OUT.tmp-<pid>, OUT.old-<pid>) goes
// first, said in one line; a failure to remove it is not this bake's error.
void removeAbandoned(const std::string& out_dir, bool quiet) {
  svit::Expected<std::vector<std::string>> removed =
      svit::baker::removeAbandonedBakeDirectories(out_dir);
  if (!removed.ok()) {
    std::fprintf(stderr, "svit-bake: warning: %s\n", removed.status().message().c_str());
  } else if (!removed->empty() && !quiet) {
    std::string list;
    for (const std::string& path : *removed) list += (list.empty() ? "" : ", ") + path;
    std::fprintf(stderr, "svit-bake: removed what killed bakes left: %s\n", list.c_str());
  }
}

// A bar redrawn in place on a terminal; plain lines (per stage and every
// 10%) when stderr is a file or pipe; nothing with --quiet.
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), terminal_(isatty(fileno(stderr))) {}

  bool operator()(const svit::baker::BakeProgress& p) {
    if (quiet_) return true;
    const int percent = int(p.stage_fraction * 100.0 + 0.5);
    char eta[32] = "";
    if (p.eta_s >= 0) std::snprintf(eta, sizeof eta, " ETA %.0fs", p.eta_s);
    if (terminal_) {
      const int filled = percent * 30 / 100;
      std::fprintf(stderr, "\r%-10s [%.*s%*s] %3d%% %6.1fs%s   ", p.stage.c_str(), filled,
                   "##############################", 30 - filled, "", percent, p.elapsed_s, eta);
      std::fflush(stderr);
    } else if (p.stage != last_stage_ || percent / 10 != last_decile_) {
      std::fprintf(stderr, "svit-bake: %s %d%% (%.1fs%s)\n", p.stage.c_str(), percent, p.elapsed_s,
                   eta);
    }
    last_stage_ = p.stage;
    last_decile_ = percent / 10;
    return true;
  }
  /// Ends the bar's line.
  void finish() const {
    if (terminal_ && !quiet_) std::fprintf(stderr, "\n");
  }

 private:
  bool quiet_;
  bool terminal_;
  std::string last_stage_;
  int last_decile_ = -1;
};

void printSummary(const svit::baker::BakeOptions& options, const svit::baker::BakeResult& result) {
  std::printf("baked %s into %s in %.2f s: %zu page(s), %zu texels, estimated error %.2f%%",
              options.level_path.c_str(), options.out_dir.c_str(), result.seconds, result.pages,
              result.covered_texels, 100.0 * result.est_rel_error);
  if (result.ref_rel_error == result.ref_rel_error)
    std::printf(", error against the reference %.2f%%", 100.0 * result.ref_rel_error);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  // Past `ulimit -f` the kernel sends SIGXFSZ, which kills silently; ignored,
  // the write fails with EFBIG and the bake says which file was too large.
  std::signal(SIGXFSZ, SIG_IGN);
  svit::baker::BakeOptions options;
  bool quiet = false;
  if (const int exit_code = parseArguments(argc, argv, options, quiet); exit_code >= 0)
    return exit_code;
  installCancelHandlers();
  removeAbandoned(options.out_dir, quiet);
  ProgressPrinter printer(quiet);
  svit::Expected<svit::baker::BakeResult> result = svit::baker::bakeLevel(
      options, [&](const svit::baker::BakeProgress& p) { return printer(p); }, &g_cancel);
  printer.finish();
  if (!result.ok()) {
    std::fprintf(stderr, "svit-bake: %s\n", result.status().message().c_str());
    return result.status().code() == svit::StatusCode::kCancelled ? 3 : 1;
  }
  if (!quiet) printSummary(options, *result);
  return 0;
}

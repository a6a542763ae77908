// svit-bake LEVEL -o OUT [--seed N] [--time SECONDS | --passes P] [--quality Q]
//   [--texels-per-m T] [--threads N] [--reference REF_OUT] [--sun JSON] [--sky JSON] [--quiet]
// svit-bake plan LEVEL -o WORK --shards N [the same options but --time]
// svit-bake shard WORK I [--threads N] [--quiet]
// svit-bake merge WORK -o OUT [--threads N] [--quiet]
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
#include "svit/baker/sharded_bake.h"

namespace {

std::atomic<bool> g_cancel{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler stores into it");

void onSignal(int) { g_cancel.store(true); }

void usage(FILE* out) {
  std::fprintf(
      out,
      "usage: svit-bake LEVEL -o OUT [--seed N] [--time SECONDS | --passes P] [--quality Q]\n"
      "                 [--texels-per-m T] [--threads N] [--reference REF_OUT]\n"
      "                 [--sun JSON] [--sky JSON] [--no-shadow-masks] [--no-filter] [--quiet]\n"
      "       svit-bake plan LEVEL -o WORK --shards N [--passes P] [the options above]\n"
      "       svit-bake shard WORK I [--threads N] [--quiet]\n"
      "       svit-bake merge WORK -o OUT [--threads N] [--quiet]\n"
      "  LEVEL            a .gltf, .glb or level .json\n"
      "  -o OUT           output directory: bake.svit, lightmap-*.exr, report.json\n"
      "  --seed N         random seed (default 1); same seed, same bytes\n"
      "  --time SECONDS   wall-time budget for the whole bake\n"
      "  --quality Q      in (0, 1], default 0.5: error target and lighting passes\n"
      "  --passes P       lighting passes in [1, 256] instead of the quality's or the\n"
      "                   budget's: the same bytes on any machine (excludes --time)\n"
      "  --texels-per-m T lightmap density (default: about 256k texels for the level)\n"
      "  --threads N      worker threads (default: all cores); results do not depend on it\n"
      "  --reference DIR  a previous bake of the same level to measure the true error against\n"
      "  --sun JSON       a bare glTF's sun, level.json's \"sun\" object, e.g.\n"
      "                   '{\"direction_to_sun\": [0.3, 1, 0.2], \"illuminance_lux\": 100000}'\n"
      "  --sky JSON       its sky, e.g. '{\"model\": \"uniform\", \"zenith_luminance\": [3000, "
      "3000, 3000]}';\n"
      "                   with either, OUT/level.json is the level baked (walk that one)\n"
      "  --no-shadow-masks  keep the baked lights' direct light in the lightmap even\n"
      "                   with dynamic objects (their shadows from those lights are then\n"
      "                   per runtime patch, not per pixel)\n"
      "  --no-filter      leave the gathered (indirect) light unfiltered; the filter\n"
      "                   never crosses charts or creases and never touches direct light\n"
      "  --quiet          print nothing but errors\n"
      "Ctrl-C or SIGTERM cancels (exit 3) and leaves OUT as it was; a kill or a full\n"
      "disk leaves it the previous bake or the whole new one.\n"
      "A sharded bake (docs/sharded-bakes.md): plan solves the radiosity once into WORK\n"
      "and cuts the lighting into N shards; shard I lights one (any order, any host,\n"
      "rerun at will); merge checks them all and writes OUT, bit-identical to\n"
      "svit-bake LEVEL -o OUT with the same --seed and --passes.\n");
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

// What the command line asks for beyond the bake's options.
struct Command {
  std::string verb;        ///< "", "plan", "shard" or "merge"
  uint32_t shards = 0;     ///< plan: --shards
  std::string work_dir;    ///< shard, merge: WORK
  std::string shard_text;  ///< shard: I as given
  bool quiet = false;
  std::vector<std::string> given;  ///< the options given, as spelled
};

bool parseWhole(const char* text, double low, double high, double& out) {
  return parseNumber(text, out) && out == std::floor(out) && out >= low && out <= high;
}

// Fills `options` and `command` from the bake's options in argv[first..];
// returns the exit code when the tool should stop now (help, bad usage), -1
// to go on. Positional arguments go to `positional`.
int parseOptions(int argc, char** argv, int first, svit::baker::BakeOptions& options,
                 Command& command, std::vector<std::string>& positional) {
  bool& quiet = command.quiet;
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](double& out) {
      if (i + 1 >= argc) return false;
      return parseNumber(argv[++i], out);
    };
    double number = 0;
    if (!arg.empty() && arg[0] == '-') command.given.push_back(arg);
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
    } else if (arg == "--passes") {
      if (!value(number) || !(number >= 1 && number <= svit::baker::kMaxBakePasses) ||
          number != std::floor(number))
        return badUsage("--passes needs a whole number in [1, 256]");
      options.passes = uint32_t(number);
    } else if (arg == "--shards" && command.verb == "plan") {
      if (!value(number) || !(number >= 1 && number <= svit::baker::kMaxShards) ||
          number != std::floor(number))
        return badUsage("--shards needs a whole number in [1, 4096]");
      command.shards = uint32_t(number);
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
    } else if (arg == "--reference" || arg == "--sun" || arg == "--sky") {
      if (i + 1 >= argc) {
        return badUsage(arg + (arg == "--reference" ? " needs a bake directory"
                                                    : " needs a JSON object, as in a level .json"));
      }
      (arg == "--reference" ? options.reference_dir
       : arg == "--sun"     ? options.sun_json
                            : options.sky_json) = argv[++i];
    } else if (arg == "--no-shadow-masks") {
      options.shadow_masks = false;
    } else if (arg == "--no-filter") {
      options.indirect_filter = false;
    } else if (arg == "--quiet") {
      quiet = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return badUsage("unknown option '" + arg + "'");
    } else {
      positional.push_back(arg);
    }
  }
  return -1;
}

// The verb's positional arguments and required options, then the bake's
// option ranges; -1 to go on, else the exit code.
int checkCommand(const std::vector<std::string>& positional, svit::baker::BakeOptions& options,
                 Command& command) {
  const size_t wanted = command.verb == "shard" ? 2 : 1;
  if (positional.size() < wanted)
    return badUsage(command.verb.empty() || command.verb == "plan" ? "no level given"
                                                                   : "no WORK directory given");
  if (positional.size() > wanted)
    return badUsage("unexpected argument '" + positional[wanted] + "'");
  if (command.verb.empty() || command.verb == "plan") {
    options.level_path = positional[0];
    if (command.verb == "plan" && command.shards == 0) return badUsage("plan needs --shards N");
    if (command.verb == "plan" && !options.shadow_masks)
      return badUsage("--no-shadow-masks is for whole bakes only: a plan's shards always mask");
    if (command.verb == "plan" && !options.indirect_filter)
      return badUsage("--no-filter is for whole bakes only: a sharded bake's pages are filtered");
    const svit::Status s = command.verb == "plan"
                               ? svit::baker::validatePlanOptions(options, command.shards)
                               : svit::baker::validateBakeOptions(options);
    if (!s.ok()) return badUsage(s.message());
    return -1;
  }
  for (const std::string& option : command.given) {
    const bool allowed =
        option == "--threads" || option == "--quiet" || (option == "-o" && command.verb == "merge");
    if (!allowed) {
      return badUsage(command.verb + " takes " + (command.verb == "merge" ? "-o, " : "") +
                      "--threads and --quiet only (the plan holds the bake's options), not " +
                      option);
    }
  }
  command.work_dir = positional[0];
  if (command.verb == "shard") command.shard_text = positional[1];
  if (command.verb == "merge" && options.out_dir.empty()) return badUsage("merge needs -o OUT");
  if (options.threads < 0 || options.threads > 1024)
    return badUsage("--threads must be in [0, 1024]");
  return -1;
}

int parseArguments(int argc, char** argv, svit::baker::BakeOptions& options, Command& command) {
  int first = 1;
  if (argc > 1) {
    const std::string verb = argv[1];
    if (verb == "plan" || verb == "shard" || verb == "merge") {
      command.verb = verb;
      first = 2;
    }
  }
  std::vector<std::string> positional;
  if (const int exit_code = parseOptions(argc, argv, first, options, command, positional);
      exit_code >= 0)
    return exit_code;
  return checkCommand(positional, options, command);
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
  if (!options.sun_json.empty() || !options.sky_json.empty()) {
    std::printf("the level baked (with --sun/--sky) is %s/level.json: walk that one\n",
                options.out_dir.c_str());
  }
}

// report.json's warnings, one line each on stderr: a level with no light
// source among them, so that black lightmaps never come without a word.
void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings) {
    std::fprintf(stderr, "svit-bake: warning: %s\n", warning.c_str());
  }
}

int reportFailure(const svit::Status& status) {
  std::fprintf(stderr, "svit-bake: %s\n", status.message().c_str());
  return status.code() == svit::StatusCode::kCancelled ? 3 : 1;
}

int runBake(const svit::baker::BakeOptions& options, bool quiet) {
  removeAbandoned(options.out_dir, quiet);
  ProgressPrinter printer(quiet);
  svit::Expected<svit::baker::BakeResult> result = svit::baker::bakeLevel(
      options, [&](const svit::baker::BakeProgress& p) { return printer(p); }, &g_cancel);
  printer.finish();
  if (!result.ok()) return reportFailure(result.status());
  if (!quiet) {
    printWarnings(result->warnings);
    printSummary(options, *result);
  }
  return 0;
}

int runPlan(const svit::baker::BakeOptions& options, const Command& command) {
  removeAbandoned(options.out_dir, command.quiet);
  ProgressPrinter printer(command.quiet);
  svit::Expected<svit::baker::ShardPlanResult> result = svit::baker::planShardedBake(
      options, command.shards, [&](const svit::baker::BakeProgress& p) { return printer(p); },
      &g_cancel);
  printer.finish();
  if (!result.ok()) return reportFailure(result.status());
  if (!command.quiet) {
    std::printf("planned %s into %s in %.2f s: %zu texels in %u shards, %u passes\n",
                options.level_path.c_str(), options.out_dir.c_str(), result->seconds,
                result->texels, result->shards, result->passes);
  }
  return 0;
}

int runShard(const svit::baker::BakeOptions& options, const Command& command) {
  double index = 0;
  if (!parseWhole(command.shard_text.c_str(), 0, svit::baker::kMaxShards - 1, index))
    return badUsage("shard index '" + command.shard_text + "' is not a whole number in [0, 4095]");
  ProgressPrinter printer(command.quiet);
  svit::Expected<svit::baker::ShardRunResult> result = svit::baker::runBakeShard(
      command.work_dir, uint32_t(index), options.threads,
      [&](const svit::baker::BakeProgress& p) { return printer(p); }, &g_cancel);
  printer.finish();
  if (!result.ok()) return reportFailure(result.status());
  if (!command.quiet) {
    std::printf("lit shard %u of %u (%zu texels) into %s in %.2f s, peak %.1f MB\n", result->shard,
                result->shards, result->texels, result->path.c_str(), result->seconds,
                double(result->peak_rss_bytes) / 1e6);
  }
  return 0;
}

int runMerge(const svit::baker::BakeOptions& options, const Command& command) {
  removeAbandoned(options.out_dir, command.quiet);
  ProgressPrinter printer(command.quiet);
  svit::Expected<svit::baker::BakeResult> result = svit::baker::mergeShardedBake(
      command.work_dir, options.out_dir, options.threads,
      [&](const svit::baker::BakeProgress& p) { return printer(p); }, &g_cancel);
  printer.finish();
  if (!result.ok()) return reportFailure(result.status());
  if (!command.quiet) {
    printWarnings(result->warnings);
    std::printf("merged %s into %s in %.2f s: %zu page(s), %zu texels, estimated error %.2f%%\n",
                command.work_dir.c_str(), options.out_dir.c_str(), result->seconds, result->pages,
                result->covered_texels, 100.0 * result->est_rel_error);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Past `ulimit -f` the kernel sends SIGXFSZ, which kills silently; ignored,
  // the write fails with EFBIG and the bake says which file was too large.
  std::signal(SIGXFSZ, SIG_IGN);
  svit::baker::BakeOptions options;
  Command command;
  if (const int exit_code = parseArguments(argc, argv, options, command); exit_code >= 0)
    return exit_code;
  installCancelHandlers();
  if (command.verb == "plan") return runPlan(options, command);
  if (command.verb == "shard") return runShard(options, command);
  if (command.verb == "merge") return runMerge(options, command);
  return runBake(options, command.quiet);
}

// The long soak (tests/soak/house_soak.h) on the generated house, headless
// under xvfb-run on whatever GL is there (Mesa llvmpipe here): FRAMES frames
// of sliding tables, doors, switched and dimmed lamps and props added and
// removed every five frames; memory from resources() sampled every
// SAMPLE_EVERY frames; then (unless --no-replay) the same seed again on a
// fresh runtime, whose deltas at the last frame must equal the first run's
// bit for bit. Writes a JSON report; exits 1 when a promise broke.
// usage: bench_soak LEVEL.json BAKE_DIR [--frames N] [--sample-every K] [--seed S]
//                   [--budget SAMPLES] [--no-replay] [--json OUT]

#include <epoxy/gl.h>

#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "soak/house_soak.h"
#include "svit/bake_file.h"
#include "svit/level.h"

namespace {

using namespace svit;

struct Options {
  std::string level, bake_dir, json;
  uint64_t frames = 20000, sample_every = 500, seed = 11;
  int budget = 16;
  bool replay = true;
};

[[noreturn]] void die(const std::string& why) {
  std::fprintf(stderr, "bench_soak: %s\n", why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  if (argc < 3) die("usage: bench_soak LEVEL.json BAKE_DIR [options]");
  Options o;
  o.level = argv[1];
  o.bake_dir = argv[2];
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) die(a + " needs a value");
      return argv[++i];
    };
    if (a == "--frames")
      o.frames = std::stoull(value());
    else if (a == "--sample-every")
      o.sample_every = std::stoull(value());
    else if (a == "--seed")
      o.seed = std::stoull(value());
    else if (a == "--budget")
      o.budget = std::stoi(value());
    else if (a == "--json")
      o.json = value();
    else if (a == "--no-replay")
      o.replay = false;
    else
      die("unknown option '" + a + "'");
  }
  if (o.sample_every == 0 || o.sample_every % soak::kPropEvery != 0)
    die("--sample-every must be a multiple of " + std::to_string(soak::kPropEvery));
  return o;
}

soak::SoakReport soakOnce(const Options& o, const Scene& scene, const BakeData& bake) {
  Expected<std::unique_ptr<Runtime>> runtime =
      Runtime::create(scene, bake, o.bake_dir, soak::soakSettings(o.budget));
  if (!runtime.ok()) die(runtime.status().message());
  return soak::runHouseSoak(**runtime, o.seed, o.frames, o.sample_every);
}

// Bytes of each resources() line, by name.
nlohmann::ordered_json lineBytes(const std::vector<std::pair<std::string, uint64_t>>& named) {
  nlohmann::ordered_json lines = nlohmann::ordered_json::object();
  for (const auto& [name, bytes] : named) lines[name] = bytes;
  return lines;
}

nlohmann::ordered_json reportJson(const soak::SoakReport& r) {
  nlohmann::ordered_json j;
  j["frames"] = r.frames;
  j["objects_added"] = r.objects_added;
  j["objects_removed"] = r.objects_removed;
  j["light_changes"] = r.light_changes;
  j["door_moves"] = r.door_moves;
  j["samples_rendered"] = r.samples_rendered;
  j["failure_count"] = r.failure_count;
  j["failures"] = r.failures;
  for (const soak::SoakSample& s : r.samples) {
    j["samples"].push_back({{"frame", s.frame},
                            {"host_bytes", s.host_bytes},
                            {"gpu_bytes", s.gpu_bytes},
                            {"heap_bytes", s.heap_bytes},
                            {"object_bytes", s.object_bytes},
                            {"emitters", s.emitters},
                            {"gl_objects", s.gl_objects},
                            {"objects", s.objects},
                            {"patches", s.patches},
                            {"mean_frame_ms", s.mean_frame_ms},
                            {"host_lines", lineBytes(s.host_lines)},
                            {"lines", lineBytes(s.lines)}});
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  if (glfwInit() != GLFW_TRUE) die("glfwInit failed (run under xvfb-run)");
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "bench_soak", nullptr, nullptr);
  if (window == nullptr) die("no OpenGL 4.5 core context");
  glfwMakeContextCurrent(window);
  Expected<Scene> scene = loadLevel(o.level);
  if (!scene.ok()) die(scene.status().message());
  Expected<BakeData> bake = readBakeFile(o.bake_dir + "/bake.svit");
  if (!bake.ok()) die(bake.status().message());
  std::printf("bench_soak: %llu frames, budget %d samples, GL: %s\n", (unsigned long long)o.frames,
              o.budget, (const char*)glGetString(GL_RENDERER));

  const soak::SoakReport first = soakOnce(o, *scene, *bake);
  nlohmann::ordered_json json = reportJson(first);
  bool replayed = true;
  if (o.replay) {
    const soak::SoakReport again = soakOnce(o, *scene, *bake);
    replayed = again.final_deltas.size() == first.final_deltas.size() &&
               std::memcmp(again.final_deltas.data(), first.final_deltas.data(),
                           first.final_deltas.size() * sizeof(Rgb)) == 0;
    json["replay_identical"] = replayed;
  }
  for (const soak::SoakSample& s : first.samples) {
    std::printf(
        "frame %6llu: host %10llu B, heap %10llu B, GPU %10llu B, %5u patches, %5u emitters, "
        "%6.2f ms/frame\n",
        (unsigned long long)s.frame, (unsigned long long)s.host_bytes,
        (unsigned long long)s.heap_bytes, (unsigned long long)s.gpu_bytes, s.patches, s.emitters,
        s.mean_frame_ms);
  }
  for (const std::string& f : first.failures) std::printf("FAILURE %s\n", f.c_str());
  std::printf("replay at frame %llu: %s\n", (unsigned long long)o.frames,
              o.replay ? (replayed ? "identical bit for bit" : "DIFFERS") : "not run");
  if (!o.json.empty()) std::ofstream(o.json) << json.dump(2) << "\n";
  glfwDestroyWindow(window);
  glfwTerminate();
  return first.failure_count == 0 && replayed ? 0 : 1;
}

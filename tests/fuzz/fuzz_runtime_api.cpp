// libFuzzer target: the runtime API abuse driver (tests/abuse) with its
// choices taken from the fuzzer's input bytes instead of a seed. Each input
// drives a fresh pair of twin runtimes and renderers over the Cornell box
// (a subject that gets every call, a reference that gets only the valid
// ones) for as many calls as its bytes make, then one compared update and
// frame. A finding of the driver (an invalid call accepted or not naming its
// argument, twins that diverge, a non-finite delta or pixel, a GL error)
// aborts, so libFuzzer keeps the input; ASan and UBSan report the rest.
//
// Needs a display (xvfb-run) for its GL 4.5 context and the bake of
// samples/levels/cornell/level.json in $SVIT_FUZZ_BAKE_DIR:
// tests/fuzz/run_runtime_fuzzer.sh sets both up.

#include <GLFW/glfw3.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "abuse/runtime_abuse_driver.h"
#include "fuzz_support.h"
#include "svit/bake_file.h"
#include "svit/level.h"

namespace {

constexpr int kMaxCalls = 48;  // per input: keeps one input under a second

/// Choices from the input bytes: one byte for small choices, two for larger.
class FuzzedDraws final : public svit::abuse::Draws {
 public:
  FuzzedDraws(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint32_t below(uint32_t n) override {
    if (n <= 1) return 0;
    uint32_t value = next();
    if (n > 256) value = value | (next() << 8);
    return value % n;
  }
  bool more() const override { return offset_ < size_; }

 private:
  uint32_t next() { return offset_ < size_ ? data_[offset_++] : 0u; }
  const uint8_t* data_;
  size_t size_;
  size_t offset_ = 0;
};

struct Level {
  svit::Scene scene;
  svit::BakeData bake;
  std::string dir;
};

const Level& level() {
  static const Level loaded = [] {
    Level out;
    const char* dir = std::getenv("SVIT_FUZZ_BAKE_DIR");
    if (dir == nullptr) svit::fuzz::fail("SVIT_FUZZ_BAKE_DIR is not set (run_runtime_fuzzer.sh)");
    out.dir = dir;
    svit::Expected<svit::Scene> scene = svit::loadLevel(SVIT_CORNELL_LEVEL);
    if (!scene.ok()) svit::fuzz::fail(scene.status().message());
    out.scene = std::move(scene).value();
    svit::Expected<svit::BakeData> bake = svit::readBakeFile(out.dir + "/bake.svit");
    if (!bake.ok()) svit::fuzz::fail(bake.status().message());
    out.bake = std::move(bake).value();
    return out;
  }();
  return loaded;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (glfwInit() != GLFW_TRUE) svit::fuzz::fail("glfwInit failed (no display? run under xvfb-run)");
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "svit fuzz", nullptr, nullptr);
  if (window == nullptr) svit::fuzz::fail("no OpenGL 4.5 core context");
  glfwMakeContextCurrent(window);
  level();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Level& cornell = level();
  svit::Expected<svit::abuse::Twin> subject =
      svit::abuse::makeTwin(cornell.scene, cornell.bake, cornell.dir);
  svit::Expected<svit::abuse::Twin> reference =
      svit::abuse::makeTwin(cornell.scene, cornell.bake, cornell.dir);
  if (!subject.ok() || !reference.ok()) svit::fuzz::fail("makeTwin failed");
  FuzzedDraws draws(data, size);
  svit::abuse::AbuseDriver driver(*subject, *reference, draws);
  for (int call = 0; call < kMaxCalls && draws.more(); ++call) driver.step();
  driver.settleAndCompare();
  static uint64_t calls = 0;
  calls += driver.tally().calls;
  if (!driver.tally().findings.empty()) svit::fuzz::fail(driver.tally().findings.front());
  // How many calls a run issued in all, for its report (a line per 1e4).
  static uint64_t reported = 0;
  if (calls / 10000 > reported) {
    reported = calls / 10000;
    std::fprintf(stderr, "svit fuzz: %llu runtime API calls issued\n", (unsigned long long)calls);
  }
  return 0;
}

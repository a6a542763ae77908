// The seeded API abuse driver (tests/abuse) on the Cornell box: random
// sequences of every public Runtime and SceneRenderer call, valid and
// invalid, against a twin that only sees the valid ones. Every invalid call
// must be rejected with an error naming its argument and change nothing
// (the twins' deltas and frames stay bit for bit equal); nothing may crash,
// raise a GL error or produce a non-finite number. A failure prints its seed
// and the calls before it: SVIT_ABUSE_SEED=<seed> replays that run alone.

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "runtime/gl_test_context.h"
#include "runtime/runtime_test_util.h"
#include "runtime_abuse_driver.h"

namespace svit {
namespace {

struct AbuseRun {
  uint64_t seed;
  int calls;
};

abuse::AbuseTally drive(const AbuseRun& run) {
  const test::BakedLevel& level = test::bakedLevel("cornell", test::cornellLevel());
  Expected<abuse::Twin> subject = abuse::makeTwin(level.scene, level.bake, level.dir);
  Expected<abuse::Twin> reference = abuse::makeTwin(level.scene, level.bake, level.dir);
  SVIT_SETUP_CHECK(subject.ok() && reference.ok(),
                   subject.ok() ? reference.status().message() : subject.status().message());
  abuse::SeededDraws draws(run.seed);
  abuse::AbuseDriver driver(*subject, *reference, draws);
  for (int i = 0; i < run.calls; ++i) driver.step();
  driver.settleAndCompare();
  return driver.tally();
}

void expectNoFindings(const AbuseRun& run, const abuse::AbuseTally& tally) {
  std::printf(
      "[measured] abuse seed %llu: %llu calls, %llu rejected as invalid, extremes %llu "
      "taken / %llu refused, %llu updates and %llu frames compared, %zu findings\n",
      (unsigned long long)run.seed, (unsigned long long)tally.calls,
      (unsigned long long)tally.rejected, (unsigned long long)tally.extreme_accepted,
      (unsigned long long)tally.extreme_rejected, (unsigned long long)tally.updates,
      (unsigned long long)tally.frames, tally.findings.size());
  // Every finding's first line, then the first few with their calls.
  for (const std::string& f : tally.findings)
    std::printf("[finding] seed %llu: %s\n", (unsigned long long)run.seed,
                f.substr(0, f.find('\n')).c_str());
  for (size_t i = 0; i < tally.findings.size() && i < 5; ++i)
    ADD_FAILURE() << "seed " << run.seed << ": " << tally.findings[i];
  EXPECT_GT(tally.rejected, 0u) << "the driver issued no invalid call";
  EXPECT_GT(tally.updates, 0u);
  EXPECT_GT(tally.frames, 0u);
}

class RuntimeAbuse : public ::testing::Test {
 protected:
  void SetUp() override { SVIT_REQUIRE_GL(gl_); }
  test::GlTestContext gl_;
};

TEST_F(RuntimeAbuse, SeededSequencesChangeNothingWhenInvalid) {
  if (const char* seed = std::getenv("SVIT_ABUSE_SEED")) {
    const AbuseRun run{std::strtoull(seed, nullptr, 10), 400};
    expectNoFindings(run, drive(run));
    return;
  }
  for (uint64_t seed : {1, 2, 3}) {
    const AbuseRun run{seed, 300};
    expectNoFindings(run, drive(run));
  }
}

}  // namespace
}  // namespace svit

#pragma once
// The API abuse driver: issues random sequences of every public Runtime and
// SceneRenderer call, with valid and invalid arguments (abuse_values.h), to
// a subject and, of those the subject accepted, to a twin reference that
// never sees an invalid call. A rejected call must name its argument, and
// since the reference never saw it, after every update both must hold the
// same deltas bit for bit and every rendered frame must match: that is what
// "an invalid call changes nothing" means here. Both share the calling
// thread's GL context. Used by tests/gl/runtime_abuse_test.cpp (seeded) and
// tests/fuzz/fuzz_runtime_api.cpp (fuzzer bytes).

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "abuse_draws.h"
#include "abuse_values.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit::abuse {

/// One runtime and a renderer drawing it.
struct Twin {
  std::unique_ptr<Runtime> runtime;
  std::unique_ptr<SceneRenderer> renderer;
};

/// Creates a twin over a baked level with settings small enough for
/// llvmpipe and a 64 x 36 frame; an error names what failed.
Expected<Twin> makeTwin(const Scene& scene, const BakeData& bake, const std::string& bake_dir);

/// What a run issued and found.
struct AbuseTally {
  uint64_t calls = 0;                 ///< public calls issued to the subject
  uint64_t rejected = 0;              ///< of them, invalid ones rejected as they must be
  uint64_t extreme_accepted = 0;      ///< legal extremes taken (kMayReject accepted)
  uint64_t extreme_rejected = 0;      ///< legal extremes refused with a clear error
  uint64_t updates = 0;               ///< updates compared between the twins
  uint64_t frames = 0;                ///< rendered frames compared between the twins
  std::vector<std::string> findings;  ///< broken promises, each with the calls before it
};

class AbuseDriver {
 public:
  /// Drives `subject` and `reference`, created alike (makeTwin) and not
  /// used by anyone else while the driver runs.
  AbuseDriver(Twin& subject, Twin& reference, Draws& draws);
  /// Issues one call (an update or a frame now and then) and checks it.
  void step();
  /// An update and a frame on both twins, compared.
  void settleAndCompare();
  const AbuseTally& tally() const { return tally_; }

 private:
  struct Ids {
    std::vector<uint32_t> live, gone;
    uint32_t issued = 0;
  };
  void addObject();
  void setTransform();
  void deform();
  void setVisible();
  void removeObject();
  void queryObject();
  void addLight();
  void setLight();
  void switchLight();
  void dimLight();
  void scaleBakedEmitter();
  void setView();
  void setSampleBudget();
  void update();
  void queryStatic();
  void render();
  void scaleRenderedEmitter();
  void resize();
  void writeFrames();
  void queryResources();

  /// Checks a call's result against what its argument demands; on success
  /// issues it to the reference too (which must accept it alike).
  template <typename Call>
  bool issue(const std::string& call, Verdict verdict, const std::string& names, Call&& make);
  void checkRejection(const std::string& call, const Status& status, Verdict verdict,
                      const std::string& names);
  void compareUpdates(const FrameStats& a, const FrameStats& b);
  void compareFrames();
  void checkGl(const std::string& call);
  void finding(const std::string& what);
  void log(const std::string& call);

  Twin& subject_;
  Twin& reference_;
  Draws& draws_;
  LevelBox box_;
  Ids objects_, lights_;
  uint32_t bake_emitters_ = 0;
  AbuseTally tally_;
  std::deque<std::string> recent_;  ///< the last calls, for a finding's report
};

}  // namespace svit::abuse

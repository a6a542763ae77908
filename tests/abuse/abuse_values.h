#pragma once
// The arguments the API abuse driver passes: for each kind of argument a
// mix of ordinary values and the ones a game sends when something upstream
// broke (NaN and infinite numbers from a physics blow-up, huge and zero
// scales, unknown and stale ids, empty and degenerate meshes, extreme light
// powers). Each value says whether the API must reject it and what the
// error must name.

#include <string>
#include <vector>

#include "abuse_draws.h"
#include "svit/runtime.h"
#include "svit/scene_renderer.h"

namespace svit::abuse {

/// What the API must do with an argument.
enum class Verdict {
  kAccept,     ///< an ordinary value: the call must succeed
  kReject,     ///< the call must fail, name the argument and change nothing
  kMayReject,  ///< legal but extreme (1e12 cd, a scale of 1e6): either a clear
               ///< rejection or an accepted call whose results stay finite
};

/// One argument: its value, what the API must do with it, and a piece of
/// text an error about it must contain (the argument's name or its value).
template <typename T>
struct Arg {
  T value;
  Verdict verdict = Verdict::kAccept;
  std::string names;
};

/// Where the driver's objects live: inside the level's box, so valid calls
/// do change the lighting.
struct LevelBox {
  Vec3 min, max;
};

Arg<Mat4> drawTransform(Draws& draws, const LevelBox& box);
Arg<DynamicMesh> drawMesh(Draws& draws);
/// Object-space positions for deformObject on an object of `count`.
Arg<std::vector<Vec3>> drawPositions(Draws& draws, size_t count);
Arg<Light> drawLight(Draws& draws, const LevelBox& box);
Arg<float> drawScale(Draws& draws, const std::string& name);
Arg<RuntimeView> drawView(Draws& draws, const LevelBox& box);
Arg<Camera> drawCamera(Draws& draws, const LevelBox& box);
Arg<int> drawSampleBudget(Draws& draws);
/// update()'s budget_ms: only values that give the same schedule on every
/// run (0, no limit, and a limit no update reaches), so the twin runtimes
/// stay comparable bit for bit; and the invalid ones.
Arg<double> drawUpdateBudget(Draws& draws);
Arg<ShadingView> drawShadingView(Draws& draws);

/// An id among `live` (ids the API handed out and that still exist),
/// `gone` (removed ones) or never issued; `what` names it in messages.
Arg<uint32_t> drawId(Draws& draws, const std::vector<uint32_t>& live,
                     const std::vector<uint32_t>& gone, uint32_t issued, const std::string& what);

}  // namespace svit::abuse

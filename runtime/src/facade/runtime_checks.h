#pragma once
// Validation at the runtime's API boundary: each bad setting, light or mesh
// is an error naming the argument and the value, and changes nothing.

#include <span>
#include <string>

#include "svit/runtime.h"

namespace svit {

Status settingError(const std::string& name, double value, const std::string& range);
Status checkSettings(const RuntimeSettings& settings);

/// The runtime's world: where a float still resolves centimetres (its
/// spacing at 1e6 m is 6 cm). Beyond it a physics blow-up's 1e20 m
/// positions would overflow areas and form factors to infinity.
inline constexpr float kWorldLimitM = 1e6f;
/// The brightest light (cd) or emission (cd/m2): 1e15 cd seen from 1 mm is
/// 1e21 lux, far inside a float even summed over every patch and bounce.
inline constexpr float kMaxLightValue = 1e15f;
/// The largest dimmer or baked emitter scale.
inline constexpr float kMaxScale = 1e6f;
/// `what` names the light in the message ("svit runtime: light 3").
Status checkLight(const Light& light, const std::string& what);
Status checkMesh(const DynamicMesh& mesh);
Status checkView(const RuntimeView& view);
/// A finite, affine transform (last row 0 0 0 1); `what` names the object.
Status checkTransform(const Mat4& transform, const std::string& what);
/// A finite point inside the world; `what` names it ("light 3: position").
Status checkWorldPoint(const Vec3& point, const std::string& what);
/// checkTransform, and every object-space position finite and placed by
/// `transform` inside the world.
Status checkPlacement(std::span<const Vec3> object_positions, const Mat4& transform,
                      const std::string& what);
/// A dimmer or scale in [0, kMaxScale]; `what` names it ("light 2: dimmer").
Status checkScale(float scale, const std::string& what);
/// update()'s budget: >= 0 (0 and infinity: no limit).
Status checkUpdateBudget(double budget_ms);

}  // namespace svit

#pragma once
// Validation at the runtime's API boundary: each bad setting, light or mesh
// is an error naming the argument and the value, and changes nothing.

#include <string>

#include "svit/runtime.h"

namespace svit {

Status settingError(const std::string& name, double value, const std::string& range);
Status checkSettings(const RuntimeSettings& settings);
/// `what` names the light in the message ("svit runtime: light 3").
Status checkLight(const Light& light, const std::string& what);
Status checkMesh(const DynamicMesh& mesh);
Status checkView(const RuntimeView& view);

}  // namespace svit

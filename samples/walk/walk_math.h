#pragma once
// Conversions between svit's public math types and GLM for svit-walk (the
// library keeps its own copy internal; a sample uses only the public API).

#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "svit/math_types.h"

namespace svit::walk {

inline glm::vec3 toGlm(const Vec3& v) { return {v.x, v.y, v.z}; }
inline glm::quat toGlm(const Quat& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::mat4 toGlm(const Mat4& m) {
  glm::mat4 out;
  std::memcpy(&out[0][0], m.m.data(), sizeof(float) * 16);  // both column-major
  return out;
}
inline Vec3 fromGlm(const glm::vec3& v) { return {v.x, v.y, v.z}; }
inline Quat fromGlm(const glm::quat& q) { return {q.x, q.y, q.z, q.w}; }
inline Mat4 fromGlm(const glm::mat4& m) {
  Mat4 out;
  std::memcpy(out.m.data(), &m[0][0], sizeof(float) * 16);
  return out;
}

}  // namespace svit::walk

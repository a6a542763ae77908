#pragma once
// Local transforms of nodes and path keys: T * R * S, column-major.

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace svit {

/// parent_from_node = translate(t) * rotate(q) * scale(s).
inline glm::mat4 composeTrs(const glm::vec3& t, const glm::quat& q, const glm::vec3& s) {
  glm::mat4 m = glm::mat4_cast(q);
  m[0] *= s.x;
  m[1] *= s.y;
  m[2] *= s.z;
  m[3] = glm::vec4(t, 1.0f);
  return m;
}

}  // namespace svit

// glTF cameras: the perspective cameras the nodes of the file hold become
// Scene::cameras (viewpoints for svit-walk --camera), placed later by the
// node's world transform (finalizeScene). Orthographic cameras have no
// viewpoint svit's viewer can fly from: a warning names each.

#include <cmath>
#include <numbers>

#include <tiny_gltf.h>

#include "gltf_import_context.h"

namespace svit::gltf {
namespace {

Status invalid(std::string message) {
  return Status(StatusCode::kInvalidInput, std::move(message));
}

std::string cameraLabel(const tinygltf::Model& model, int camera) {
  const std::string& name = model.cameras[size_t(camera)].name;
  return "camera " + (name.empty() ? std::to_string(camera) : "'" + name + "'");
}

// The glTF's projection, checked as the specification bounds it: yfov in
// (0, pi), 0 < znear, and znear < zfar when zfar is given (0 = infinite).
Status readPerspective(const tinygltf::PerspectiveCamera& source, const std::string& what,
                       SceneCamera& camera) {
  const double yfov = source.yfov, znear = source.znear, zfar = source.zfar;
  if (!(yfov > 0 && yfov < std::numbers::pi)) {
    return invalid(what + ": yfov " + std::to_string(yfov) + " is not in (0, pi)");
  }
  if (!(znear > 0 && std::isfinite(znear))) {
    return invalid(what + ": znear " + std::to_string(znear) + " is not a positive number");
  }
  if (!(zfar == 0 || (zfar > znear && std::isfinite(zfar)))) {
    return invalid(what + ": zfar " + std::to_string(zfar) + " is not beyond znear " +
                   std::to_string(znear));
  }
  camera.yfov_rad = float(yfov);
  camera.near_m = float(znear);
  camera.far_m = float(zfar);
  return Status();
}

}  // namespace

Status importCameras(ImportContext& context) {
  const tinygltf::Model& model = context.model;
  Scene& scene = context.scene;
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const int index = model.nodes[i].camera;
    if (index < 0) continue;
    const std::string node = context.path + ": " + nodeLabel(model, int(i));
    if (size_t(index) >= model.cameras.size()) {
      return invalid(node + ": camera " + std::to_string(index) + " does not exist (file has " +
                     std::to_string(model.cameras.size()) + ")");
    }
    const std::string what = node + ": " + cameraLabel(model, index);
    const tinygltf::Camera& source = model.cameras[size_t(index)];
    if (source.type != "perspective") {
      scene.warnings.push_back(what + " is " + source.type + ": not a viewpoint, skipped");
      continue;
    }
    SceneCamera camera;
    if (Status s = readPerspective(source.perspective, what, camera); !s.ok()) return s;
    camera.name = !source.name.empty()           ? source.name
                  : !model.nodes[i].name.empty() ? model.nodes[i].name
                                                 : "camera " + std::to_string(index);
    camera.node = int(i);
    scene.nodes[i].camera = index;
    scene.cameras.push_back(camera);
  }
  return Status();
}

}  // namespace svit::gltf

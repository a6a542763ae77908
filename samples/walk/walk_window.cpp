#include "walk_window.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "walk_camera.h"
#include "walk_math.h"

namespace svit::walk {
namespace {

// Interactive state, reached from GLFW's key callback.
struct Controls {
  WalkSession* session = nullptr;
  FlyCamera camera;
  float speed_m_per_s = 1;
  int picked_node = -1;
  int screenshots = 0;
  float baked_lamp_scale = 1;
  bool lamp_pending = false;             // K pressed: apply the new baked lamp scale
  std::string message;                   // last action, shown in the title and the overlay
  bool overlay_visible = true;           // F1
  std::vector<OverlayRow> overlay_rows;  // refreshed with the title
  Status error;                          // a runtime call that failed in the callback
};

// The instance a patch's first element lies on, or -1.
int patchInstance(const BakeData& bake, uint32_t patch) {
  if (patch >= bake.patches.size()) return -1;
  const uint32_t first = bake.patches[patch].first_element;
  if (first >= bake.patch_elements.size()) return -1;
  const uint32_t triangle = bake.patch_elements[first] / 2;
  return triangle < bake.triangle_uvs.size() ? int(bake.triangle_uvs[triangle].instance) : -1;
}

// The level's baked lamp: the first bake emitter of kind patch or light,
// with every other emissive patch of the same object (Cornell's ceiling
// quad is two patches); empty when the bake has none.
std::vector<uint32_t> bakedLamp(const BakeData& bake) {
  for (uint32_t e = 0; e < bake.emitters.size(); ++e) {
    const BakeEmitter& first = bake.emitters[e];
    if (first.kind == BakeEmitter::Kind::kLight) return {e};
    if (first.kind != BakeEmitter::Kind::kPatch) continue;
    const int instance = patchInstance(bake, first.index);
    std::vector<uint32_t> lamp = {e};
    for (uint32_t o = e + 1; o < bake.emitters.size(); ++o) {
      const BakeEmitter& other = bake.emitters[o];
      if (other.kind == BakeEmitter::Kind::kPatch && instance >= 0 &&
          patchInstance(bake, other.index) == instance) {
        lamp.push_back(o);
      }
    }
    return lamp;
  }
  return {};
}

std::string nodeName(const Scene& scene, int node) {
  const std::string& name = scene.nodes[size_t(node)].name;
  return name.empty() ? "node " + std::to_string(node) : name;
}

// The dynamic object nearest the camera.
int nearestObjectNode(const WalkSession& session, const Vec3& from) {
  int best = -1;
  float best_d = 1e30f;
  for (int node : session.motion->objectNodes()) {
    const glm::vec3 p(toGlm(session.motion->worldFromNode(node))[3]);
    const float d = glm::length(p - toGlm(from));
    if (d < best_d) best_d = d, best = node;
  }
  return best;
}

// Keeps the first failure of a runtime call made from the key callback.
void check(Controls& c, const Status& status) {
  if (!status.ok() && c.error.ok()) c.error = status;
}

// P: the dynamic object nearest the camera becomes the one the arrows move.
void pickNearestObject(Controls& c) {
  c.picked_node = nearestObjectNode(*c.session, c.camera.position);
  c.message = c.picked_node >= 0 ? "picked " + nodeName(c.session->scene, c.picked_node)
                                 : "no dynamic object";
}

// L: switches the first runtime light off or on.
void toggleRuntimeLight(Controls& c) {
  WalkSession& s = *c.session;
  const std::vector<LightId> lights = s.runtime->lights();
  if (lights.empty()) {
    c.message = "no runtime light";
  } else if (Expected<RuntimeLightInfo> info = s.runtime->lightInfo(lights[0]); info.ok()) {
    check(c, s.runtime->setLightEnabled(lights[0], !info->enabled));
    c.message = info->light.name + (info->enabled ? " off" : " on");
  }
}

// [ and ]: dims or brightens the first runtime light.
void dimRuntimeLight(Controls& c, int key) {
  WalkSession& s = *c.session;
  const std::vector<LightId> lights = s.runtime->lights();
  if (lights.empty()) {
    c.message = "no runtime light";
  } else if (Expected<RuntimeLightInfo> info = s.runtime->lightInfo(lights[0]); info.ok()) {
    const float dimmer =
        std::clamp(info->dimmer * (key == GLFW_KEY_LEFT_BRACKET ? 0.8f : 1.25f), 0.01f, 4.0f);
    check(c, s.runtime->setLightDimmer(lights[0], dimmer));
    char text[64];
    std::snprintf(text, sizeof text, " dimmer %.2f", dimmer);
    c.message = info->light.name + text;
  }
}

// K: steps the baked lamp's emission through 1, 0.5, 0.25, 0.
void cycleBakedLamp(Controls& c) {
  WalkSession& s = *c.session;
  const std::vector<uint32_t> lamp = bakedLamp(s.bake);
  if (lamp.empty()) {
    c.message = "no baked lamp";
    return;
  }
  c.baked_lamp_scale = c.baked_lamp_scale > 0.9f   ? 0.5f
                       : c.baked_lamp_scale > 0.4f ? 0.25f
                       : c.baked_lamp_scale > 0.2f ? 0.0f
                                                   : 1.0f;
  for (uint32_t e : lamp) check(c, scaleBakeEmitter(s, e, c.baked_lamp_scale));
  char text[96];
  std::snprintf(text, sizeof text, "baked lamp (emitter %u, %zu in all) x %.2f", lamp[0],
                lamp.size(), c.baked_lamp_scale);
  c.message = text;
}

// V: baked only -> runtime -> patch delta -> baked only.
void cycleView(Controls& c) {
  WalkSession& s = *c.session;
  s.view = s.view == ShadingView::kBakedOnly ? ShadingView::kRuntime
           : s.view == ShadingView::kRuntime ? ShadingView::kPatchDelta
                                             : ShadingView::kBakedOnly;
  c.message = std::string("view ") + viewName(s.view);
}

// F12: renders the current view offscreen once more (with the overlay if shown) and saves it.
void saveScreenshot(Controls& c) {
  WalkSession& s = *c.session;
  if (Expected<RenderStats> r = s.renderer->render(c.camera.camera(), s.view); !r.ok()) {
    check(c, r.status());
    return;
  }
  if (c.overlay_visible && s.overlay) {
    check(c, s.overlay->draw(c.overlay_rows, s.renderer->offscreenFramebuffer(),
                             s.renderer->width(), s.renderer->height()));
  }
  char name[48];
  std::snprintf(name, sizeof name, "svit-walk-%03d.png", c.screenshots++);
  check(c, s.renderer->writePng(name));
  c.message = std::string("saved ") + name;
}

void onKey(GLFWwindow* window, int key, int, int action, int) {
  if (action != GLFW_PRESS) return;
  Controls& c = *static_cast<Controls*>(glfwGetWindowUserPointer(window));
  switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window, GLFW_TRUE); break;
    case GLFW_KEY_P: pickNearestObject(c); break;
    case GLFW_KEY_L: toggleRuntimeLight(c); break;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET: dimRuntimeLight(c, key); break;
    case GLFW_KEY_K: cycleBakedLamp(c); break;
    case GLFW_KEY_V: cycleView(c); break;
    case GLFW_KEY_F1: c.overlay_visible = !c.overlay_visible; break;
    case GLFW_KEY_F12: saveScreenshot(c); break;
    default: break;
  }
}

// WASD (+ Q/E down/up, Shift faster) and the picked object's arrows and PgUp/PgDn.
void moveByKeys(GLFWwindow* window, Controls& c, float dt_s) {
  auto down = [&](int key) { return glfwGetKey(window, key) == GLFW_PRESS; };
  const float step = c.speed_m_per_s * dt_s * (down(GLFW_KEY_LEFT_SHIFT) ? 4.0f : 1.0f);
  const glm::vec3 forward = toGlm(c.camera.forward()), right = toGlm(c.camera.right());
  glm::vec3 p = toGlm(c.camera.position);
  if (down(GLFW_KEY_W)) p += step * forward;
  if (down(GLFW_KEY_S)) p -= step * forward;
  if (down(GLFW_KEY_D)) p += step * right;
  if (down(GLFW_KEY_A)) p -= step * right;
  if (down(GLFW_KEY_E)) p.y += step;
  if (down(GLFW_KEY_Q)) p.y -= step;
  c.camera.position = fromGlm(p);
  if (c.picked_node < 0) return;
  // The picked object moves in the camera's horizontal frame, in world space.
  const glm::vec3 flat_forward =
      glm::normalize(glm::vec3(forward.x, 0, forward.z) + glm::vec3(1e-6f, 0, 0));
  glm::vec3 delta(0);
  if (down(GLFW_KEY_UP)) delta += step * 0.5f * flat_forward;
  if (down(GLFW_KEY_DOWN)) delta -= step * 0.5f * flat_forward;
  if (down(GLFW_KEY_RIGHT)) delta += step * 0.5f * right;
  if (down(GLFW_KEY_LEFT)) delta -= step * 0.5f * right;
  if (down(GLFW_KEY_PAGE_UP)) delta.y += step * 0.5f;
  if (down(GLFW_KEY_PAGE_DOWN)) delta.y -= step * 0.5f;
  if (delta == glm::vec3(0)) return;
  // A world-space step in the parent's space (the node's TRS is local).
  const int parent = c.session->scene.nodes[size_t(c.picked_node)].parent;
  if (parent >= 0)
    delta = glm::inverse(glm::mat3(toGlm(c.session->motion->worldFromNode(parent)))) * delta;
  Trs trs = c.session->motion->localTrs(c.picked_node);
  trs.translation = fromGlm(toGlm(trs.translation) + delta);
  c.session->motion->moveNode(c.picked_node, trs);
}

std::string statsLine(const WalkSession& s, const Controls& c, const FrameRecord& r) {
  char text[320];
  std::snprintf(text, sizeof text,
                "svit-walk [%s] frame %.1f ms | runtime %.1f (maps %.1f, reduce %.1f, bounce %.1f, "
                "upload %.1f) "
                "shade %.1f | %u emitters refreshed, %u pending, %u maps | %s",
                viewName(s.view), r.frame_ms, r.runtime.total_ms, r.runtime.maps_ms,
                r.runtime.reduction_ms, r.runtime.bounce_ms, r.runtime.upload_ms,
                r.render.shading_ms, r.runtime.emitters_refreshed, r.runtime.emitters_pending,
                r.runtime.samples_rendered, c.message.c_str());
  return text;
}

}  // namespace

Status runWindow(WalkSession& session) {
  using Clock = std::chrono::steady_clock;
  GLFWwindow* window = session.window->handle();
  Controls controls;
  controls.session = &session;
  controls.camera = FlyCamera::lookingLike(
      cameraAt(session.scene, session.overview, session.script.camera, session.scene_camera, 0));
  controls.speed_m_per_s = std::max(
      0.1f, glm::length(toGlm(session.overview.position) - toGlm(session.overview.look_at)) / 6);
  controls.message =
      "WASD QE move, right mouse look, P pick, arrows PgUp/PgDn move it, L [ ] light, K lamp, V "
      "view, "
      "F1 overlay, F12 shot";
  glfwSetWindowUserPointer(window, &controls);
  glfwSetKeyCallback(window, onKey);

  const Clock::time_point start = Clock::now();
  Clock::time_point last = start, last_title = start;
  size_t first_unshown = 0;  // first stats record the overlay's mean has not covered
  double last_x = 0, last_y = 0;
  glfwGetCursorPos(window, &last_x, &last_y);
  std::vector<bool> fired(session.script.events.size(), false);
  for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
    const Clock::time_point now = Clock::now();
    const float dt_s = std::min(0.25f, std::chrono::duration<float>(now - last).count());
    const float t_s = std::chrono::duration<float>(now - start).count();
    last = now;
    glfwPollEvents();
    if (!controls.error.ok()) return controls.error;
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
      controls.camera.yaw_rad -= float(x - last_x) * 0.004f;
      controls.camera.pitch_rad =
          std::clamp(controls.camera.pitch_rad - float(y - last_y) * 0.004f, -1.5f, 1.5f);
    }
    last_x = x, last_y = y;
    moveByKeys(window, controls, dt_s);
    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    if (width < 16 || height < 16) continue;  // minimised
    if (width != session.renderer->width() || height != session.renderer->height())
      session.renderer->resize(width, height);

    const Clock::time_point frame_start = Clock::now();
    for (size_t e = 0; e < session.script.events.size(); ++e) {
      if (fired[e] || float(session.script.events[e].frame) / session.fps > t_s) continue;
      fired[e] = true;
      if (Status s = applyEvent(session, session.script.events[e]); !s.ok()) return s;
    }
    Expected<FrameStats> lighting = stepLighting(session, t_s, controls.camera.camera(),
                                                 height > 0 ? float(width) / float(height) : 1.0f);
    if (!lighting.ok()) return lighting.status();
    Expected<RenderStats> render =
        session.renderer->render(controls.camera.camera(), session.view, true);
    if (!render.ok()) return render.status();
    const double frame_ms =
        std::chrono::duration<double, std::milli>(Clock::now() - frame_start).count();
    const FrameRecord record{frame, double(t_s), *lighting, *render, frame_ms, session.view};
    session.stats.add(record);
    // Title and overlay show the mean of the last quarter second: legible,
    // and steadier than any single frame.
    if (now - last_title > std::chrono::milliseconds(250) || controls.overlay_rows.empty()) {
      const FrameRecord mean = session.stats.meanSince(first_unshown);
      first_unshown = session.stats.frames().size();
      glfwSetWindowTitle(window, statsLine(session, controls, mean).c_str());
      controls.overlay_rows = statsRows(mean, controls.message);
      last_title = now;
    }
    if (controls.overlay_visible && session.overlay) {
      if (Status s = session.overlay->draw(controls.overlay_rows, 0, width, height); !s.ok())
        return s;
    }
    glfwSwapBuffers(window);
  }
  return Status();
}

}  // namespace svit::walk

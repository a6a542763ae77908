#include "walk_gl_window.h"

#include <GLFW/glfw3.h>

namespace svit::walk {
namespace {

// GLFW reports errors through a callback; keep the last for the Status.
std::string g_glfw_error;
void onGlfwError(int code, const char* description) {
  g_glfw_error = "GLFW error " + std::to_string(code) + ": " + (description ? description : "?");
}

}  // namespace

Expected<std::unique_ptr<GlWindow>> GlWindow::create(int width, int height, bool visible,
                                                     const std::string& title) {
  glfwSetErrorCallback(onGlfwError);
  if (glfwInit() != GLFW_TRUE) {
    return Status(StatusCode::kUnsupported, "cannot initialise GLFW (" + g_glfw_error +
                                                "); without a display run under xvfb-run -a");
  }
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    return Status(StatusCode::kUnsupported,
                  "cannot create an OpenGL 4.5 core context (" + g_glfw_error + ")");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(visible ? 1 : 0);
  return std::unique_ptr<GlWindow>(new GlWindow(window));
}

GlWindow::~GlWindow() {
  glfwMakeContextCurrent(nullptr);
  glfwDestroyWindow(window_);
  glfwTerminate();
}

}  // namespace svit::walk

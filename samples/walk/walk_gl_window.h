#pragma once
// The GLFW window that owns svit-walk's OpenGL 4.5 core context: hidden for
// headless runs (still an X window: run under xvfb-run -a without a
// display), visible otherwise.

#include <memory>
#include <string>

#include "svit/status.h"

struct GLFWwindow;

namespace svit::walk {

class GlWindow {
 public:
  /// Initialises GLFW, opens a `width` x `height` window with a current GL
  /// 4.5 core context. Errors: no display, no GL 4.5 core (GLFW's message).
  static Expected<std::unique_ptr<GlWindow>> create(int width, int height, bool visible,
                                                    const std::string& title);
  ~GlWindow();
  GlWindow(const GlWindow&) = delete;
  GlWindow& operator=(const GlWindow&) = delete;

  GLFWwindow* handle() const { return window_; }

 private:
  explicit GlWindow(GLFWwindow* window) : window_(window) {}
  GLFWwindow* window_ = nullptr;
};

}  // namespace svit::walk

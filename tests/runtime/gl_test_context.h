#pragma once
// A hidden GLFW window with an OpenGL 4.5 core context for GL tests (label
// `gl`, run under xvfb-run on Mesa llvmpipe). One per test; the context is
// current on the test's thread for its lifetime.

#include <gtest/gtest.h>

#include <GLFW/glfw3.h>

#include <chrono>
#include <string>
#include <thread>

namespace svit::test {

/// GLFW's last error, for the message of a test without a context.
inline std::string& lastGlfwError() {
  static std::string error;
  return error;
}

class GlTestContext {
 public:
  GlTestContext(int width = 64, int height = 64) {
    glfwSetErrorCallback([](int code, const char* description) {
      lastGlfwError() = "GLFW error " + std::to_string(code) + ": " + description;
    });
    if (!initGlfw()) return;
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    window_ = glfwCreateWindow(width, height, "svit gl test", nullptr, nullptr);
    if (window_ != nullptr) glfwMakeContextCurrent(window_);
  }
  ~GlTestContext() {
    if (window_ != nullptr) {
      glfwMakeContextCurrent(nullptr);
      glfwDestroyWindow(window_);
    }
    glfwTerminate();
  }
  GlTestContext(const GlTestContext&) = delete;
  GlTestContext& operator=(const GlTestContext&) = delete;
  /// False when no display or no GL 4.5 core context (run under xvfb-run -a).
  bool ok() const { return window_ != nullptr; }

 private:
  // An X server resets when its last client leaves (the test before this
  // one closed its display) and refuses connections while it does: a few
  // tries over two seconds instead of a failed test.
  static bool initGlfw() {
    for (int attempt = 0; attempt < 20; ++attempt) {
      if (glfwInit() == GLFW_TRUE) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

  GLFWwindow* window_ = nullptr;
};

}  // namespace svit::test

/// Skips nothing: a GL test without a context fails loudly.
#define SVIT_REQUIRE_GL(context)                                                       \
  ASSERT_TRUE((context).ok()) << "no OpenGL 4.5 core context: run under xvfb-run -a (" \
                              << svit::test::lastGlfwError() << ")"

// The runtime refuses to start without a current GL 4.5 context, and accepts
// the one Mesa llvmpipe gives under Xvfb. Label `gl`: run under xvfb-run.

#include <gtest/gtest.h>

#include <GLFW/glfw3.h>

#include "svit/gl_context.h"

namespace svit {
namespace {

TEST(GlContext, NoCurrentContextIsAClearError) {
  Expected<GlContextInfo> info = checkGlContext();
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(info.status().message().find("no current OpenGL context"), std::string::npos);
}

TEST(GlContext, HiddenGlfwWindowGivesGl45Core) {
  ASSERT_EQ(glfwInit(), GLFW_TRUE) << "no display: run under xvfb-run -a";
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  GLFWwindow* window = glfwCreateWindow(64, 64, "svit gl test", nullptr, nullptr);
  ASSERT_NE(window, nullptr) << "no OpenGL 4.5 core context available";
  glfwMakeContextCurrent(window);
  Expected<GlContextInfo> info = checkGlContext();
  ASSERT_TRUE(info.ok()) << info.status().message();
  EXPECT_GE(info->major * 10 + info->minor, 45);
  EXPECT_TRUE(info->core_profile);
  EXPECT_FALSE(info->renderer.empty());
  std::printf("GL %s on %s\n", info->version.c_str(), info->renderer.c_str());
  glfwMakeContextCurrent(nullptr);
  EXPECT_FALSE(checkGlContext().ok());  // released again
  glfwDestroyWindow(window);
  glfwTerminate();
}

}  // namespace
}  // namespace svit

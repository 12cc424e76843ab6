// SPDX-License-Identifier: MIT
// GLFW window + Dear ImGui (Debian's libimgui-dev ships the GLFW and OpenGL 3 backends in
// libimgui.a). Our GLFW callbacks are installed before ImGui's, which then chains to them.
#include "tumble/viewer/window.hpp"

#include <epoxy/gl.h>
// epoxy provides the OpenGL declarations; GLFW must not include the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cstdlib>

#include "tumble/error.hpp"

namespace tumble::viewer {
namespace {

std::string g_glfwError;

std::optional<Key> mapKey(int key) {
  switch (key) {
    case GLFW_KEY_LEFT: return Key::Left;
    case GLFW_KEY_RIGHT: return Key::Right;
    case GLFW_KEY_UP: return Key::Up;
    case GLFW_KEY_DOWN: return Key::Down;
    case GLFW_KEY_SPACE: return Key::Space;
    case GLFW_KEY_LEFT_SHIFT: return Key::LeftShift;
    case GLFW_KEY_W: return Key::W;
    case GLFW_KEY_A: return Key::A;
    case GLFW_KEY_S: return Key::S;
    case GLFW_KEY_D: return Key::D;
    case GLFW_KEY_Q: return Key::Q;
    case GLFW_KEY_Z: return Key::Z;
    case GLFW_KEY_E: return Key::E;
    case GLFW_KEY_R: return Key::R;
    case GLFW_KEY_0: case GLFW_KEY_KP_0: return Key::Num0;
    case GLFW_KEY_1: case GLFW_KEY_KP_1: return Key::Num1;
    case GLFW_KEY_2: case GLFW_KEY_KP_2: return Key::Num2;
    case GLFW_KEY_3: case GLFW_KEY_KP_3: return Key::Num3;
    case GLFW_KEY_4: case GLFW_KEY_KP_4: return Key::Num4;
    case GLFW_KEY_5: case GLFW_KEY_KP_5: return Key::Num5;
    case GLFW_KEY_P: return Key::P;
    case GLFW_KEY_N: return Key::N;
    case GLFW_KEY_C: return Key::C;
    case GLFW_KEY_H: return Key::H;
    case GLFW_KEY_L: return Key::L;
    case GLFW_KEY_V: return Key::V;
    case GLFW_KEY_ESCAPE: return Key::Escape;
    default: return std::nullopt;
  }
}

}  // namespace

struct Window::Impl {
  GLFWwindow* window = nullptr;
  std::function<void(Key, bool)> onKey;
  Camera* camera = nullptr;
  bool dragging = false;
  double lastX = 0, lastY = 0;

  static Impl* self(GLFWwindow* w) { return static_cast<Impl*>(glfwGetWindowUserPointer(w)); }
};

Window::Window(const std::string& title, int width, int height) : m(std::make_unique<Impl>()) {
  glfwSetErrorCallback([](int, const char* what) { g_glfwError = what ? what : ""; });
  if (!glfwInit()) {
    const char* display = std::getenv("DISPLAY");
    throw Error("cannot open a window: " + g_glfwError + " (DISPLAY=" + (display ? display : "unset") +
                "); use `tumble render` for images and videos without a screen, or run under xvfb-run");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  m->window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!m->window) {
    glfwTerminate();
    throw Error("cannot open an OpenGL 3.3 core window: " + g_glfwError);
  }
  glfwMakeContextCurrent(m->window);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(m->window, m.get());
  glfwSetKeyCallback(m->window, [](GLFWwindow* w, int key, int, int action, int) {
    Impl* s = Impl::self(w);
    if (action == GLFW_REPEAT || !s->onKey) return;
    if (const auto k = mapKey(key)) s->onKey(*k, action == GLFW_PRESS);
  });
  glfwSetMouseButtonCallback(m->window, [](GLFWwindow* w, int button, int action, int) {
    Impl* s = Impl::self(w);
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    s->dragging = action == GLFW_PRESS && !ImGui::GetIO().WantCaptureMouse;
    glfwGetCursorPos(w, &s->lastX, &s->lastY);
  });
  glfwSetCursorPosCallback(m->window, [](GLFWwindow* w, double x, double y) {
    Impl* s = Impl::self(w);
    if (s->dragging && s->camera) s->camera->orbit(float(x - s->lastX), float(y - s->lastY));
    s->lastX = x;
    s->lastY = y;
  });
  glfwSetScrollCallback(m->window, [](GLFWwindow* w, double, double dy) {
    Impl* s = Impl::self(w);
    if (s->camera && !ImGui::GetIO().WantCaptureMouse) s->camera->zoom(float(dy));
  });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(m->window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

Window::~Window() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(m->window);
  glfwTerminate();
}

void Window::setKeyHandler(std::function<void(Key, bool)> handler) { m->onKey = std::move(handler); }
void Window::setCamera(Camera* camera) { m->camera = camera; }
bool Window::shouldClose() const { return glfwWindowShouldClose(m->window); }
double Window::time() const { return glfwGetTime(); }
void Window::setTitle(const std::string& title) { glfwSetWindowTitle(m->window, title.c_str()); }

void Window::beginFrame() {
  glfwPollEvents();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void Window::endFrame() {
  ImGui::Render();
  int w = 0, h = 0;
  framebufferSize(w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, w, h);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glfwSwapBuffers(m->window);
}

void Window::framebufferSize(int& w, int& h) const { glfwGetFramebufferSize(m->window, &w, &h); }

Image Window::readBack() const {
  int w = 0, h = 0;
  framebufferSize(w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  return readPixels(w, h);
}

void helpOverlay(const std::vector<KeyHelp>& help) {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->WorkPos.x + vp->WorkSize.x - 10.0f, vp->WorkPos.y + 10.0f), ImGuiCond_Always,
                          ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::Begin("Keys", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  ImGui::TextUnformatted("Keys (H hides this)");
  ImGui::Separator();
  if (ImGui::BeginTable("keys", 2)) {
    for (const KeyHelp& k : help) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(k.keys);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(k.action);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace tumble::viewer

// SPDX-License-Identifier: MIT
/// @file window.hpp
/// A GLFW window with an OpenGL 3.3 core context, 4× multisampling, vsync and a Dear ImGui
/// overlay. Keys go to a handler as viewer::Key; the left mouse button drags an orbit camera
/// and the wheel zooms it. One window per process, used from the main thread only.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "tumble/viewer/camera.hpp"
#include "tumble/viewer/controls.hpp"
#include "tumble/viewer/renderer.hpp"

namespace tumble::viewer {

class Window {
 public:
  /// Opens the window; throws tumble::Error when there is no display (naming $DISPLAY and
  /// pointing to `tumble render`, which needs none) or no OpenGL 3.3 core context.
  Window(const std::string& title, int width, int height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  /// Called for every key press and release (not for auto-repeat) of a key in viewer::Key.
  void setKeyHandler(std::function<void(Key, bool)> handler);
  /// The camera the mouse moves (may be null).
  void setCamera(Camera* camera);

  bool shouldClose() const;
  /// Processes pending events (key handler, mouse) and starts an ImGui frame.
  void beginFrame();
  /// Renders the ImGui overlay and shows the frame.
  void endFrame();
  /// Size of the drawable area in pixels.
  void framebufferSize(int& w, int& h) const;
  /// Reads what has been drawn so far into the back buffer (call before endFrame() to get the
  /// scene without the overlay).
  Image readBack() const;
  /// Seconds since the window opened.
  double time() const;
  void setTitle(const std::string& title);

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// Draws the key help as an ImGui window in the top-right corner.
void helpOverlay(const std::vector<KeyHelp>& help);

}  // namespace tumble::viewer

// SPDX-License-Identifier: MIT
/// @file offscreen.hpp
/// Off-screen OpenGL without a window system: an EGL context with no surface (Mesa's
/// surfaceless platform, else the EGL device platform, else the default display) and a
/// multisampled framebuffer object to draw into. Works without an X server and without a GPU
/// (Mesa llvmpipe).
#pragma once
#include <memory>
#include <string>

#include "tumble/viewer/renderer.hpp"

namespace tumble::viewer {

/// An OpenGL 3.3 core context made current on the calling thread, with no surface.
class OffscreenContext {
 public:
  /// Throws tumble::Error naming what failed (no EGL display, no OpenGL 3.3 core context, …).
  OffscreenContext();
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;
  /// Which EGL platform was used: "surfaceless", "device" or "default".
  const std::string& platform() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// A w × h framebuffer object with 4× multisampling, resolved into a plain one for reading.
class Framebuffer {
 public:
  Framebuffer(int w, int h, int samples = 4);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;
  /// Binds the multisampled framebuffer for drawing.
  void bind();
  /// Resolves the samples and reads the image (top row first).
  Image read();
  int width() const { return m_w; }
  int height() const { return m_h; }

 private:
  int m_w, m_h;
  unsigned m_msFbo = 0, m_msColor = 0, m_msDepth = 0, m_fbo = 0, m_color = 0;
};

}  // namespace tumble::viewer

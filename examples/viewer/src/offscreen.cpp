// SPDX-License-Identifier: MIT
// Headless EGL. Mesa offers EGL_MESA_platform_surfaceless, which needs neither a display
// server nor a DRM device: with no GPU it runs llvmpipe. The EGL device platform
// (EGL_EXT_platform_device) is the portable fallback (NVIDIA's driver offers it too), and
// eglGetDisplay(EGL_DEFAULT_DISPLAY) the last resort. The context is made current with
// EGL_NO_SURFACE (EGL_KHR_surfaceless_context); all drawing goes to framebuffer objects.
#include "tumble/viewer/offscreen.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/viewer/renderer.hpp"

namespace tumble::viewer {
namespace {

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string eglErrorString(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error " + std::to_string(e);
  }
}

// Deletes the framebuffer's objects (zero names are ignored by OpenGL) and zeroes the names.
void deleteObjects(unsigned& msFbo, unsigned& fbo, unsigned& msColor, unsigned& msDepth, unsigned& color) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  glDeleteFramebuffers(1, &msFbo);
  glDeleteFramebuffers(1, &fbo);
  glDeleteRenderbuffers(1, &msColor);
  glDeleteRenderbuffers(1, &msDepth);
  glDeleteRenderbuffers(1, &color);
  msFbo = fbo = msColor = msDepth = color = 0;
}

}  // namespace

struct OffscreenContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string platform;

  bool tryDisplay(EGLDisplay d, const char* name) {
    if (d == EGL_NO_DISPLAY) return false;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) return false;
    if (!eglBindAPI(EGL_OPENGL_API)) {
      eglTerminate(d);
      return false;
    }
    const EGLint cfgAttrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig cfg = nullptr;
    EGLint numCfg = 0;
    const bool haveCfg = eglChooseConfig(d, cfgAttrs, &cfg, 1, &numCfg) && numCfg > 0;
    const bool noConfig = hasExtension(eglQueryString(d, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
    if (!haveCfg && !noConfig) {
      eglTerminate(d);
      return false;
    }
    const EGLint ctxAttrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    const EGLContext c = eglCreateContext(d, haveCfg ? cfg : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctxAttrs);
    if (c == EGL_NO_CONTEXT) {
      eglTerminate(d);
      return false;
    }
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
      eglDestroyContext(d, c);
      eglTerminate(d);
      return false;
    }
    display = d;
    context = c;
    platform = name;
    return true;
  }
};

OffscreenContext::OffscreenContext() : m(std::make_unique<Impl>()) {
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool platformBase = hasExtension(clientExt, "EGL_EXT_platform_base");
  if (platformBase && hasExtension(clientExt, "EGL_MESA_platform_surfaceless"))
    if (m->tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                      "surfaceless"))
      return;
  if (platformBase && hasExtension(clientExt, "EGL_EXT_platform_device") &&
      hasExtension(clientExt, "EGL_EXT_device_enumeration")) {
    EGLDeviceEXT devices[16];
    EGLint numDevices = 0;
    if (eglQueryDevicesEXT(16, devices, &numDevices))
      for (EGLint i = 0; i < numDevices; ++i)
        if (m->tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), "device")) return;
  }
  if (m->tryDisplay(eglGetDisplay(EGL_DEFAULT_DISPLAY), "default")) return;
  throw Error("cannot create an off-screen OpenGL 3.3 context through EGL (" + eglErrorString(eglGetError()) +
              "); install libegl-mesa0 and libgl1-mesa-dri (Mesa llvmpipe works without a GPU)");
}

OffscreenContext::~OffscreenContext() {
  eglMakeCurrent(m->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(m->display, m->context);
  eglTerminate(m->display);
}

const std::string& OffscreenContext::platform() const { return m->platform; }

Framebuffer::Framebuffer(int w, int h, int samples) : m_w(w), m_h(h) {
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  // Clear errors left over from earlier calls, so that they are not blamed on this framebuffer.
  GLenum pending = glGetError();
  for (int i = 0; pending != GL_NO_ERROR && i < 16; ++i) pending = glGetError();
  GLint maxSamples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  samples = std::max(0, std::min(samples, static_cast<int>(maxSamples)));
  glGenFramebuffers(1, &m_msFbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_msFbo);
  glGenRenderbuffers(1, &m_msColor);
  glBindRenderbuffer(GL_RENDERBUFFER, m_msColor);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_msColor);
  glGenRenderbuffers(1, &m_msDepth);
  glBindRenderbuffer(GL_RENDERBUFFER, m_msDepth);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_msDepth);
  const GLenum ms = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glGenFramebuffers(1, &m_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
  glGenRenderbuffers(1, &m_color);
  glBindRenderbuffer(GL_RENDERBUFFER, m_color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_color);
  const GLenum resolve = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  const GLenum err = glGetError();
  if (ms != GL_FRAMEBUFFER_COMPLETE || resolve != GL_FRAMEBUFFER_COMPLETE || err != GL_NO_ERROR) {
    // The destructor does not run for a constructor that throws: free the objects here.
    deleteObjects(m_msFbo, m_fbo, m_msColor, m_msDepth, m_color);
    throw Error("cannot create a " + size + " off-screen framebuffer" +
                (err != GL_NO_ERROR ? " (" + glErrorName(err) + ")" : std::string()) +
                (err == GL_OUT_OF_MEMORY ? "; try a smaller --size" : ""));
  }
}

Framebuffer::~Framebuffer() { deleteObjects(m_msFbo, m_fbo, m_msColor, m_msDepth, m_color); }

void Framebuffer::bind() { glBindFramebuffer(GL_FRAMEBUFFER, m_msFbo); }

Image Framebuffer::read() {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_msFbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_fbo);
  glBlitFramebuffer(0, 0, m_w, m_h, 0, 0, m_w, m_h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
  Image img = readPixels(m_w, m_h);  // throws on any OpenGL error since the last read-back
  glBindFramebuffer(GL_FRAMEBUFFER, m_msFbo);
  return img;
}

}  // namespace tumble::viewer

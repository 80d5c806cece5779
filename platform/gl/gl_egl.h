// EglSession: the EGL plumbing the KMS, X11 and headless displays share (display, config, GLES 2
// context, optional window surface), owned RAII-style, with readable EGL error names.
#pragma once

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "gl/gl_loader.h"
#include "util/result.h"

namespace emboss {

// "EGL_BAD_ALLOC" etc. for eglGetError() codes.
std::string eglErrorName(EGLint error);
// True when the extension string of `display` (EGL_NO_DISPLAY: the client extensions) names it.
bool hasEglExtension(EGLDisplay display, const std::string& extension);

class EglSession {
 public:
  // Opens and initialises the EGL display of `platform` (EGL_PLATFORM_GBM_KHR, _X11_KHR,
  // _SURFACELESS_MESA) on `nativeDisplay`; EGL_NONE: eglGetDisplay(nativeDisplay), the old way.
  // `who` prefixes error messages ("kms", "x11", ...).
  static Result<std::unique_ptr<EglSession>> open(EGLenum platform, void* nativeDisplay, const std::string& who);
  ~EglSession();
  EglSession(const EglSession&) = delete;
  EglSession& operator=(const EglSession&) = delete;

  // Picks the first GLES 2 config with at least 8-bit RGB (for `surfaceType`, 0 for none) for
  // which `accept` says yes (e.g. the GBM format or X visual matches), and creates the context.
  Status createContext(EGLint surfaceType, const std::function<bool(EGLConfig)>& accept = {});
  // A window surface on `nativeWindow` (a gbm_surface*, or a pointer to an X11 Window).
  Status createWindowSurface(void* nativeWindow);
  // A pbuffer surface (for EGL implementations without surfaceless contexts).
  Status createPbufferSurface(int width, int height);
  // Makes the context current on this thread unless it already is.
  bool makeCurrent();
  // eglSwapBuffers; false when the surface is gone.
  bool swapBuffers();
  void setSwapInterval(int interval);

  EGLDisplay display() const { return display_; }
  EGLConfig config() const { return config_; }
  EGLContext context() const { return context_; }
  EGLSurface surface() const { return surface_; }
  GlProcLoader procLoader() const;
  // "EGL 1.5 (Mesa Project)".
  std::string versionString() const;

 private:
  EglSession() = default;

  std::string who_;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLConfig config_ = nullptr;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  std::uint64_t boundEpoch_ = 0;
};

}  // namespace emboss

// EglSession: EGL display, GLES 2 context and surface handling shared by the EGL displays.
#include "gl/gl_egl.h"

#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <vector>

namespace emboss {
namespace {

// EGL hands out one EGLDisplay per platform and native display, and eglTerminate ends it for
// everyone; count the sessions using each so two displays in one process do not pull the rug.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayUsers;

void releaseDisplay(EGLDisplay display) {
  std::lock_guard lock(gDisplayMutex);
  auto it = gDisplayUsers.find(display);
  if (it == gDisplayUsers.end()) return;
  if (--it->second == 0) {
    gDisplayUsers.erase(it);
    eglTerminate(display);
  }
}

}  // namespace

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(error));
      return std::string("EGL error ") + code;
    }
  }
}

bool hasEglExtension(EGLDisplay display, const std::string& extension) {
  const char* all = eglQueryString(display, EGL_EXTENSIONS);
  if (all == nullptr) {
    eglGetError();  // EGL_NO_DISPLAY queries fail on EGL 1.4 without client extensions; clear it
    return false;
  }
  const std::size_t n = extension.size();
  for (const char* p = all; (p = std::strstr(p, extension.c_str())) != nullptr; p += n) {
    if ((p == all || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

Result<std::unique_ptr<EglSession>> EglSession::open(EGLenum platform, void* nativeDisplay, const std::string& who) {
  std::unique_ptr<EglSession> session(new EglSession());
  session->who_ = who;
  EGLDisplay display = platform == EGL_NONE
                           ? eglGetDisplay(reinterpret_cast<EGLNativeDisplayType>(nativeDisplay))
                           : eglGetPlatformDisplay(platform, nativeDisplay, nullptr);
  if (display == EGL_NO_DISPLAY) {
    return fail(who + ": eglGetPlatformDisplay failed (" + eglErrorName(eglGetError()) +
                "); is Mesa's libEGL installed (libegl-mesa0)?");
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    return fail(who + ": eglInitialize failed (" + eglErrorName(eglGetError()) +
                "); no usable GPU driver for this platform");
  }
  {
    std::lock_guard lock(gDisplayMutex);
    ++gDisplayUsers[display];
  }
  session->display_ = display;
  if (!eglBindAPI(EGL_OPENGL_ES_API)) return fail(who + ": this EGL has no OpenGL ES");
  return session;
}

EglSession::~EglSession() {
  if (display_ == EGL_NO_DISPLAY) return;
  if (eglGetCurrentContext() == context_ && context_ != EGL_NO_CONTEXT) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  releaseDisplay(display_);
}

Status EglSession::createContext(EGLint surfaceType, const std::function<bool(EGLConfig)>& accept) {
  const EGLint attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT,
                               EGL_SURFACE_TYPE,    surfaceType,
                               EGL_RED_SIZE,        8,
                               EGL_GREEN_SIZE,      8,
                               EGL_BLUE_SIZE,       8,
                               EGL_NONE};
  EGLint count = 0;
  if (!eglChooseConfig(display_, attributes, nullptr, 0, &count) || count <= 0) {
    return fail(who_ + ": no EGL config with GLES 2 and 8-bit colour (" + eglErrorName(eglGetError()) + ")");
  }
  std::vector<EGLConfig> configs(static_cast<std::size_t>(count));
  eglChooseConfig(display_, attributes, configs.data(), count, &count);
  config_ = nullptr;
  for (EGLint i = 0; i < count; ++i) {
    if (!accept || accept(configs[static_cast<std::size_t>(i)])) {
      config_ = configs[static_cast<std::size_t>(i)];
      break;
    }
  }
  if (config_ == nullptr) return fail(who_ + ": no EGL config matches the output's pixel format");
  const EGLint contextAttributes[] = {EGL_CONTEXT_CLIENT_VERSION, 2, EGL_NONE};
  context_ = eglCreateContext(display_, config_, EGL_NO_CONTEXT, contextAttributes);
  if (context_ == EGL_NO_CONTEXT) {
    return fail(who_ + ": cannot create a GLES 2 context (" + eglErrorName(eglGetError()) + ")");
  }
  return Ok{};
}

Status EglSession::createWindowSurface(void* nativeWindow) {
  surface_ = eglCreatePlatformWindowSurface(display_, config_, nativeWindow, nullptr);
  if (surface_ == EGL_NO_SURFACE) {
    return fail(who_ + ": cannot create the window surface (" + eglErrorName(eglGetError()) + ")");
  }
  return Ok{};
}

Status EglSession::createPbufferSurface(int width, int height) {
  const EGLint attributes[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
  surface_ = eglCreatePbufferSurface(display_, config_, attributes);
  if (surface_ == EGL_NO_SURFACE) {
    return fail(who_ + ": cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                " pbuffer (" + eglErrorName(eglGetError()) + ")");
  }
  return Ok{};
}

bool EglSession::makeCurrent() {
  const std::uint64_t epoch = foreignGlBindingEpoch();
  if (eglGetCurrentContext() == context_ && eglGetCurrentSurface(EGL_DRAW) == surface_) {
    if (epoch == boundEpoch_) return true;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);  // OSMesa took over GL
  }
  boundEpoch_ = epoch;
  return eglMakeCurrent(display_, surface_, surface_, context_) == EGL_TRUE;
}

bool EglSession::swapBuffers() { return eglSwapBuffers(display_, surface_) == EGL_TRUE; }

void EglSession::setSwapInterval(int interval) { eglSwapInterval(display_, interval); }

GlProcLoader EglSession::procLoader() const {
  return [](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); };
}

std::string EglSession::versionString() const {
  const char* version = eglQueryString(display_, EGL_VERSION);
  const char* vendor = eglQueryString(display_, EGL_VENDOR);
  return std::string("EGL ") + (version != nullptr ? version : "?") + " (" + (vendor != nullptr ? vendor : "?") + ")";
}

}  // namespace emboss

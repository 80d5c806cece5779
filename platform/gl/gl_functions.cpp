// Loading the GL entry points through a context's GetProcAddress.
#include "gl/gl_functions.h"

#include <cstring>

namespace emboss {
namespace {
thread_local std::uint64_t tForeignGlEpoch = 0;
}  // namespace

void noteForeignGlBinding() { ++tForeignGlEpoch; }
std::uint64_t foreignGlBindingEpoch() { return tForeignGlEpoch; }

Result<GlFunctions> loadGlFunctions(const GlProcLoader& loader) {
  GlFunctions gl;
#define EMBOSS_GL_LOAD(type, name)                                                          \
  gl.name = reinterpret_cast<type>(loader("gl" #name));                                     \
  if (gl.name == nullptr) {                                                                 \
    return fail("GL: the driver does not provide gl" #name " (need GLES 2.0 or GL 2.1)");   \
  }
  EMBOSS_GL_FUNCTIONS(EMBOSS_GL_LOAD)
#undef EMBOSS_GL_LOAD
  return gl;
}

bool hasGlExtension(const GlFunctions& gl, const std::string& extension) {
  const auto* all = reinterpret_cast<const char*>(gl.GetString(GL_EXTENSIONS));
  if (all == nullptr) return false;
  const std::size_t n = extension.size();
  for (const char* p = all; (p = std::strstr(p, extension.c_str())) != nullptr; p += n) {
    const bool startOk = p == all || p[-1] == ' ';
    const bool endOk = p[n] == ' ' || p[n] == '\0';
    if (startOk && endOk) return true;
  }
  return false;
}

std::string shortRendererName(const std::string& glRenderer) {
  std::string s = glRenderer.substr(0, glRenderer.find(" ("));
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s.empty() ? std::string("unknown GPU") : s;
}

}  // namespace emboss

// The two facts a GL back end tells the presenter about its context, without any GL header: how
// to look up entry points and which shading language it speaks.
#pragma once

#include <cstdint>
#include <functional>

namespace emboss {

// Returns the address of a GL entry point of the current API (eglGetProcAddress,
// OSMesaGetProcAddress), or null.
using GlProcLoader = std::function<void*(const char* name)>;

// GLSL ES 1.00 (GLES 2) or GLSL 1.20 (desktop GL 2.1+, e.g. OSMesa). The presenter picks the
// #version line and precision statements from this.
enum class GlFlavor { kGles2, kDesktop };

// EGL and OSMesa both drive Mesa's one GL dispatch per thread. A back end that binds its context
// behind EGL's back (OSMesa) bumps this thread's epoch; an EGL back end that sees a newer epoch
// than at its last bind binds again even though EGL still calls its context current.
void noteForeignGlBinding();
std::uint64_t foreignGlBindingEpoch();

}  // namespace emboss

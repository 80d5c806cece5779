// GlFunctions: the GLES 2 / GL 2.1 entry points the presenter uses, loaded through the context's
// own GetProcAddress (EGL or OSMesa), so one binary can drive libGLESv2 and libOSMesa side by side.
#pragma once

#include <GLES2/gl2.h>
#include <GLES2/gl2ext.h>

#include <string>

#include "gl/gl_loader.h"
#include "util/result.h"

namespace emboss {

struct GlFunctions {
#define EMBOSS_GL_FUNCTIONS(X)                                             \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                 \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                   \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                       \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                       \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                             \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                     \
  X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                         \
  X(PFNGLBUFFERDATAPROC, BufferData)                                       \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)               \
  X(PFNGLCLEARPROC, Clear)                                                 \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                       \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                 \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                 \
  X(PFNGLCREATESHADERPROC, CreateShader)                                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                 \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                       \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                 \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                   \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                               \
  X(PFNGLDISABLEPROC, Disable)                                             \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, DisableVertexAttribArray)           \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                       \
  X(PFNGLENABLEPROC, Enable)                                               \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)             \
  X(PFNGLFINISHPROC, Finish)                                               \
  X(PFNGLFLUSHPROC, Flush)                                                 \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                   \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                       \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                             \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                     \
  X(PFNGLGETERRORPROC, GetError)                                           \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                     \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                         \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                   \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                           \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                     \
  X(PFNGLGETSTRINGPROC, GetString)                                         \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                       \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                     \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                     \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                       \
  X(PFNGLSCISSORPROC, Scissor)                                             \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                   \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                       \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                 \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                                 \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                         \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                         \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                       \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                     \
  X(PFNGLVIEWPORTPROC, Viewport)

#define EMBOSS_GL_DECLARE(type, name) type name = nullptr;
  EMBOSS_GL_FUNCTIONS(EMBOSS_GL_DECLARE)
#undef EMBOSS_GL_DECLARE
};

// Loads every entry point; fails naming the first one missing.
Result<GlFunctions> loadGlFunctions(const GlProcLoader& loader);

// True when the space-separated GL_EXTENSIONS string of the current context names `extension`.
bool hasGlExtension(const GlFunctions& gl, const std::string& extension);

// "llvmpipe (LLVM 15.0.6, 256 bits)" -> "llvmpipe"; "V3D 4.2" stays as it is.
std::string shortRendererName(const std::string& glRenderer);

}  // namespace emboss

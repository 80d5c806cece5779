// The GL presenter: dirty-rectangle texture uploads, the fullscreen blit, and the overlay pass.
#include "gl/gl_presenter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "gl/gl_functions.h"
#include "gl/gl_text.h"

namespace emboss {
namespace {

// Attribute slots shared by all programs.
constexpr GLuint kPos = 0;    // blit: clip space; overlay: screen pixels
constexpr GLuint kAux = 1;    // blit: texture coordinate; shapes: pixels from the centre; text: atlas uv
constexpr GLuint kShape = 2;  // shapes: half width, half height, corner radius, ring half thickness (<0: rect)
constexpr GLuint kColor = 3;  // overlay colour, straight alpha

constexpr int kShapeFloats = 12;  // pos 2, aux 2, shape 4, colour 4
constexpr int kTextFloats = 8;    // pos 2, aux 2, colour 4
constexpr float kAaMargin = 1.0f;  // pixels added around a shape for its antialiased edge

const char* const kBlitVertex = R"(
attribute vec2 a_pos;
attribute vec2 a_aux;
varying vec2 v_aux;
void main() {
  v_aux = a_aux;
  gl_Position = vec4(a_pos, 0.0, 1.0);
}
)";

const char* const kBlitFragment = R"(
uniform sampler2D u_texture;
varying vec2 v_aux;
void main() {
  gl_FragColor = vec4(texture2D(u_texture, v_aux).rgb, 1.0);
}
)";

const char* const kOverlayVertex = R"(
attribute vec2 a_pos;
attribute vec2 a_aux;
attribute vec4 a_shape;
attribute vec4 a_color;
uniform vec2 u_screen;
varying vec2 v_aux;
varying vec4 v_shape;
varying vec4 v_color;
void main() {
  v_aux = a_aux;
  v_shape = a_shape;
  v_color = a_color;
  gl_Position = vec4(a_pos.x / u_screen.x * 2.0 - 1.0, 1.0 - a_pos.y / u_screen.y * 2.0, 0.0, 1.0);
}
)";

// Signed distance in pixels to the shape's edge (negative inside); coverage = 0.5 - distance,
// which gives a one-pixel antialiased edge and exact pixels for integer-aligned rectangles.
const char* const kShapeFragment = R"(
varying vec2 v_aux;
varying vec4 v_shape;
varying vec4 v_color;
void main() {
  float d;
  if (v_shape.w >= 0.0) {
    d = abs(length(v_aux) - v_shape.x) - v_shape.w;
  } else {
    vec2 q = abs(v_aux) - v_shape.xy + vec2(v_shape.z);
    d = length(max(q, 0.0)) + min(max(q.x, q.y), 0.0) - v_shape.z;
  }
  float coverage = clamp(0.5 - d, 0.0, 1.0);
  gl_FragColor = vec4(v_color.rgb, v_color.a * coverage);
}
)";

const char* const kTextFragment = R"(
uniform sampler2D u_texture;
varying vec2 v_aux;
varying vec4 v_color;
void main() {
  gl_FragColor = vec4(v_color.rgb, v_color.a * texture2D(u_texture, v_aux).r);
}
)";

std::string versionHeader(GlFlavor flavor, bool fragment) {
  if (flavor == GlFlavor::kDesktop) return "#version 120\n";
  if (!fragment) return "#version 100\n";
  // Pixel distances need more than fp16 on big screens; take highp where the GPU has it.
  return "#version 100\n#ifdef GL_FRAGMENT_PRECISION_HIGH\nprecision highp float;\n#else\n"
         "precision mediump float;\n#endif\n";
}

float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

void pushVertex(std::vector<float>& v, float x, float y, float ax, float ay, const float* shape,
                const OverlayColor& c) {
  v.insert(v.end(), {x, y, ax, ay});
  if (shape != nullptr) v.insert(v.end(), shape, shape + 4);
  v.insert(v.end(), {clamp01(c.r), clamp01(c.g), clamp01(c.b), clamp01(c.a)});
}

// Two triangles covering [x0,x1]x[y0,y1]; aux runs [a0,a1] the same way.
void pushQuad(std::vector<float>& v, float x0, float y0, float x1, float y1, float ax0, float ay0, float ax1,
              float ay1, const float* shape, const OverlayColor& c) {
  pushVertex(v, x0, y0, ax0, ay0, shape, c);
  pushVertex(v, x1, y0, ax1, ay0, shape, c);
  pushVertex(v, x0, y1, ax0, ay1, shape, c);
  pushVertex(v, x1, y0, ax1, ay0, shape, c);
  pushVertex(v, x1, y1, ax1, ay1, shape, c);
  pushVertex(v, x0, y1, ax0, ay1, shape, c);
}

bool finite(float a, float b, float c, float d) {
  return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d);
}

}  // namespace

struct GlPresenter::Impl {
  GlFunctions gl{};
  GlFlavor flavor = GlFlavor::kGles2;
  int width = 0, height = 0;
  bool offscreen = false;
  bool rowLength = false;
  GLint maxTextureSize = 0;
  std::string renderer;
  std::string lastError;

  GLuint blitProgram = 0, shapeProgram = 0, textProgram = 0;
  GLint shapeScreen = -1, textScreen = -1;
  GLuint quadBuffer = 0, streamBuffer = 0;
  GLuint frameTexture = 0;
  int textureWidth = 0, textureHeight = 0;
  bool haveFrame = false;
  bool drawnOnce = false;        // the offscreen target holds a whole drawn frame
  GLuint atlasTexture = 0;
  GLuint targetFbo = 0, targetTexture = 0;      // offscreen target
  GLuint snapshotFbo = 0, snapshotTexture = 0;  // screenshot() of an on-screen target

  std::unique_ptr<GlyphAtlas> atlas;
  Overlay overlay;  // the last one drawn, for screenshot()
  std::vector<std::uint8_t> packed;
  std::vector<float> vertices;
  GlPresenterStats stats;

  ~Impl();
  Status init(const GlProcLoader& loader, GlFlavor flavor, int width, int height, bool offscreen,
              const GlPresenterSettings& settings);
  Result<GLuint> buildProgram(const char* name, const char* vertex, const char* fragment);
  Result<GLuint> createTargetTexture(GLuint* fbo);
  // Returns whether the whole frame was sent (the first frame, a new size).
  bool uploadFrame(const Image& frame, std::span<const Rect> dirty);
  // Draws the frame and the overlay into fbo, within `areas` only (image pixels, top-down rows)
  // when given, everywhere when not.
  void drawScene(GLuint fbo, const std::vector<Rect>* areas = nullptr);
  void drawLayers();
  void drawShapes();
  void drawTexts();
  void drawGlyphs(const std::vector<float>& glyphVertices);
  void bindStream(const std::vector<float>& data, int floatsPerVertex, bool withShape);
};

GlPresenter::Impl::~Impl() {
  if (gl.DeleteProgram == nullptr) return;  // never got as far as loading GL
  for (GLuint p : {blitProgram, shapeProgram, textProgram}) {
    if (p != 0) gl.DeleteProgram(p);
  }
  for (GLuint b : {quadBuffer, streamBuffer}) {
    if (b != 0) gl.DeleteBuffers(1, &b);
  }
  for (GLuint t : {frameTexture, atlasTexture, targetTexture, snapshotTexture}) {
    if (t != 0) gl.DeleteTextures(1, &t);
  }
  for (GLuint f : {targetFbo, snapshotFbo}) {
    if (f != 0) gl.DeleteFramebuffers(1, &f);
  }
}

Result<GLuint> GlPresenter::Impl::buildProgram(const char* name, const char* vertex, const char* fragment) {
  GLuint shaders[2] = {0, 0};
  const GLenum types[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  const char* bodies[2] = {vertex, fragment};
  auto cleanup = [&] {
    for (GLuint s : shaders) {
      if (s != 0) gl.DeleteShader(s);
    }
  };
  for (int i = 0; i < 2; ++i) {
    const std::string header = versionHeader(flavor, i == 1);
    const char* parts[2] = {header.c_str(), bodies[i]};
    shaders[i] = gl.CreateShader(types[i]);
    gl.ShaderSource(shaders[i], 2, parts, nullptr);
    gl.CompileShader(shaders[i]);
    GLint ok = 0;
    gl.GetShaderiv(shaders[i], GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[1024] = {};
      gl.GetShaderInfoLog(shaders[i], sizeof log, nullptr, log);
      cleanup();
      return fail(std::string("GL: the ") + name + (i == 0 ? " vertex" : " fragment") +
                  " shader does not compile on " + renderer + ": " + log);
    }
  }
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, shaders[0]);
  gl.AttachShader(program, shaders[1]);
  gl.BindAttribLocation(program, kPos, "a_pos");
  gl.BindAttribLocation(program, kAux, "a_aux");
  gl.BindAttribLocation(program, kShape, "a_shape");
  gl.BindAttribLocation(program, kColor, "a_color");
  gl.LinkProgram(program);
  cleanup();  // flagged for deletion; they live on inside the program
  GLint ok = 0;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
    gl.DeleteProgram(program);
    return fail(std::string("GL: the ") + name + " program does not link on " + renderer + ": " + log);
  }
  gl.UseProgram(program);
  if (const GLint sampler = gl.GetUniformLocation(program, "u_texture"); sampler >= 0) gl.Uniform1i(sampler, 0);
  return program;
}

Result<GLuint> GlPresenter::Impl::createTargetTexture(GLuint* fbo) {
  GLuint texture = 0;
  gl.GenTextures(1, &texture);
  gl.BindTexture(GL_TEXTURE_2D, texture);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  gl.GenFramebuffers(1, fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, *fbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    gl.DeleteFramebuffers(1, fbo);
    *fbo = 0;
    gl.DeleteTextures(1, &texture);
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", status);
    return fail("GL: cannot render into a " + std::to_string(width) + "x" + std::to_string(height) +
                " RGBA texture on " + renderer + " (framebuffer status " + code + ")");
  }
  return texture;
}

Status GlPresenter::Impl::init(const GlProcLoader& loader, GlFlavor glFlavor, int w, int h, bool offscreenTarget,
                               const GlPresenterSettings& settings) {
  flavor = glFlavor;
  width = w;
  height = h;
  offscreen = offscreenTarget;
  if (w <= 0 || h <= 0) return fail("GL: bad target size " + std::to_string(w) + "x" + std::to_string(h));
  auto loaded = loadGlFunctions(loader);
  if (!loaded) return fail(loaded.error());
  gl = *loaded;
  const auto* rendererString = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
  if (rendererString == nullptr) return fail("GL: no current context (glGetString(GL_RENDERER) is null)");
  renderer = shortRendererName(rendererString);
  gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
  if (std::max(w, h) > maxTextureSize) {
    return fail("GL: " + renderer + " cannot hold a " + std::to_string(w) + "x" + std::to_string(h) +
                " frame (max texture size " + std::to_string(maxTextureSize) + "); pick a smaller mode");
  }
  // Desktop GL always has GL_UNPACK_ROW_LENGTH; GLES 2 only with GL_EXT_unpack_subimage.
  rowLength = settings.allowRowLengthUpload &&
              (flavor == GlFlavor::kDesktop || hasGlExtension(gl, "GL_EXT_unpack_subimage"));

  auto blit = buildProgram("frame", kBlitVertex, kBlitFragment);
  if (!blit) return fail(blit.error());
  blitProgram = *blit;
  auto shape = buildProgram("shape", kOverlayVertex, kShapeFragment);
  if (!shape) return fail(shape.error());
  shapeProgram = *shape;
  shapeScreen = gl.GetUniformLocation(shapeProgram, "u_screen");
  auto text = buildProgram("text", kOverlayVertex, kTextFragment);
  if (!text) return fail(text.error());
  textProgram = *text;
  textScreen = gl.GetUniformLocation(textProgram, "u_screen");

  const float quad[] = {-1, 1, 0, 0, -1, -1, 0, 1, 1, 1, 1, 0, 1, -1, 1, 1};
  gl.GenBuffers(1, &quadBuffer);
  gl.BindBuffer(GL_ARRAY_BUFFER, quadBuffer);
  gl.BufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  gl.GenBuffers(1, &streamBuffer);
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);

  gl.GenTextures(1, &frameTexture);
  gl.BindTexture(GL_TEXTURE_2D, frameTexture);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

  // The glyph atlas: one 8-bit channel (GL_LUMINANCE exists in GLES 2 and compatibility GL).
  gl.GenTextures(1, &atlasTexture);
  gl.BindTexture(GL_TEXTURE_2D, atlasTexture);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  {
    const std::vector<std::uint8_t> zeros(static_cast<std::size_t>(GlyphAtlas::kAtlasSize) * GlyphAtlas::kAtlasSize, 0);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE, GlyphAtlas::kAtlasSize, GlyphAtlas::kAtlasSize, 0, GL_LUMINANCE,
                  GL_UNSIGNED_BYTE, zeros.data());
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  }
  auto atlasOrError = GlyphAtlas::create(settings.fontPath, [this](int x, int y, int w, int h, const std::uint8_t* px) {
    gl.BindTexture(GL_TEXTURE_2D, atlasTexture);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexSubImage2D(GL_TEXTURE_2D, 0, x, y, w, h, GL_LUMINANCE, GL_UNSIGNED_BYTE, px);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  });
  if (!atlasOrError) return fail(atlasOrError.error());
  atlas = std::move(*atlasOrError);

  if (offscreen) {
    auto target = createTargetTexture(&targetFbo);
    if (!target) return fail(target.error());
    targetTexture = *target;
  }
  if (const GLenum error = gl.GetError(); error != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", error);
    return fail("GL: setting up the presenter on " + renderer + " failed (GL error " + code + ")");
  }
  return Ok{};
}

bool GlPresenter::Impl::uploadFrame(const Image& frame, std::span<const Rect> dirty) {
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, frameTexture);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  const bool sizeChanged = frame.width != textureWidth || frame.height != textureHeight;
  if (!haveFrame || sizeChanged) {
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, frame.width, frame.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                  frame.rgba.data());
    textureWidth = frame.width;
    textureHeight = frame.height;
    haveFrame = true;
    ++stats.fullUploads;
    stats.uploadedPixels += static_cast<std::uint64_t>(frame.width) * frame.height;
    // 1:1 pixels stay exact; a frame of another size is scaled smoothly.
    const GLint filter = frame.width == width && frame.height == height ? GL_NEAREST : GL_LINEAR;
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    return true;  // the whole frame
  }
  for (const Rect& r : dirty) {
    const int x0 = std::max(r.x, 0), y0 = std::max(r.y, 0);
    const int x1 = std::min(r.x + std::max(r.w, 0), frame.width);
    const int y1 = std::min(r.y + std::max(r.h, 0), frame.height);
    const int w = x1 - x0, h = y1 - y0;
    if (w <= 0 || h <= 0) continue;
    if (w == frame.width) {  // whole rows are contiguous already
      gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, y0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, frame.pixel(0, y0));
    } else if (rowLength) {
      gl.PixelStorei(GL_UNPACK_ROW_LENGTH_EXT, frame.width);
      gl.TexSubImage2D(GL_TEXTURE_2D, 0, x0, y0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, frame.pixel(x0, y0));
      gl.PixelStorei(GL_UNPACK_ROW_LENGTH_EXT, 0);
    } else {
      const std::size_t rowBytes = static_cast<std::size_t>(w) * 4;
      packed.resize(rowBytes * h);
      for (int row = 0; row < h; ++row) {
        std::memcpy(&packed[row * rowBytes], frame.pixel(x0, y0 + row), rowBytes);
      }
      gl.TexSubImage2D(GL_TEXTURE_2D, 0, x0, y0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, packed.data());
    }
    ++stats.rectUploads;
    stats.uploadedPixels += static_cast<std::uint64_t>(w) * h;
  }
  return false;
}

void GlPresenter::Impl::bindStream(const std::vector<float>& data, int floatsPerVertex, bool withShape) {
  gl.BindBuffer(GL_ARRAY_BUFFER, streamBuffer);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STREAM_DRAW);
  const GLsizei stride = floatsPerVertex * static_cast<GLsizei>(sizeof(float));
  auto offset = [](int floats) { return reinterpret_cast<const void*>(static_cast<std::uintptr_t>(floats * sizeof(float))); };
  gl.EnableVertexAttribArray(kPos);
  gl.VertexAttribPointer(kPos, 2, GL_FLOAT, GL_FALSE, stride, offset(0));
  gl.EnableVertexAttribArray(kAux);
  gl.VertexAttribPointer(kAux, 2, GL_FLOAT, GL_FALSE, stride, offset(2));
  if (withShape) {
    gl.EnableVertexAttribArray(kShape);
    gl.VertexAttribPointer(kShape, 4, GL_FLOAT, GL_FALSE, stride, offset(4));
  } else {
    gl.DisableVertexAttribArray(kShape);
  }
  gl.EnableVertexAttribArray(kColor);
  gl.VertexAttribPointer(kColor, 4, GL_FLOAT, GL_FALSE, stride, offset(withShape ? 8 : 4));
}

void GlPresenter::Impl::drawShapes() {
  vertices.clear();
  for (const OverlayRect& r : overlay.rects) {
    if (!finite(r.x, r.y, r.w, r.h) || r.w <= 0 || r.h <= 0 || r.color.a <= 0) continue;
    const float hw = r.w / 2, hh = r.h / 2;
    const float radius = std::isfinite(r.radius) ? std::clamp(r.radius, 0.0f, std::min(hw, hh)) : 0.0f;
    const float shape[4] = {hw, hh, radius, -1.0f};
    const float ex = hw + kAaMargin, ey = hh + kAaMargin;
    const float cx = r.x + hw, cy = r.y + hh;
    pushQuad(vertices, cx - ex, cy - ey, cx + ex, cy + ey, -ex, -ey, ex, ey, shape, r.color);
  }
  for (const OverlayRing& g : overlay.rings) {
    if (!finite(g.cx, g.cy, g.r, g.thickness) || g.r < 0 || g.thickness <= 0 || g.color.a <= 0) continue;
    const float shape[4] = {g.r, 0.0f, 0.0f, g.thickness / 2};
    const float e = g.r + g.thickness / 2 + kAaMargin;
    pushQuad(vertices, g.cx - e, g.cy - e, g.cx + e, g.cy + e, -e, -e, e, e, shape, g.color);
  }
  if (vertices.empty()) return;
  gl.UseProgram(shapeProgram);
  gl.Uniform2f(shapeScreen, static_cast<float>(width), static_cast<float>(height));
  bindStream(vertices, kShapeFloats, true);
  gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / kShapeFloats));
}

void GlPresenter::Impl::drawGlyphs(const std::vector<float>& glyphVertices) {
  if (glyphVertices.empty()) return;
  gl.UseProgram(textProgram);
  gl.Uniform2f(textScreen, static_cast<float>(width), static_cast<float>(height));
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, atlasTexture);
  bindStream(glyphVertices, kTextFloats, false);
  gl.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(glyphVertices.size() / kTextFloats));
}

void GlPresenter::Impl::drawTexts() {
  vertices.clear();
  std::vector<PlacedGlyph> placed;
  constexpr float kScale = 1.0f / GlyphAtlas::kAtlasSize;
  for (const OverlayText& t : overlay.texts) {
    if (t.text.empty() || !finite(t.x, t.y, t.size, 0) || t.size <= 0 || t.color.a <= 0) continue;
    placed.clear();
    if (!atlas->layout(t.text, t.x, t.y, t.size, placed)) {
      // The atlas is full: draw what refers to it now, start it afresh, and lay out again.
      drawGlyphs(vertices);
      vertices.clear();
      atlas->reset();
      placed.clear();
      if (!atlas->layout(t.text, t.x, t.y, t.size, placed)) continue;  // cannot fit even alone
    }
    for (const PlacedGlyph& p : placed) {
      const AtlasGlyph& g = *p.glyph;
      pushQuad(vertices, static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.x + g.width),
               static_cast<float>(p.y + g.height), g.atlasX * kScale, g.atlasY * kScale,
               (g.atlasX + g.width) * kScale, (g.atlasY + g.height) * kScale, nullptr, t.color);
    }
  }
  drawGlyphs(vertices);
}

void GlPresenter::Impl::drawScene(GLuint fbo, const std::vector<Rect>* areas) {
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  gl.Viewport(0, 0, width, height);
  if (!areas) {
    drawLayers();
    stats.drawnPixels += static_cast<std::uint64_t>(width) * height;
    return;
  }
  // Each area on its own: what lies outside them is what the target holds already.
  gl.Enable(GL_SCISSOR_TEST);
  for (const Rect& r : *areas) {
    gl.Scissor(r.x, height - (r.y + r.h), r.w, r.h);  // GL's rows run bottom up
    drawLayers();
    stats.drawnPixels += static_cast<std::uint64_t>(r.w) * r.h;
  }
  gl.Disable(GL_SCISSOR_TEST);
}

void GlPresenter::Impl::drawLayers() {
  gl.Disable(GL_BLEND);
  if (!haveFrame) {
    gl.ClearColor(0, 0, 0, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
  } else {
    gl.UseProgram(blitProgram);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, frameTexture);
    gl.BindBuffer(GL_ARRAY_BUFFER, quadBuffer);
    gl.EnableVertexAttribArray(kPos);
    gl.VertexAttribPointer(kPos, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    gl.EnableVertexAttribArray(kAux);
    gl.VertexAttribPointer(kAux, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                           reinterpret_cast<const void*>(2 * sizeof(float)));
    gl.DisableVertexAttribArray(kShape);
    gl.DisableVertexAttribArray(kColor);
    gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  }
  // Straight-alpha "over" for colour; the destination alpha stays opaque.
  gl.Enable(GL_BLEND);
  gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  drawShapes();
  drawTexts();
  gl.Disable(GL_BLEND);
  for (GLuint a : {kPos, kAux, kShape, kColor}) gl.DisableVertexAttribArray(a);
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);
}

namespace {

// The pixels a shape's quad covers (its antialiased margin and a pixel of rounding included).
Rect boxOf(float x0, float y0, float x1, float y1) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return {-1 << 20, -1 << 20, 1 << 21, 1 << 21};
  const float m = kAaMargin + 1.0f;
  const int a = static_cast<int>(std::floor(std::max(x0 - m, -1e6f))), b = static_cast<int>(std::floor(std::max(y0 - m, -1e6f)));
  const int c = static_cast<int>(std::ceil(std::min(x1 + m, 1e6f))), d = static_cast<int>(std::ceil(std::min(y1 + m, 1e6f)));
  return {a, b, c - a, d - b};
}
Rect boxOf(const OverlayRect& r) { return boxOf(r.x, r.y, r.x + std::max(r.w, 0.0f), r.y + std::max(r.h, 0.0f)); }
Rect boxOf(const OverlayRing& g) {
  const float e = g.r + g.thickness / 2;
  return boxOf(g.cx - e, g.cy - e, g.cx + e, g.cy + e);
}
bool same(const OverlayColor& a, const OverlayColor& b) { return a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a; }
bool same(const OverlayRect& a, const OverlayRect& b) {
  return a.x == b.x && a.y == b.y && a.w == b.w && a.h == b.h && a.radius == b.radius && same(a.color, b.color);
}
bool same(const OverlayRing& a, const OverlayRing& b) {
  return a.cx == b.cx && a.cy == b.cy && a.r == b.r && a.thickness == b.thickness && same(a.color, b.color);
}
bool same(const OverlayText& a, const OverlayText& b) {
  return a.x == b.x && a.y == b.y && a.size == b.size && a.text == b.text && same(a.color, b.color);
}

// Where the overlay changed from `was` to `now`: the old and the new places of every shape that
// differs (position in the list); false when a text changed (redraw everything: its glyphs' boxes
// are the atlas's to know).
template <class T>
void shapeDamage(const std::vector<T>& was, const std::vector<T>& now, std::vector<Rect>& out) {
  for (size_t i = 0; i < std::max(was.size(), now.size()); ++i) {
    if (i < was.size() && i < now.size() && same(was[i], now[i])) continue;
    if (i < was.size()) out.push_back(boxOf(was[i]));
    if (i < now.size()) out.push_back(boxOf(now[i]));
  }
}
bool overlayDamage(const Overlay& was, const Overlay& now, std::vector<Rect>& out) {
  if (was.texts.size() != now.texts.size()) return false;
  for (size_t i = 0; i < now.texts.size(); ++i)
    if (!same(was.texts[i], now.texts[i])) return false;
  shapeDamage(was.rects, now.rects, out);
  shapeDamage(was.rings, now.rings, out);
  return true;
}

// The areas clipped to the screen, overlapping ones united until none overlaps; more than a
// handful become their hull (each area is one more pass over the layers).
std::vector<Rect> tidy(std::vector<Rect> areas, int width, int height) {
  std::vector<Rect> out;
  for (Rect r : areas) {
    const int x0 = std::max(r.x, 0), y0 = std::max(r.y, 0);
    const int x1 = std::min(r.x + std::max(r.w, 0), width), y1 = std::min(r.y + std::max(r.h, 0), height);
    if (x1 > x0 && y1 > y0) out.push_back({x0, y0, x1 - x0, y1 - y0});
  }
  auto overlap = [](const Rect& a, const Rect& b) { return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h; };
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < out.size() && !merged; ++i)
      for (size_t j = i + 1; j < out.size() && !merged; ++j)
        if (overlap(out[i], out[j])) {
          out[i] = unite(out[i], out[j]);
          out.erase(out.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
  }
  if (out.size() > 8) {
    Rect all;
    for (const Rect& r : out) all = unite(all, r);
    out = {all};
  }
  return out;
}

}  // namespace

// ---- GlPresenter

GlPresenter::GlPresenter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlPresenter::~GlPresenter() = default;

Result<std::unique_ptr<GlPresenter>> GlPresenter::create(const GlProcLoader& loader, GlFlavor flavor, int width,
                                                         int height, bool offscreen,
                                                         const GlPresenterSettings& settings) {
  auto impl = std::make_unique<Impl>();
  if (Status s = impl->init(loader, flavor, width, height, offscreen, settings); !s) return fail(s.error());
  return std::unique_ptr<GlPresenter>(new GlPresenter(std::move(impl)));
}

int GlPresenter::width() const { return impl_->width; }
int GlPresenter::height() const { return impl_->height; }
const std::string& GlPresenter::renderer() const { return impl_->renderer; }
const char* GlPresenter::uploadPath() const { return impl_->rowLength ? "unpack-row-length" : "packed copy"; }
const GlPresenterStats& GlPresenter::stats() const { return impl_->stats; }
const std::string& GlPresenter::lastError() const { return impl_->lastError; }

bool GlPresenter::draw(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) {
  Impl& m = *impl_;
  if (frame.width <= 0 || frame.height <= 0 ||
      frame.rgba.size() != static_cast<std::size_t>(frame.width) * frame.height * 4) {
    m.lastError = "present: the frame is empty or its pixel buffer does not match its size";
    return false;
  }
  if (std::max(frame.width, frame.height) > m.maxTextureSize) {
    m.lastError = "present: a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                  " frame is larger than the GPU's textures (" + std::to_string(m.maxTextureSize) + ")";
    return false;
  }
  const bool whole = m.uploadFrame(frame, dirty);
  // An offscreen target we own keeps its pixels: after a whole first frame, only the damage is
  // drawn again (a window's back buffer is undefined after a swap: drawn whole every time). The
  // same pixels as a whole redraw: every pixel drawn is drawn from the frame and the whole overlay.
  std::vector<Rect> areas;
  bool partial = m.offscreen && m.drawnOnce && !whole && frame.width == m.width && frame.height == m.height &&
                 overlayDamage(m.overlay, overlay, areas);
  if (partial) {
    areas.insert(areas.end(), dirty.begin(), dirty.end());
    areas = tidy(std::move(areas), m.width, m.height);
  }
  m.overlay = overlay;
  if (partial) {
    ++m.stats.partialFrames;
    if (!areas.empty()) m.drawScene(m.targetFbo, &areas);
  } else {
    m.drawScene(m.offscreen ? m.targetFbo : 0);
    m.drawnOnce = m.offscreen;
  }
  m.gl.Flush();
  ++m.stats.frames;
  if (const GLenum error = m.gl.GetError(); error != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", error);
    m.lastError = std::string("present: GL error ") + code + " on " + m.renderer;
    return false;
  }
  return true;
}

Image GlPresenter::screenshot() {
  Impl& m = *impl_;
  GLuint fbo = m.targetFbo;
  if (!m.offscreen) {
    if (m.snapshotFbo == 0) {
      auto texture = m.createTargetTexture(&m.snapshotFbo);
      if (!texture) {
        m.lastError = texture.error();
        return Image();
      }
      m.snapshotTexture = *texture;
    }
    fbo = m.snapshotFbo;
    m.drawScene(fbo);
  }
  Image image(m.width, m.height);
  m.gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  m.gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  m.gl.ReadPixels(0, 0, m.width, m.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  m.gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  // GL rows run bottom up; Image rows top down.
  const std::size_t rowBytes = static_cast<std::size_t>(m.width) * 4;
  std::vector<std::uint8_t> row(rowBytes);
  for (int y = 0; y < m.height / 2; ++y) {
    std::uint8_t* a = image.pixel(0, y);
    std::uint8_t* b = image.pixel(0, m.height - 1 - y);
    std::memcpy(row.data(), a, rowBytes);
    std::memcpy(a, b, rowBytes);
    std::memcpy(b, row.data(), rowBytes);
  }
  return image;
}

float GlPresenter::measureText(const std::string& text, float size) { return impl_->atlas->measure(text, size); }

}  // namespace emboss

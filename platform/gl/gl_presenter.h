// GlPresenter: the GL drawing shared by the EGL and OSMesa displays -- the frame as a texture fed
// with dirty rectangles, drawn fullscreen, then the Overlay (SDF rects and rings, FreeType text).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "devices/display.h"
#include "gl/gl_loader.h"
#include "render/image.h"
#include "util/result.h"

namespace emboss {

// Knobs every GL back end factory accepts (the defaults are right for the kiosk).
struct GlPresenterSettings {
  std::string fontPath;              // empty: $EMBOSS_FONT, else DejaVu Sans
  bool allowRowLengthUpload = true;  // false: always pack dirty rectangles (the plain GLES 2 path)
};

// Counters for tests and the diagnostics screen.
struct GlPresenterStats {
  std::uint64_t frames = 0;
  std::uint64_t fullUploads = 0;     // the whole frame (first frame, size change)
  std::uint64_t rectUploads = 0;     // glTexSubImage2D calls for dirty rectangles
  std::uint64_t uploadedPixels = 0;  // pixels sent to the texture, full uploads included
  // Offscreen targets keep what was drawn: a frame draws again only its damage (the dirty
  // rectangles and the overlay's shapes that moved or changed, old and new places).
  std::uint64_t drawnPixels = 0;     // pixels drawn again, over all frames
  std::uint64_t partialFrames = 0;   // frames drawn only where they changed (none: nothing changed)
};

// Needs its context current for every call, destruction included. Not thread-safe.
class GlPresenter {
 public:
  // Draws into the current framebuffer (a window or OSMesa buffer) of width x height, or, with
  // `offscreen`, into a texture-backed FBO of that size that it owns (EGL surfaceless).
  static Result<std::unique_ptr<GlPresenter>> create(const GlProcLoader& loader, GlFlavor flavor, int width,
                                                     int height, bool offscreen,
                                                     const GlPresenterSettings& settings = {});
  ~GlPresenter();
  GlPresenter(const GlPresenter&) = delete;
  GlPresenter& operator=(const GlPresenter&) = delete;

  int width() const;
  int height() const;
  // GL_RENDERER, shortened ("llvmpipe", "V3D 4.2").
  const std::string& renderer() const;
  // How dirty rectangles travel: "unpack-row-length" (one call a rectangle, straight from the
  // frame) or "packed copy" (rows copied together first; GLES 2 without GL_EXT_unpack_subimage).
  const char* uploadPath() const;
  const GlPresenterStats& stats() const;

  // Uploads the dirty rectangles of `frame` (all of it the first time or after a size change),
  // draws it over the whole target, then the overlay. Does not swap. False (see lastError())
  // when the frame is unusable or GL reports an error.
  bool draw(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay);
  // The last drawn picture, top row first, as it is on screen. Redraws it into a private FBO
  // unless the target is offscreen already, so a window's buffers are never disturbed.
  Image screenshot();
  // Width in pixels of `text` drawn as OverlayText with this size (for centring labels).
  float measureText(const std::string& text, float size);
  const std::string& lastError() const;

 private:
  struct Impl;
  explicit GlPresenter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace emboss

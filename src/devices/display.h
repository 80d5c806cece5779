// The display: shows the traced frame (updated in dirty rectangles) under a UI overlay.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "render/image.h"

namespace emboss {

// The overlay is a list of simple primitives in screen pixels (origin top left), built by the app
// each frame and drawn by the display back end over the traced picture (with GLES where there is
// GL, into the picture for the software path).
struct OverlayColor {
  float r = 1, g = 1, b = 1, a = 1;
};
struct OverlayRect {
  float x, y, w, h;
  OverlayColor color;
  float radius = 0;  // rounded corners; radius >= min(w,h)/2 makes a disc or a pill
};
struct OverlayRing {  // an outline circle, e.g. the tool's footprint under the pen
  float cx, cy, r, thickness;
  OverlayColor color;
};
struct OverlayText {
  float x, y;      // top-left corner of the text box
  float size;      // pixel height of a capital letter
  std::string text;  // UTF-8
  OverlayColor color;
};
struct Overlay {
  std::vector<OverlayRect> rects;
  std::vector<OverlayRing> rings;
  std::vector<OverlayText> texts;
  void clear() {
    rects.clear();
    rings.clear();
    texts.clear();
  }
};

class Display {
 public:
  virtual ~Display() = default;
  virtual std::string name() const = 0;
  virtual int width() const = 0;
  virtual int height() const = 0;
  // Shows `frame` (width() x height()); only `dirty` rectangles changed since the last call (an
  // empty span after a resize means all). Returns false when the output is lost (the caller then
  // re-creates the display).
  virtual bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) = 0;
  // The last presented picture, overlay included, as it is on screen (for snapshots and tests).
  virtual Image screenshot() = 0;
};

}  // namespace emboss

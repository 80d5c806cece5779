// Pixel spans: a set of pixels given row by row, what a dirty update traces (the projection of a
// stroke's support, tighter than its rectangle), and the convex outlines in the image they come from.
#pragma once

#include <span>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include "render/image.h"

namespace emboss {

// Row box.y + i holds the pixels [rows[i].x0, rows[i].x1) (none when x1 <= x0); all lie in box.
struct PixelSpans {
  struct Span {
    int x0 = 0, x1 = 0;
    bool empty() const { return x1 <= x0; }
  };
  Rect box;
  std::vector<Span> rows;

  // Every pixel of r.
  static PixelSpans of(const Rect& r);
  bool empty() const { return area() == 0; }
  long area() const;
  bool contains(int x, int y) const;
  // Row y's span (empty outside the box).
  Span row(int y) const;
  // Every pixel within n pixels of one of these (each way, diagonals included), clipped to a
  // w x h image.
  PixelSpans grown(int n, int w, int h) const;
  // Both sets (each row the hull of its two spans: a pixel between them is kept too).
  PixelSpans united(const PixelSpans& o) const;
  // The rows [y0, y1) of these.
  PixelSpans band(int y0, int y1) const;
  // The first n of these pixels in row order (whole rows, then the leftmost of the next row's
  // span), and the rest.
  std::pair<PixelSpans, PixelSpans> split(long n) const;
};

// Collects convex polygons in image coordinates (pixel x's centre at x + 0.5) and gives the pixels
// whose centres lie within one pixel of one of them, each way (as a rectangle of projected
// corners grown by a pixel would), clipped to a w x h image.
class SpanBuilder {
 public:
  SpanBuilder(int width, int height) : w_(width), h_(height) {}
  // The convex hull of the points is taken: any order, repeats allowed.
  void addHullOf(std::span<const glm::dvec2> points);
  PixelSpans take() const;

 private:
  int w_, h_;
  int y0_ = 0, y1_ = 0;  // rows [y0_, y1_) seen so far
  std::vector<PixelSpans::Span> rows_;  // by row from y0_
};

}  // namespace emboss

// Axis-aligned boxes in 2D (the plate's plane) and 3D, in millimetres.
#pragma once

#include <algorithm>
#include <limits>

namespace emboss {

struct Box2 {
  double x0 = std::numeric_limits<double>::infinity(), y0 = std::numeric_limits<double>::infinity();
  double x1 = -std::numeric_limits<double>::infinity(), y1 = -std::numeric_limits<double>::infinity();

  bool empty() const { return !(x0 <= x1 && y0 <= y1); }
  bool contains(double x, double y) const { return x0 <= x && x <= x1 && y0 <= y && y <= y1; }
  bool overlaps(const Box2& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
  void extend(double x, double y) {
    x0 = std::min(x0, x), x1 = std::max(x1, x);
    y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  void extend(const Box2& o) {
    x0 = std::min(x0, o.x0), x1 = std::max(x1, o.x1);
    y0 = std::min(y0, o.y0), y1 = std::max(y1, o.y1);
  }
  Box2 grown(double r) const { return {x0 - r, y0 - r, x1 + r, y1 + r}; }
  // The common part of two boxes (empty() when they do not meet).
  Box2 intersected(const Box2& o) const {
    return {std::max(x0, o.x0), std::max(y0, o.y0), std::min(x1, o.x1), std::min(y1, o.y1)};
  }
  bool operator==(const Box2&) const = default;
};

struct Box3 {
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  Box2 xy() const { return {x0, y0, x1, y1}; }
};

}  // namespace emboss

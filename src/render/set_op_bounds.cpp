// Bounds of the set operations.
#include "render/set_op_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace emboss {

namespace {

// A little slack for rounding: every bound here is widened by it.
Interval widen(const Interval& v) {
  const double m = 1e-12 + 1e-12 * std::max(std::abs(v.lo), std::abs(v.hi));
  return {v.lo - m, v.hi + m};
}

}  // namespace

Interval toolBound(const ToolShape& tool, const P3<Interval>& p) {
  switch (tool.type) {
    case ToolShape::Type::Sphere:
      return widen(Interval(tool.r * tool.r) -
                   (sqr(p.x - Interval(tool.center.x)) + sqr(p.y - Interval(tool.center.y)) + sqr(p.z - Interval(tool.center.z))));
    case ToolShape::Type::Cylinder: {
      // r^2 - the squared distance to the axis segment a-b: the distance from the box to the
      // segment lies between the distances of its nearest and farthest corners' bounds.
      const double ex = tool.end.x - tool.center.x, ey = tool.end.y - tool.center.y, ez = tool.end.z - tool.center.z;
      const double len2 = ex * ex + ey * ey + ez * ez;
      const Interval px = p.x - Interval(tool.center.x), py = p.y - Interval(tool.center.y), pz = p.z - Interval(tool.center.z);
      Interval t(0.0);
      if (len2 > 0.0) {
        t = (px * Interval(ex) + py * Interval(ey) + pz * Interval(ez)) * Interval(1.0 / len2);
        t = Interval(std::clamp(t.lo, 0.0, 1.0), std::clamp(t.hi, 0.0, 1.0));
      }
      const Interval d2 = sqr(px - t * Interval(ex)) + sqr(py - t * Interval(ey)) + sqr(pz - t * Interval(ez));
      // Interval arithmetic over t and p together is conservative (it contains every pairing).
      return widen(Interval(tool.r * tool.r) - d2);
    }
    case ToolShape::Type::Flat:
      return widen(min(min(Interval(tool.half.x) - abs(p.x - Interval(tool.center.x)),
                           Interval(tool.half.y) - abs(p.y - Interval(tool.center.y))),
                       Interval(tool.half.z) - abs(p.z - Interval(tool.center.z))));
  }
  return Interval::whole();
}

Interval combineBound(const PreparedOp& prepared, const Interval& f, const P3<Interval>& box) {
  const Operation& op = prepared.op();
  const Interval g = toolBound(op.tool, box);
  const double fAbs = std::max(std::abs(f.lo), std::abs(f.hi));
  const Interval f2 = sqr(f), g2 = sqr(g);
  Interval c;
  if (op.kind == OpKind::Subtract) {
    c = Interval(std::min(f.lo, -g.hi), std::min(f.hi, -g.lo));
  } else {
    // s = g + sqrt(f^2 + g^2) >= 0; at most |f| + 2 max(g, 0), and f^2 / (2 |g|) when g <= 0.
    double sHi = fAbs + 2.0 * std::max(g.hi, 0.0);
    if (g.hi < 0.0) sHi = std::min(sHi, f2.hi / (2.0 * -g.hi));
    const double sLo = g.lo > 0.0 ? 2.0 * g.lo : 0.0;
    // bump = a1 / (1 + (f/a2)^2 + (g/a3)^2).
    const double dLo = 1.0 + f2.lo / (op.a2 * op.a2) + g2.lo / (op.a3 * op.a3);
    const double dHi = 1.0 + f2.hi / (op.a2 * op.a2) + g2.hi / (op.a3 * op.a3);
    const double b1 = op.a1 / dLo, b2 = op.a1 / dHi;
    const double bLo = std::min(b1, b2), bHi = std::max(b1, b2);
    if (op.kind == OpKind::BlendUnion)
      c = Interval(f.lo + sLo + bLo, f.hi + sHi + bHi);
    else
      c = Interval(f.lo - sHi + bLo, f.hi - sLo + bHi);
  }
  // The taper's weight w in [0, 1]: f + w (c - f) lies between f and c.
  return widen(Interval(std::min(f.lo, c.lo), std::max(f.hi, c.hi)));
}

}  // namespace emboss

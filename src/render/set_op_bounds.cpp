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

// s = g + sqrt(f^2 + g^2) >= 0, without cancellation: f^2 / (sqrt(f^2 + g^2) - g) when g < 0.
double rSum(double f, double g) {
  const double r = std::sqrt(f * f + g * g);
  return g >= 0.0 ? g + r : (r - g > 0.0 ? f * f / (r - g) : 0.0);
}

}  // namespace

using set_op_bounds::bumpHi;
using set_op_bounds::widenHi;

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

double SetOpUpper::over(double fHi, const P3<Interval>& box) const {
  const Interval g = toolBound(tool, box);
  double c;
  if (kind == OpKind::Subtract) {
    c = std::min(fHi, -g.lo);
  } else {
    const double b = bumpHi(a1, invA2Squared, fHi, sqr(g).lo * invA3Squared);
    c = kind == OpKind::BlendUnion ? fHi + rSum(fHi, g.hi) + b : fHi - rSum(fHi, g.lo) + b;
    c += 1e-13 * (std::abs(fHi) + std::max(std::abs(g.lo), std::abs(g.hi)));
  }
  return widenHi(std::max(fHi, c));
}

std::optional<BallFar> ballFarBound(const Operation& op, double within) {
  if (op.kind != OpKind::BlendUnion || op.tool.type != ToolShape::Type::Sphere) return std::nullopt;
  const double r = op.tool.r, a1 = std::max(op.a1, 0.0), invA3 = 1.0 / op.a3;
  if (!(r > 0.0) || !std::isfinite(invA3)) return std::nullopt;
  std::optional<BallFar> found;
  for (const double k : {1.5, 2.0, 3.0}) {
    const double rho0 = k * r;
    if (!(rho0 < within)) break;
    const double b0 = rho0 * rho0 - r * r;
    const double bump0 = a1 / (1.0 + b0 * b0 * invA3 * invA3);
    if (!(b0 > 2.0 * bump0 * (1.0 + 1e-6) + 1e-9)) continue;
    // The smaller root, without cancellation.
    const double root = 2.0 * b0 * bump0 / (b0 + std::sqrt(b0 * b0 - 2.0 * b0 * bump0));
    found = BallFar{rho0, root * (1.0 + 1e-6) + 1e-9};
    if (found->raise <= kFarRaiseWanted) break;
  }
  return found;
}

}  // namespace emboss

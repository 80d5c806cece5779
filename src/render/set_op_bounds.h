// Bounds of the set operations (4) over a box, without interval arithmetic's dependency problem.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "frep/operation.h"

namespace emboss {

// The tool's f_tool (ToolShape::value) over a box: conservative.
Interval toolBound(const ToolShape& tool, const P3<Interval>& p);

namespace set_op_bounds {

// The upper end of a bound widened for rounding, as every bound here is.
inline double widenHi(double v) { return v + 1e-12 + 1e-12 * std::abs(v); }

// The bump's upper end, a1 / (1 + (f/a2)^2 + (g/a3)^2), for f's upper end fHi (its lower one not
// known: it may be anything below) and (g/a3)^2 at least g2lo3.
inline double bumpHi(double a1, double invA2Squared, double fHi, double g2lo3) {
  if (!(a1 > 0.0)) return 0.0;  // a1 / d <= 0 for every d >= 1; its supremum is 0
  const double f2lo = fHi < 0.0 ? fHi * fHi : 0.0;
  return a1 / (1.0 + f2lo * invA2Squared + g2lo3);
}

}  // namespace set_op_bounds

// Upper bounds of PreparedOp::combine(f, p) for the set kinds: what proves f < 0 over a box needs
// only f's upper end. Interval arithmetic on the blends' formulas is useless away from the tool:
// f + g + sqrt(f^2 + g^2) with g an interval of width 10 gives a range of width 20 where the true
// values differ from f by a hundredth. Rewritten: blend_union = f + s + bump, blend_subtract =
// f - s + bump and subtract = min(f, -g), with s = g + sqrt(f^2 + g^2) and bump = a1 / (1 +
// (f/a2)^2 + (g/a3)^2); f + s and f - s are monotone in f and in g, so their upper ends are their
// values at the corners of f's and g's ranges; the taper then blends between f and that
// (docs/rendering.md).
//
// Made from what the bounds read of the operation (its kind, tool and the bump's constants, 1 / a2^2
// and 1 / a3^2 products where they were divisions), kept beside the renderer's set operations: the
// interval tests of a ray through a pile read a dozen of them each.
struct SetOpUpper {
  OpKind kind = OpKind::BlendUnion;
  double a1 = 0.0, invA2Squared = 0.0, invA3Squared = 0.0;
  ToolShape tool;

  SetOpUpper() = default;
  explicit SetOpUpper(const Operation& op)
      : kind(op.kind), a1(op.a1), invA2Squared(1.0 / (op.a2 * op.a2)), invA3Squared(1.0 / (op.a3 * op.a3)), tool(op.tool) {}

  // An upper bound of combine(f, p) over p in `box` and every f <= fHi.
  double over(double fHi, const P3<Interval>& box) const;

  // The same wherever the tool is (a cheaper, looser bound, without the tool's shape or shift): a
  // subtraction raises f by its bump at most (plain subtraction not at all); +infinity for a union.
  double anywhere(double fHi) const {
    using set_op_bounds::widenHi;
    switch (kind) {
      case OpKind::Subtract: return widenHi(fHi);  // min(f, -g) <= f
      case OpKind::BlendSubtract: {
        // f - s + bump with s >= 0, and the bump at most as big as with g = 0.
        const double b = set_op_bounds::bumpHi(a1, invA2Squared, fHi, 0.0);
        return widenHi(std::max(fHi, fHi + b + 1e-13 * std::abs(fHi)));
      }
      default: return std::numeric_limits<double>::infinity();  // a union's tool may raise f anywhere
    }
  }

  // The most the operation raises f anywhere: combine(f, p) <= f + raise() (past rounding's last
  // bits) for every f and p; +infinity for a union.
  double raise() const {
    switch (kind) {
      case OpKind::Subtract: return 0.0;
      case OpKind::BlendSubtract: return std::max(a1, 0.0);  // -s <= 0, the bump at most a1
      default: return std::numeric_limits<double>::infinity();
    }
  }
};

// A ball's smooth union (blend_union with a sphere tool) far from its tool: f + s + bump, s = g +
// sqrt(f^2 + g^2), bump = a1 / (1 + (f/a2)^2 + (g/a3)^2), g = r^2 - |p - c|^2, tapered towards f
// (combine() is never above it: it is never below f). At rho0 > r or more from c, g <= -b0 with
// b0 = rho0^2 - r^2 > 0. With f = -a < 0: for a <= b0, f + s = -a - b + sqrt(a^2 + b^2) <= -a +
// a^2 / (2 b0); for a > b0, f + s <= -min(a, b) / 2 <= -b0 / 2; the bump is at most bump0 = a1 /
// (1 + (b0/a3)^2). So combine(f, p) < 0 wherever f < -raise, raise the smaller root of a - a^2 /
// (2 b0) = bump0 (widened), when b0 / 2 > bump0. rho0 (nearRadius) is one of 1.5, 2 and 3 tool
// radii below `within` (kFarRaiseWanted); none: nullopt.
struct BallFar {
  double nearRadius = 0.0, raise = 0.0;
};
// The raise a far window is cut for: the first rho0 whose raise is at most this (else the last that
// has one). Near the sheet a walk creeps through the raise's height; the near stretch is searched
// by intervals.
inline constexpr double kFarRaiseWanted = 0.05;
std::optional<BallFar> ballFarBound(const Operation& op, double within);

}  // namespace emboss

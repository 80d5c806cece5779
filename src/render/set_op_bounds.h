// Bounds of the set operations (4) over a box, without interval arithmetic's dependency problem.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/operation.h"

namespace emboss {

// The tool's f_tool (ToolShape::value) over a box: conservative.
Interval toolBound(const ToolShape& tool, const P3<Interval>& p);

// Upper bounds of PreparedOp::combine(f, p) for the set kinds: what proves f < 0 over a box needs
// only f's upper end. Interval arithmetic on the blends' formulas is useless away from the tool:
// f + g + sqrt(f^2 + g^2) with g an interval of width 10 gives a range of width 20 where the true
// values differ from f by a hundredth. Rewritten: blend_union = f + s + bump, blend_subtract =
// f - s + bump and subtract = min(f, -g), with s = g + sqrt(f^2 + g^2) and bump = a1 / (1 +
// (f/a2)^2 + (g/a3)^2); f + s and f - s are monotone in f and in g, so their upper ends are their
// values at the corners of f's and g's ranges; the taper then blends between f and that
// (docs/rendering.md).
//
// An upper bound of combine(f, p) over p in `box` and every f <= fHi.
double combineUpper(const PreparedOp& op, double fHi, const P3<Interval>& box);
// The same wherever the tool is (a cheaper, looser bound, without the tool's shape or shift): a
// subtraction raises f by its bump at most (plain subtraction not at all); +infinity for a union.
double combineUpperAnywhere(const PreparedOp& op, double fHi);

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

// combineUpperAnywhere() from what it reads of the operation, kept beside the renderer's set
// operations (read for a dozen of them in every interval test of a ray through a pile): the kind and
// the bump's constants, 1 / a2^2 a product where it was a division.
struct AnywhereUpper {
  OpKind kind = OpKind::BlendUnion;
  double a1 = 0.0, invA2Squared = 0.0;

  AnywhereUpper() = default;
  explicit AnywhereUpper(const Operation& op) : kind(op.kind), a1(op.a1), invA2Squared(1.0 / (op.a2 * op.a2)) {}

  double operator()(double fHi) const {
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
};

}  // namespace emboss

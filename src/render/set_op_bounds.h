// Bounds of the set operations (4) over a box, without interval arithmetic's dependency problem.
#pragma once

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

}  // namespace emboss

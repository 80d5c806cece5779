// Bounds of the set operations (4) over a box, without interval arithmetic's dependency problem.
#pragma once

#include "frep/operation.h"

namespace emboss {

// The tool's f_tool (ToolShape::value) over a box: conservative.
Interval toolBound(const ToolShape& tool, const P3<Interval>& p);

// A conservative range of PreparedOp::combine(f, p) over f in `f` and p in `box`, for the set
// kinds. Interval arithmetic on the blends' formulas is useless away from the tool: f + g +
// sqrt(f^2 + g^2) with g an interval of width 10 gives a range of width 20 where the true values
// differ from f by a hundredth. Rewritten: blend_union = f + s + bump, blend_subtract = f - s +
// bump and subtract = min(f, -g), with s = g + sqrt(f^2 + g^2) and bump = a1 / (1 + (f/a2)^2 +
// (g/a3)^2); f + s and f - s are monotone in f and in g, so their ranges are their values at the
// corners of f's and g's ranges; the taper then blends between f and that, so the result lies
// between the two ranges' ends (docs/rendering.md).
Interval combineBound(const PreparedOp& op, const Interval& f, const P3<Interval>& box);

}  // namespace emboss

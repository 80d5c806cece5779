// Generator of large synthetic vm-format models (medallion outlines) for stress tests and benchmarks.
#pragma once

#include <string>

namespace emboss {

// A valid vm text of roughly `clauses` clauses (at least one primitive's worth): a 2D outline
// (var-x, var-y only; negative inside) made of a central disc smoothly blended with many circles
// and rotated rounded boxes, a few small holes cut out, all within about +-1 unit of the origin.
// Rotated frames and |x| (mirror symmetry) are shared by several primitives, so the model has
// shared sub-expressions as real ones do. Deterministic for a given (clauses, seed) on every
// platform.
std::string generateVmRelief(int clauses, unsigned seed);

}  // namespace emboss

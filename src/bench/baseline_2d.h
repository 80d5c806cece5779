// The benchmark's yardstick: a plain interval-pruning 2D renderer of a vm model, timed in the same
// run as the embossing renderer so that their ratio, not a number of milliseconds, says how fast
// the embossing renderer is on whatever machine runs the bench (docs/performance.md).
//
// "Plain" as the renderers of libfive and Fidget are without their tape simplification: the image
// is cut into 64x64 tiles; a tile whose interval over the model is all inside or all outside is
// filled, an ambiguous one is split into four, down to 8x8 cells whose pixels are evaluated one by
// one. The whole program is evaluated every time. The pool's threads take the 64x64 tiles.
#pragma once

#include <cstdint>
#include <vector>

#include "frep/vm_model.h"
#include "render/thread_pool.h"

namespace emboss {

struct Baseline2dResult {
  double ms = 0;            // wall time
  long intervalEvals = 0;   // interval evaluations of the program
  long pointEvals = 0;      // point evaluations
  long insidePixels = 0;    // pixels inside (vm value < 0)
  std::vector<std::uint8_t> mask;  // size x size, 255 inside, row 0 at +y
};

// Renders the model's z = 0 slice over [-halfWidth, halfWidth]^2 at size x size pixels.
Baseline2dResult renderBaseline2d(const VmProgram& program, int size, double halfWidth, ThreadPool& pool);

}  // namespace emboss

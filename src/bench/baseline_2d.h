// The benchmark's yardstick: a plain interval-pruning 2D renderer of a vm model, timed in the same
// run as the embossing renderer so that their ratio, not a number of milliseconds, says how fast
// the embossing renderer is on whatever machine runs the bench (docs/performance.md).
//
// The classic scheme of libfive and Fidget, plain (no JIT, no SIMD, scalar doubles): the image is
// cut into 64x64 tiles; a tile whose interval over the model is all inside or all outside is
// filled; in an ambiguous one every min and max that one operand decides over the whole tile is
// replaced by that operand and what no longer reaches the result is dropped (the tape pruned), and
// the tile is split into four with the shorter tape, down to 8x8 cells whose pixels are evaluated
// one by one with their cell's tape. The pool's threads take the 64x64 tiles.
#pragma once

#include <cstdint>
#include <vector>

#include "frep/vm_model.h"
#include "render/thread_pool.h"

namespace emboss {

struct Baseline2dResult {
  double ms = 0;            // wall time
  long intervalEvals = 0;   // interval evaluations of the program
  long pointEvals = 0;      // point evaluations (with pruned tapes)
  long insidePixels = 0;    // pixels inside (vm value < 0)
  double meanLeafTape = 0;  // nodes of the tape the 8x8 cells evaluate their pixels with, on average
  std::size_t fullTape = 0; // nodes of the whole program
  std::vector<std::uint8_t> mask;  // size x size, 255 inside, row 0 at +y
};

// Renders the model's z = 0 slice over [-halfWidth, halfWidth]^2 at size x size pixels.
Baseline2dResult renderBaseline2d(const VmProgram& program, int size, double halfWidth, ThreadPool& pool);

}  // namespace emboss

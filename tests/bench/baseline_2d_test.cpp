// Tests for the bench's yardstick: the interval-pruning 2D renderer gives, pixel for pixel, what
// evaluating the model at every pixel gives, and it prunes (far fewer point evaluations than pixels).
#include <gtest/gtest.h>

#include "bench/baseline_2d.h"
#include "frep/vm_generate.h"

namespace emboss {
namespace {

TEST(Baseline2d, EveryPixelIsWhatThePointEvaluationSays) {
  auto program = VmProgram::parse(generateVmRelief(600, 5), "test");
  ASSERT_TRUE(program) << program.error();
  ThreadPool pool(2);
  const int size = 160;  // not a multiple of the 64-pixel tiles: the edge tiles are clipped
  const double half = 1.1;
  const Baseline2dResult r = renderBaseline2d(*program, size, half, pool);
  ASSERT_EQ(r.mask.size(), static_cast<size_t>(size) * size);
  const double px = 2.0 * half / size;
  long differ = 0, inside = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const bool in = program->eval(-half + (x + 0.5) * px, half - (y + 0.5) * px, 0.0) < 0.0;
      inside += in;
      differ += in != (r.mask[static_cast<size_t>(y) * size + x] != 0);
    }
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(r.insidePixels, inside);
  EXPECT_GT(inside, size * size / 20) << "the generated medallion should fill part of the view";
  EXPECT_LT(inside, size * size) << "and not all of it";
  EXPECT_LT(r.pointEvals, static_cast<long>(size) * size) << "intervals should settle whole cells";
  EXPECT_GT(r.intervalEvals, 0);
  EXPECT_GT(r.meanLeafTape, 0.0);
  EXPECT_LT(r.meanLeafTape, 0.5 * static_cast<double>(r.fullTape)) << "intervals should prune the tape near the edge";
}

}  // namespace
}  // namespace emboss

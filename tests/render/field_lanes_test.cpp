// The height field's reads at many points at once in SIMD lanes (the cavity depth; D and its
// slopes) give each point's one-point read, bit for bit, on every SIMD target this machine has
// and the build compiled.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "bench/piece_generator.h"
#include "hwy/targets.h"
#include "render/renderer.h"

namespace emboss {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(FieldLanes, CavityDepthsAreTheOnePointReadsOnEveryTarget) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;
  auto model = generatePiece(600, 11, opt).makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  ThreadPool pool(2);
  Renderer renderer(pool);
  renderer.sync(*model);
  const HeightField& f = renderer.field();
  const Box2 dom = f.domain();
  // Points inside the domain, on its edges, and beyond them (clamped to the edge samples), and
  // exactly on samples.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(dom.x0 - 3.0, dom.x1 + 3.0), uy(dom.y0 - 3.0, dom.y1 + 3.0);
  std::uniform_int_distribution<int> si(0, f.nx() - 1), sj(0, f.ny() - 1);
  std::vector<double> x, y;
  for (int k = 0; k < 20000; ++k) {
    if (k % 7 == 0) {
      x.push_back(f.sampleX(si(rng))), y.push_back(f.sampleY(sj(rng)));
    } else {
      x.push_back(ux(rng)), y.push_back(uy(rng));
    }
  }
  int targets = 0;
  long deep = 0;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    ++targets;
    // Runs of every length from 1 to 37 points (whole vectors and a remainder).
    size_t k = 0;
    for (int len = 1; k + static_cast<size_t>(len) <= x.size(); len = len % 37 + 1) {
      double out[37];
      f.cavityDepths(&x[k], &y[k], len, out);
      for (int q = 0; q < len; ++q) {
        const double want = f.cavityDepth(x[k + static_cast<size_t>(q)], y[k + static_cast<size_t>(q)]);
        ASSERT_TRUE(sameBits(out[q], want)) << hwy::TargetName(target) << ": point " << k + static_cast<size_t>(q)
                                            << " lanes " << out[q] << ", one at a time " << want;
        deep += want > 0.05;
      }
      k += static_cast<size_t>(len);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(targets, 1);
  EXPECT_GT(deep, 100);  // the piece has cavities: the reads are not all zero
}

TEST(FieldLanes, ValuesAndGradientsAreTheOnePointReadsOnEveryTarget) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;
  auto model = generatePiece(600, 13, opt).makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  ThreadPool pool(2);
  Renderer renderer(pool);
  renderer.sync(*model);
  const HeightField& f = renderer.field();
  const Box2 dom = f.domain();
  // Points inside the domain and on its edges (where the renderer reads the field), and exactly
  // on samples.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(dom.x0, dom.x1), uy(dom.y0, dom.y1);
  std::uniform_int_distribution<int> si(0, f.nx() - 1), sj(0, f.ny() - 1);
  std::vector<double> x, y;
  for (int k = 0; k < 20000; ++k) {
    if (k % 7 == 0)
      x.push_back(f.sampleX(si(rng))), y.push_back(f.sampleY(sj(rng)));
    else if (k % 11 == 0)
      x.push_back(k % 2 ? dom.x0 : dom.x1), y.push_back(uy(rng));
    else
      x.push_back(ux(rng)), y.push_back(uy(rng));
  }
  int targets = 0;
  long sloped = 0;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    ++targets;
    size_t k = 0;
    for (int len = 1; k + static_cast<size_t>(len) <= x.size(); len = len % 37 + 1) {
      double v[37], gx[37], gy[37];
      f.valuesAndGradients(&x[k], &y[k], len, v, gx, gy);
      for (int q = 0; q < len; ++q) {
        double wv, wgx, wgy;
        f.valueAndGradient(x[k + static_cast<size_t>(q)], y[k + static_cast<size_t>(q)], wv, wgx, wgy);
        ASSERT_TRUE(sameBits(v[q], wv) && sameBits(gx[q], wgx) && sameBits(gy[q], wgy))
            << hwy::TargetName(target) << ": point " << k + static_cast<size_t>(q) << " lanes " << v[q] << " " << gx[q]
            << " " << gy[q] << ", one at a time " << wv << " " << wgx << " " << wgy;
        sloped += std::abs(wgx) + std::abs(wgy) > 0.1;
      }
      k += static_cast<size_t>(len);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(targets, 1);
  EXPECT_GT(sloped, 1000);  // the piece has relief: the slopes are not all zero
}

}  // namespace
}  // namespace emboss

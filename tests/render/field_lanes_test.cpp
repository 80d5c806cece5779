// The height field's reads at many points at once in SIMD lanes (the cavity depth; D and its
// slopes) give each point's one-point read, bit for bit, on every SIMD target this machine has
// and the build compiled; so do the cavity filter's rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "bench/piece_generator.h"
#include "hwy/targets.h"
#include "render/field_lanes.h"
#include "render/renderer.h"

namespace emboss {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A dense piece's renderer (2 threads), its field built, and points to read the field at: inside
// its domain, on its edges, `beyond` it by up to 3 mm (clamped to the edge samples), and exactly
// on samples.
struct SyncedField {
  SyncedField(unsigned seed, double beyond) : renderer(pool) {
    PieceOptions opt;
    opt.width = 100, opt.height = 70;
    auto model = generatePiece(600, seed, opt).makeModel();
    if (!model.ok()) throw std::runtime_error(model.error());
    renderer.sync(*model);
    const HeightField& f = field();
    const Box2 dom = f.domain();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(dom.x0 - beyond, dom.x1 + beyond), uy(dom.y0 - beyond, dom.y1 + beyond);
    std::uniform_int_distribution<int> si(0, f.nx() - 1), sj(0, f.ny() - 1);
    for (int k = 0; k < 20000; ++k) {
      if (k % 7 == 0)
        x.push_back(f.sampleX(si(rng))), y.push_back(f.sampleY(sj(rng)));
      else if (k % 11 == 0)
        x.push_back(k % 2 ? dom.x0 : dom.x1), y.push_back(uy(rng));
      else
        x.push_back(ux(rng)), y.push_back(uy(rng));
    }
  }
  const HeightField& field() const { return renderer.field(); }
  // For every SIMD target: `read(target, k, len)` over runs of every length from 1 to 37 points
  // (whole vectors of lanes and a remainder) from point k. Returns the targets tried.
  template <class Read>
  int onEveryTarget(const Read& read) const {
    int targets = 0;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      ++targets;
      size_t k = 0;
      for (int len = 1; k + static_cast<size_t>(len) <= x.size(); len = len % 37 + 1) {
        if (!read(hwy::TargetName(target), k, len)) break;
        k += static_cast<size_t>(len);
      }
    }
    hwy::SetSupportedTargetsForTest(0);
    return targets;
  }
  ThreadPool pool{2};
  Renderer renderer;
  std::vector<double> x, y;
};

TEST(FieldLanes, CavityDepthsAreTheOnePointReadsOnEveryTarget) {
  const SyncedField p(11, 3.0);
  long deep = 0;
  const int targets = p.onEveryTarget([&](const char* target, size_t k, int len) {
    double out[37];
    p.field().cavityDepths(&p.x[k], &p.y[k], len, out);
    for (int q = 0; q < len; ++q) {
      const size_t at = k + static_cast<size_t>(q);
      const double want = p.field().cavityDepth(p.x[at], p.y[at]);
      EXPECT_TRUE(sameBits(out[q], want)) << target << ": point " << at << " lanes " << out[q] << ", one at a time " << want;
      if (!sameBits(out[q], want)) return false;
      deep += want > 0.05;
    }
    return true;
  });
  EXPECT_GE(targets, 1);
  EXPECT_GT(deep, 100);  // the piece has cavities: the reads are not all zero
}

TEST(FieldLanes, ValuesAndGradientsAreTheOnePointReadsOnEveryTarget) {
  const SyncedField p(13, 0.0);  // (the renderer reads D inside the domain only)
  long sloped = 0;
  const int targets = p.onEveryTarget([&](const char* target, size_t k, int len) {
    double v[37], gx[37], gy[37];
    p.field().valuesAndGradients(&p.x[k], &p.y[k], len, v, gx, gy);
    for (int q = 0; q < len; ++q) {
      const size_t at = k + static_cast<size_t>(q);
      double wv, wgx, wgy;
      p.field().valueAndGradient(p.x[at], p.y[at], wv, wgx, wgy);
      const bool same = sameBits(v[q], wv) && sameBits(gx[q], wgx) && sameBits(gy[q], wgy);
      EXPECT_TRUE(same) << target << ": point " << at << " lanes " << v[q] << " " << gx[q] << " " << gy[q]
                        << ", one at a time " << wv << " " << wgx << " " << wgy;
      if (!same) return false;
      sloped += std::abs(wgx) + std::abs(wgy) > 0.1;
    }
    return true;
  });
  EXPECT_GE(targets, 1);
  EXPECT_GT(sloped, 1000);  // the piece has relief: the slopes are not all zero
}

// The cavity filter's rows in lanes (HeightField::updateCavity) are the scalar loop's sums, bit
// for bit, on every target: random D and weights (the field's own 24 taps are positive and small;
// these include negatives and zeros), every length from 0 to 40, rows starting anywhere.
TEST(FieldLanes, TapSumsAreTheScalarSumsOnEveryTarget) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ud(-3.0f, 3.0f), uw(-0.1f, 0.3f);
  constexpr int kTaps = 24, kWidth = 64;
  std::vector<float> plane(kTaps * kWidth + kWidth), w(kTaps);
  for (float& v : plane) v = ud(rng);
  for (float& v : w) v = uw(rng);
  w[3] = 0.0f, plane[5] = -0.0f;
  int targets = 0;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    if (target == HWY_SCALAR || target == HWY_EMU128) continue;
    hwy::SetSupportedTargetsForTest(target);
    ++targets;
    for (int len = 0; len <= 40; ++len)
      for (int shift = 0; shift < 9; ++shift) {
        std::vector<const float*> rows(kTaps);
        for (int t = 0; t < kTaps; ++t) rows[static_cast<size_t>(t)] = &plane[static_cast<size_t>(t * kWidth + (shift + 3 * t) % 17)];
        const float* own = &plane[static_cast<size_t>(kTaps * kWidth + shift)];
        std::vector<float> out(static_cast<size_t>(len) + 1, 7.0f);
        tapSumsLanes(rows.data(), w.data(), kTaps, own, len, out.data());
        for (int k = 0; k < len; ++k) {
          float acc = 0.0f;
          for (int t = 0; t < kTaps; ++t) acc += w[static_cast<size_t>(t)] * rows[static_cast<size_t>(t)][k];
          const float want = acc - own[k];
          ASSERT_EQ(0, std::memcmp(&want, &out[static_cast<size_t>(k)], sizeof(float)))
              << hwy::TargetName(target) << ": length " << len << ", sample " << k << ": " << out[static_cast<size_t>(k)] << " vs " << want;
        }
        ASSERT_EQ(7.0f, out[static_cast<size_t>(len)]) << hwy::TargetName(target) << ": wrote past length " << len;
      }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(targets, 1);
}

}  // namespace
}  // namespace emboss

// leafNetBounds: a pyramid leaf's bounds a row of patches at a time in SIMD lanes are the ones the
// patches' Bezier nets give worked out one patch at a time, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "render/leaf_bounds.h"

namespace emboss {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Patch by patch, as the nets are defined: each corner's value, plus or minus a third of its
// scaled slopes, and a ninth of its scaled twist.
LeafNetBounds reference(const LeafSamples& s, int nu, int nv) {
  const double inf = std::numeric_limits<double>::infinity();
  LeafNetBounds r{inf, -inf, inf, -inf, inf, -inf};
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      double b[4][4];
      for (int cu = 0; cu < 2; ++cu)
        for (int cv = 0; cv < 2; ++cv) {
          const int a = i + cu, c = j + cv;
          const double d = s.d[c][a];
          const double x = cu ? -s.x[c][a] : s.x[c][a], y = cv ? -s.y[c][a] : s.y[c][a];
          const double t = cu != cv ? -s.t[c][a] : s.t[c][a];
          const int u = cu * 3, v = cv * 3, un = cu ? 2 : 1, vn = cv ? 2 : 1;
          b[u][v] = d;
          b[un][v] = d + x;
          b[u][vn] = d + y;
          b[un][vn] = d + x + y + t;
        }
      for (int u = 0; u < 4; ++u)
        for (int v = 0; v < 4; ++v) {
          r.lo = std::min(r.lo, b[u][v]), r.hi = std::max(r.hi, b[u][v]);
          if (u < 3) {
            const double du = 3.0 * (b[u + 1][v] - b[u][v]);
            r.uLo = std::min(r.uLo, du), r.uHi = std::max(r.uHi, du);
          }
          if (v < 3) {
            const double dv = 3.0 * (b[u][v + 1] - b[u][v]);
            r.vLo = std::min(r.vLo, dv), r.vHi = std::max(r.vHi, dv);
          }
        }
    }
  return r;
}

TEST(LeafBounds, EqualThePatchByPatchNetsBitForBit) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int round = 0; round < 40; ++round)
    for (int nu = 1; nu <= 8; ++nu)
      for (int nv = 1; nv <= 8; ++nv) {
        LeafSamples s;
        // Unused entries hold values that would show if they were read.
        for (auto* a : {&s.d, &s.x, &s.y, &s.t})
          for (auto& row : *a) std::fill(std::begin(row), std::end(row), round % 2 ? 1e300 : -1e300);
        // Values of a relief in mm, scaled thirds of slopes, ninths of twists; some rounds flat
        // stretches and equal values (ties between lanes), one with an extreme far from the rest.
        for (int c = 0; c <= nv; ++c)
          for (int a = 0; a <= nu; ++a) {
            const bool flat = round % 5 == 0 && a < 4;
            s.d[c][a] = flat ? 0.25 : 2.0 * u(rng);
            s.x[c][a] = flat ? 0.0 : 0.05 * u(rng);
            s.y[c][a] = flat ? -0.0 : 0.05 * u(rng);
            s.t[c][a] = flat ? 0.0 : 0.01 * u(rng);
          }
        if (round % 7 == 3) s.d[nv / 2][nu / 2] = 40.0;
        const LeafNetBounds got = leafNetBounds(s, nu, nv), want = reference(s, nu, nv);
        EXPECT_TRUE(sameBits(got.lo, want.lo) || (got.lo == 0 && want.lo == 0)) << nu << "x" << nv << " " << got.lo << " " << want.lo;
        EXPECT_TRUE(sameBits(got.hi, want.hi) || (got.hi == 0 && want.hi == 0)) << nu << "x" << nv;
        EXPECT_EQ(got.uLo, want.uLo) << nu << "x" << nv;
        EXPECT_EQ(got.uHi, want.uHi) << nu << "x" << nv;
        EXPECT_EQ(got.vLo, want.vLo) << nu << "x" << nv;
        EXPECT_EQ(got.vHi, want.vHi) << nu << "x" << nv;
        ++checked;
      }
  EXPECT_EQ(checked, 40 * 64);
}

TEST(LeafBounds, SamplesAreTakenInAsOneAtATime) {
  // Rows of (d, dx, dy, dxy) floats, 37 samples a row; every leaf size at every offset along it.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  constexpr int kRow = 37, kRows = 12;
  std::vector<float> samples(4 * kRow * kRows);
  for (float& f : samples) f = u(rng);
  const double s = 0.125;
  int checked = 0;
  for (int nu = 1; nu <= 9; ++nu)
    for (int nv = 1; nv <= 9; ++nv)
      for (int i0 : {0, 1, 5, kRow - nu})
        for (int j0 : {0, 2, kRows - nv}) {
          LeafSamples got;
          loadLeafSamples(&samples[4 * (static_cast<size_t>(j0) * kRow + i0)], 4L * kRow, nu, nv, s, got);
          for (int c = 0; c < nv; ++c)
            for (int a = 0; a < nu; ++a) {
              const float* k = &samples[4 * (static_cast<size_t>(j0 + c) * kRow + i0 + a)];
              ASSERT_TRUE(sameBits(got.d[c][a], k[0])) << nu << "x" << nv << " at " << a << "," << c;
              ASSERT_TRUE(sameBits(got.x[c][a], s * k[1] / 3.0)) << nu << "x" << nv << " at " << a << "," << c;
              ASSERT_TRUE(sameBits(got.y[c][a], s * k[2] / 3.0)) << nu << "x" << nv << " at " << a << "," << c;
              ASSERT_TRUE(sameBits(got.t[c][a], s * s * k[3] / 9.0)) << nu << "x" << nv << " at " << a << "," << c;
            }
          ++checked;
        }
  EXPECT_EQ(checked, 81 * 12);
}

TEST(LeafBounds, ARowsTwistsAreItsSamplesOneAtATime) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  constexpr int kRow = 40;
  std::vector<float> rows(3 * 4 * kRow);
  for (float& f : rows) f = u(rng);
  const float* below = rows.data();
  const float* row = below + 4 * kRow;
  const float* above = row + 4 * kRow;
  const double den = 2 * 0.125;
  for (int first = 1; first < 4; ++first)
    for (int n = 1; first + n < kRow; ++n) {
      std::vector<float> got(static_cast<size_t>(n));
      twistRow(below + 4 * first, row + 4 * first, above + 4 * first, n, den, got.data());
      for (int k = 0; k < n; ++k) {
        const int i = first + k;
        const double dxy = (static_cast<double>(above[4 * i + 1]) - below[4 * i + 1]) / den;
        const double dyx = (static_cast<double>(row[4 * (i + 1) + 2]) - row[4 * (i - 1) + 2]) / den;
        const float want = static_cast<float>(0.5 * (dxy + dyx));
        ASSERT_EQ(std::memcmp(&got[static_cast<size_t>(k)], &want, sizeof want), 0) << "n " << n << " k " << k;
      }
    }
}

}  // namespace
}  // namespace emboss

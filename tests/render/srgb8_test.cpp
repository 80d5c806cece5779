// The sRGB step table returns exactly what toSrgb8() returns.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <hwy/targets.h>

#include "render/shading.h"
#include "render/srgb8.h"

namespace emboss {
namespace {

TEST(Srgb8, MatchesToSrgb8EverywhereItMatters) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 300000; ++i) {
    // Linear values as shading makes them: mostly 0..2, some far beyond, some negative.
    const double scale = i % 10 == 0 ? 1000.0 : 2.0;
    const glm::dvec3 c(unit(rng) * scale, unit(rng) * scale - 0.1, unit(rng) * 0.05);
    ASSERT_EQ(toSrgb8Fast(c), toSrgb8(c)) << c.x << " " << c.y << " " << c.z;
  }
}

TEST(Srgb8, MatchesAroundEveryStep) {
  // Scan the doubles around each change of the byte, where a table could be off by one.
  for (int k = 0; k < 255; ++k) {
    double lo = 0.0, hi = 1e6;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (toSrgb8(glm::dvec3(mid, 0, 0))[0] > k)
        hi = mid;
      else
        lo = mid;
    }
    std::uint64_t bits = std::bit_cast<std::uint64_t>(hi) - 20000;
    for (int j = 0; j < 40000; ++j, ++bits) {
      const double x = std::bit_cast<double>(bits);
      ASSERT_EQ(toSrgb8Fast(glm::dvec3(x, x, x)), toSrgb8(glm::dvec3(x, x, x))) << x;
    }
  }
}

TEST(Srgb8, MatchesAtEveryBucketsEdges) {
  // The lookup starts from buckets of 1/128 of an octave: their edges, and values beyond the
  // octaves they cover (tiny and bright), on both sides.
  for (int e = -24; e <= 4; ++e)
    for (int m = 0; m < 128; ++m) {
      const std::uint64_t edge = std::bit_cast<std::uint64_t>(std::ldexp(1.0 + m / 128.0, e));
      for (std::uint64_t bits = edge - 3; bits <= edge + 3; ++bits) {
        const double x = std::bit_cast<double>(bits);
        ASSERT_EQ(toSrgb8Fast(glm::dvec3(x, x, x)), toSrgb8(glm::dvec3(x, x, x))) << x;
      }
    }
}

TEST(Srgb8, OddValuesFallBack) {
  for (double x : {-0.0, -1.0, 1e7, 1e300, std::numeric_limits<double>::infinity(), std::nan("")}) {
    const glm::dvec3 c(x, 0.5, 0.25);
    EXPECT_EQ(toSrgb8Fast(c), toSrgb8(c)) << x;
  }
}

// Values where a lookup could go wrong: random ones as shading makes them, the doubles around every
// step, the buckets' edges, and odd ones (negative, huge, infinite, NaN).
std::vector<double> hardValues() {
  std::vector<double> v;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 100000; ++i) v.push_back(unit(rng) * (i % 10 == 0 ? 1000.0 : 2.0) - (i % 7 == 0 ? 0.1 : 0.0));
  for (int k = 0; k < 255; ++k) {
    double lo = 0.0, hi = 1e6;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (toSrgb8(glm::dvec3(mid, 0, 0))[0] > k ? hi : lo) = mid;
    }
    // Inside and just outside the ulps where toSrgb8() decides, on both sides.
    const std::uint64_t b = std::bit_cast<std::uint64_t>(hi);
    for (std::uint64_t j = 0; j < 12000; j += 7) v.push_back(std::bit_cast<double>(b - 6000 + j));
  }
  for (int e = -24; e <= 4; ++e)
    for (int m = 0; m < 128; ++m) {
      const std::uint64_t edge = std::bit_cast<std::uint64_t>(std::ldexp(1.0 + m / 128.0, e));
      for (std::uint64_t bits = edge - 2; bits <= edge + 2; ++bits) v.push_back(std::bit_cast<double>(bits));
    }
  for (double x : {0.0, -0.0, -1.0, 1e6, 1e7, 1e300, std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(), std::nan(""), std::numeric_limits<double>::denorm_min()})
    v.push_back(x);
  return v;
}

void expectChannelsAsToSrgb8(const std::vector<double>& v) {
  std::vector<std::uint8_t> out(v.size() + 1, 0xAB);
  // Every length up to two vectors and more (the last values go alone), then all at once.
  for (int n = 1; n <= 20; ++n) {
    toSrgb8Channels(v.data() + 100, n, out.data());
    for (int i = 0; i < n; ++i) ASSERT_EQ(out[static_cast<size_t>(i)], toSrgb8(glm::dvec3(v[100 + i], 0, 0))[0]) << n << " " << i;
    ASSERT_EQ(out[static_cast<size_t>(n)], 0xAB) << "wrote past " << n;
  }
  toSrgb8Channels(v.data(), static_cast<int>(v.size()), out.data());
  for (size_t i = 0; i < v.size(); ++i) {
    ASSERT_EQ(out[i], toSrgb8(glm::dvec3(v[i], 0, 0))[0]) << v[i];
    ASSERT_EQ(out[i], toSrgb8Channel(v[i])) << v[i];
  }
}

TEST(Srgb8, ChannelsInLanesMatchToSrgb8) { expectChannelsAsToSrgb8(hardValues()); }

TEST(Srgb8, ChannelsInLanesMatchOnEveryInstructionSetOfThisMachine) {
  const std::vector<double> v = hardValues();
  int sets = 0;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    if (target == HWY_SCALAR || target == HWY_EMU128) continue;  // (Highway's fallbacks, not SIMD)
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    expectChannelsAsToSrgb8(v);
    ++sets;
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(sets, 1);
}

}  // namespace
}  // namespace emboss

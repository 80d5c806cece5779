// The sRGB step table returns exactly what toSrgb8() returns.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

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

}  // namespace
}  // namespace emboss

// portableSin/portableCos: close to libm's (they replace it only for bit-for-bit reproducibility).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "util/portable_math.h"

namespace emboss {
namespace {

TEST(PortableMath, SinAndCosAgreeWithLibmToAFewUlps) {
  double worst = 0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 0.0173;  // about +-3460 rad, every quadrant many times
    const double es = std::abs(portableSin(x) - std::sin(x)), ec = std::abs(portableCos(x) - std::cos(x));
    worst = std::max({worst, es, ec});
    ASSERT_LE(es, 4e-16 + 4e-16 * std::abs(std::sin(x))) << x;
    ASSERT_LE(ec, 4e-16 + 4e-16 * std::abs(std::cos(x))) << x;
  }
  // Exact where it must be.
  EXPECT_EQ(portableSin(0.0), 0.0);
  EXPECT_EQ(portableCos(0.0), 1.0);
  EXPECT_NEAR(portableSin(M_PI / 2), 1.0, 1e-16);
  EXPECT_NEAR(portableCos(M_PI), -1.0, 1e-16);
  EXPECT_EQ(portableHypot(3.0, 4.0), 5.0);
}

// The integer floors and ceilings give std::floor's and std::ceil's values: at and beside the
// integers (one ulp either side), at fractions, at -0, and far out in both directions.
TEST(PortableMath, IntegerFloorsAndCeilingsAreLibms) {
  std::vector<double> xs{0.0, -0.0, 1e-300, -1e-300, 0.5, -0.5, 2.0e9, -2.0e9, 4.0e15, -4.0e15};
  for (int i = -3000; i <= 3000; ++i) {
    const double x = i * 0.37;
    xs.insert(xs.end(), {x, std::nextafter(x, 1e300), std::nextafter(x, -1e300), static_cast<double>(i),
                         std::nextafter(static_cast<double>(i), 1e300), std::nextafter(static_cast<double>(i), -1e300)});
  }
  for (double x : xs) {
    ASSERT_EQ(floorToLong(x), static_cast<long>(std::floor(x))) << x;
    ASSERT_EQ(ceilToLong(x), static_cast<long>(std::ceil(x))) << x;
    if (std::abs(x) < 2.0e9) ASSERT_EQ(floorToInt(x), static_cast<int>(std::floor(x))) << x;
  }
}

}  // namespace
}  // namespace emboss

// portableSin/portableCos: close to libm's (they replace it only for bit-for-bit reproducibility).
#include <cmath>

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

}  // namespace
}  // namespace emboss

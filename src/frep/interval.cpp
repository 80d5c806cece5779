// Interval versions of the transcendental functions used by imported models.
#include "frep/interval.h"

#include <numbers>

namespace emboss {

Interval sin(Interval a) {
  if (!(a.width() < 2.0 * std::numbers::pi)) return {-1.0, 1.0};
  double lo = std::min(std::sin(a.lo), std::sin(a.hi));
  double hi = std::max(std::sin(a.lo), std::sin(a.hi));
  // Extremes at pi/2 + 2k pi (max) and -pi/2 + 2k pi (min) inside the interval.
  const double twoPi = 2.0 * std::numbers::pi;
  const double kMax = std::ceil((a.lo - std::numbers::pi / 2) / twoPi);
  if (std::numbers::pi / 2 + kMax * twoPi <= a.hi) hi = 1.0;
  const double kMin = std::ceil((a.lo + std::numbers::pi / 2) / twoPi);
  if (-std::numbers::pi / 2 + kMin * twoPi <= a.hi) lo = -1.0;
  return {lo, hi};
}

Interval cos(Interval a) { return sin(a + Interval(std::numbers::pi / 2)); }

Interval atan2(Interval y, Interval x) {
  // Exact bounds need care around the branch cut; a box not touching x <= 0 is monotone enough.
  if (x.lo > 0.0) {
    const double c[4] = {std::atan2(y.lo, x.lo), std::atan2(y.lo, x.hi), std::atan2(y.hi, x.lo),
                         std::atan2(y.hi, x.hi)};
    return {*std::min_element(c, c + 4), *std::max_element(c, c + 4)};
  }
  if (y.lo > 0.0 || y.hi < 0.0) {
    const double c[4] = {std::atan2(y.lo, x.lo), std::atan2(y.lo, x.hi), std::atan2(y.hi, x.lo),
                         std::atan2(y.hi, x.hi)};
    return {*std::min_element(c, c + 4), *std::max_element(c, c + 4)};
  }
  return {-std::numbers::pi, std::numbers::pi};
}

Interval pow(Interval a, double e) {
  if (e == std::floor(e)) {
    const long n = static_cast<long>(e);
    if (n == 0) return {1.0, 1.0};
    if (n == 2) return sqr(a);
    if (n > 0 && n % 2 == 1) return {std::pow(a.lo, e), std::pow(a.hi, e)};
    if (n > 0) {
      const Interval m = abs(a);
      return {std::pow(m.lo, e), std::pow(m.hi, e)};
    }
    return Interval(1.0) / pow(a, -e);
  }
  if (a.hi < 0.0) return Interval::whole();
  const double lo = std::max(a.lo, 0.0);
  return e > 0 ? Interval{std::pow(lo, e), std::pow(a.hi, e)} : Interval{std::pow(a.hi, e), std::pow(lo, e)};
}

}  // namespace emboss

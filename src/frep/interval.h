// Interval arithmetic: conservative bounds of a function over a box, for pruning and root finding.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace emboss {

// A closed interval [lo, hi]. Every operation returns an interval that contains every value the
// exact operation takes on its arguments' intervals (rounding is not directed: the kernels add a
// small margin where it matters). An empty or NaN-producing argument yields the whole line.
struct Interval {
  double lo = 0.0;
  double hi = 0.0;

  constexpr Interval() = default;
  constexpr Interval(double v) : lo(v), hi(v) {}  // NOLINT: a constant is a degenerate interval
  constexpr Interval(double l, double h) : lo(l), hi(h) {}

  static constexpr Interval whole() {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  }
  constexpr double width() const { return hi - lo; }
  constexpr double mid() const { return 0.5 * (lo + hi); }
  constexpr bool contains(double v) const { return lo <= v && v <= hi; }
};

inline Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }
inline Interval operator-(Interval a, Interval b) { return {a.lo - b.hi, a.hi - b.lo}; }
inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
inline Interval operator*(Interval a, Interval b) {
  const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
  return {std::min(std::min(p1, p2), std::min(p3, p4)), std::max(std::max(p1, p2), std::max(p3, p4))};
}
inline Interval operator/(Interval a, Interval b) {
  if (b.lo <= 0.0 && b.hi >= 0.0) return Interval::whole();
  return a * Interval(1.0 / b.hi, 1.0 / b.lo);
}
inline Interval& operator+=(Interval& a, Interval b) { return a = a + b; }
inline Interval& operator-=(Interval& a, Interval b) { return a = a - b; }
inline Interval& operator*=(Interval& a, Interval b) { return a = a * b; }

inline Interval sqr(Interval a) {
  if (a.lo >= 0.0) return {a.lo * a.lo, a.hi * a.hi};
  if (a.hi <= 0.0) return {a.hi * a.hi, a.lo * a.lo};
  return {0.0, std::max(a.lo * a.lo, a.hi * a.hi)};
}
inline Interval abs(Interval a) {
  if (a.lo >= 0.0) return a;
  if (a.hi <= 0.0) return -a;
  return {0.0, std::max(-a.lo, a.hi)};
}
inline Interval sqrt(Interval a) {
  return {std::sqrt(std::max(a.lo, 0.0)), std::sqrt(std::max(a.hi, 0.0))};
}
inline Interval min(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
inline Interval max(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }
inline Interval exp(Interval a) { return {std::exp(a.lo), std::exp(a.hi)}; }
inline Interval log(Interval a) {
  if (a.hi <= 0.0) return Interval::whole();
  return {a.lo > 0.0 ? std::log(a.lo) : -std::numeric_limits<double>::infinity(), std::log(a.hi)};
}
Interval sin(Interval a);
Interval cos(Interval a);
Interval atan2(Interval y, Interval x);
Interval pow(Interval a, double e);

// The interval of a monotone decreasing function g on [a.lo, a.hi].
template <class F>
inline Interval decreasing(Interval a, F g) {
  return {g(a.hi), g(a.lo)};
}
template <class F>
inline Interval increasing(Interval a, F g) {
  return {g(a.lo), g(a.hi)};
}

}  // namespace emboss

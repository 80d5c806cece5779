// The paper's kernels, written once over the scalar types (double, Grad, Interval).
#pragma once

#include "frep/scalar.h"

namespace emboss::kernels {

// Where every bounded kernel stops being exact: within kExactSpan characteristic lengths L it is the
// paper's function to the last bit; over the next kTaperSpan * L it is multiplied by a quintic
// "smootherstep" that falls from 1 to 0 with zero first and second derivatives at both ends; beyond
// (kExactSpan + kTaperSpan) * L it is exactly zero. See docs/kernels.md.
inline constexpr double kExactSpan = 3.0;
inline constexpr double kTaperSpan = 1.0;
inline constexpr double kSupportSpan = kExactSpan + kTaperSpan;

// The taper weight for a distance t >= 0 (in units of L already divided out: s = t / L).
inline double taperWeight(double s) {
  if (s <= kExactSpan) return 1.0;
  if (s >= kSupportSpan) return 0.0;
  const double u = (s - kExactSpan) / kTaperSpan;
  return 1.0 - u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}
inline double taperWeightDerivative(double s) {
  if (s <= kExactSpan || s >= kSupportSpan) return 0.0;
  const double u = (s - kExactSpan) / kTaperSpan;
  return -30.0 * u * u * (1.0 - u) * (1.0 - u) / kTaperSpan;
}
inline double taper(double s) { return taperWeight(s); }
inline Grad taper(const Grad& s) { return chain(s, taperWeight(s.v), taperWeightDerivative(s.v)); }
// The weight falls monotonically with s.
inline Interval taper(const Interval& s) { return {taperWeight(s.hi), taperWeight(s.lo)}; }

// The hand-over weight at a trace joint, of u = (P - J) . dir / r: 0 for u <= -1, 1 for u >= 1, the
// quintic smootherstep of (u + 1) / 2 between (zero first and second derivatives at both ends).
// Rising monotonically; joinStep(u) + (1 - joinStep(u)) = 1 for the two pieces at a joint.
inline double joinWeight(double u) {
  if (u <= -1.0) return 0.0;
  if (u >= 1.0) return 1.0;
  const double s = 0.5 * (u + 1.0);
  return s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
}
inline double joinWeightDerivative(double u) {
  if (u <= -1.0 || u >= 1.0) return 0.0;
  const double s = 0.5 * (u + 1.0);
  return 15.0 * s * s * (1.0 - s) * (1.0 - s);  // d/ds is 30 s^2 (1 - s)^2, ds/du = 1/2
}
inline constexpr double kJoinMaxSlope = 0.9375;  // max of joinWeightDerivative (at u = 0)
inline double joinStep(double u) { return joinWeight(u); }
inline Grad joinStep(const Grad& u) { return chain(u, joinWeight(u.v), joinWeightDerivative(u.v)); }
inline Interval joinStep(const Interval& u) { return {joinWeight(u.lo), joinWeight(u.hi)}; }

// Squared distance, over t2 = |P'|^2 (or t^2 across a traced line), in the scalar type.
// Witch of Agnesi, equation (2): a^3 / (t^2 + a^2), peak a at t = 0.
template <class T>
inline T agnesi(const T& t2, double a) {
  return (a * a * a) / (t2 + a * a);
}
inline Interval agnesi(const Interval& t2, double a) {
  const double a3 = a * a * a, a2 = a * a;
  return {a3 / (std::max(t2.hi, 0.0) + a2), a3 / (std::max(t2.lo, 0.0) + a2)};
}

// Equation (3): p a^3 / (q |P'|^2 + a^2), peak p a.
template <class T>
inline T punch(const T& r2, double a, double p, double q) {
  return (p * a * a * a) / (q * r2 + a * a);
}
inline Interval punch(const Interval& r2, double a, double p, double q) {
  const double n = p * a * a * a, a2 = a * a;
  const double lo = n / (q * std::max(r2.hi, 0.0) + a2), hi = n / (q * std::max(r2.lo, 0.0) + a2);
  return p >= 0 ? Interval{lo, hi} : Interval{hi, lo};
}

// The square root of a squared distance, safe at zero for gradients and intervals.
template <class T>
inline T distanceFromSquared(const T& d2) {
  return sqrt(d2);
}

// Squared distance from (x, y) to the segment A-B (A, B constants), in the scalar type.
template <class T>
inline T segmentDistance2(const T& x, const T& y, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double len2 = ex * ex + ey * ey;
  const T px = x - ax, py = y - ay;
  if (len2 <= 0.0) return sqr(px) + sqr(py);
  T t = (px * ex + py * ey) * (1.0 / len2);
  t = min(max(t, T(0.0)), T(1.0));
  return sqr(px - t * ex) + sqr(py - t * ey);
}

// Union with blending, equation (4) (Pasko and Savchenko 1994), given 1 / a2 and 1 / a3 (a
// prepared operation keeps them: two divisions less at every point, the same bits).
template <class T>
inline T blendUnionByInverses(const T& f, const T& g, double a1, double invA2, double invA3) {
  return f + g + sqrt(sqr(f) + sqr(g)) + a1 / (1.0 + sqr(f * invA2) + sqr(g * invA3));
}
template <class T>
inline T blendUnion(const T& f, const T& g, double a1, double a2, double a3) {
  return blendUnionByInverses(f, g, a1, 1.0 / a2, 1.0 / a3);
}
// Subtraction with blending.
template <class T>
inline T blendSubtractByInverses(const T& f, const T& g, double a1, double invA2, double invA3) {
  return f - g - sqrt(sqr(f) + sqr(g)) + a1 / (1.0 + sqr(f * invA2) + sqr(g * invA3));
}
template <class T>
inline T blendSubtract(const T& f, const T& g, double a1, double a2, double a3) {
  return blendSubtractByInverses(f, g, a1, 1.0 / a2, 1.0 / a3);
}
// Plain subtraction: min(f, -g).
template <class T>
inline T subtract(const T& f, const T& g) {
  return min(f, -g);
}

}  // namespace emboss::kernels

// Forward-mode automatic differentiation: a value with its gradient in x, y, z.
#pragma once

#include <algorithm>
#include <cmath>

namespace emboss {

// Grad carries f and (df/dx, df/dy, df/dz). The kernels are written once as templates over the
// scalar type and instantiated for double (value), Grad (value and gradient) and Interval (bounds),
// so the gradient is exact and cannot drift from the value.
struct Grad {
  double v = 0.0;
  double dx = 0.0, dy = 0.0, dz = 0.0;

  constexpr Grad() = default;
  constexpr Grad(double value) : v(value) {}  // NOLINT: a constant has zero gradient
  constexpr Grad(double value, double gx, double gy, double gz) : v(value), dx(gx), dy(gy), dz(gz) {}
};

inline Grad operator+(Grad a, Grad b) { return {a.v + b.v, a.dx + b.dx, a.dy + b.dy, a.dz + b.dz}; }
inline Grad operator-(Grad a, Grad b) { return {a.v - b.v, a.dx - b.dx, a.dy - b.dy, a.dz - b.dz}; }
inline Grad operator-(Grad a) { return {-a.v, -a.dx, -a.dy, -a.dz}; }
inline Grad operator*(Grad a, Grad b) {
  return {a.v * b.v, a.dx * b.v + a.v * b.dx, a.dy * b.v + a.v * b.dy, a.dz * b.v + a.v * b.dz};
}
// The chain rule for a scalar function with value fv and derivative d at a.v.
inline Grad chain(Grad a, double fv, double d) { return {fv, d * a.dx, d * a.dy, d * a.dz}; }
inline Grad operator/(Grad a, Grad b) {
  // The value is a plain quotient so that it equals the double evaluation to the last bit.
  const double inv = 1.0 / b.v;
  const double q = a.v / b.v;
  return {q, (a.dx - q * b.dx) * inv, (a.dy - q * b.dy) * inv, (a.dz - q * b.dz) * inv};
}
inline Grad& operator+=(Grad& a, Grad b) { return a = a + b; }
inline Grad& operator-=(Grad& a, Grad b) { return a = a - b; }
inline Grad& operator*=(Grad& a, Grad b) { return a = a * b; }

inline Grad sqr(Grad a) { return chain(a, a.v * a.v, 2.0 * a.v); }
inline Grad abs(Grad a) { return a.v < 0.0 ? -a : a; }
inline Grad sqrt(Grad a) {
  const double s = std::sqrt(std::max(a.v, 0.0));
  return chain(a, s, s > 0.0 ? 0.5 / s : 0.0);
}
inline Grad min(Grad a, Grad b) { return a.v <= b.v ? a : b; }
inline Grad max(Grad a, Grad b) { return a.v >= b.v ? a : b; }
inline Grad exp(Grad a) {
  const double e = std::exp(a.v);
  return chain(a, e, e);
}
inline Grad log(Grad a) { return chain(a, std::log(a.v), 1.0 / a.v); }
inline Grad sin(Grad a) { return chain(a, std::sin(a.v), std::cos(a.v)); }
inline Grad cos(Grad a) { return chain(a, std::cos(a.v), -std::sin(a.v)); }
inline Grad atan2(Grad y, Grad x) {
  const double r2 = x.v * x.v + y.v * y.v;
  const double inv = r2 > 0.0 ? 1.0 / r2 : 0.0;
  return {std::atan2(y.v, x.v), (x.v * y.dx - y.v * x.dx) * inv, (x.v * y.dy - y.v * x.dy) * inv,
          (x.v * y.dz - y.v * x.dz) * inv};
}
inline Grad pow(Grad a, double e) { return chain(a, std::pow(a.v, e), e * std::pow(a.v, e - 1.0)); }

}  // namespace emboss

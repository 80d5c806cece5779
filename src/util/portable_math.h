// sin, cos and hypot that give the same bits on every machine: IEEE +, -, *, / and sqrt only (the
// build forbids fused multiply-add), no libm. glibc's sin and cos differ in the last bit between
// x86-64 (an FMA variant picked at run time) and arm64, and the attract pieces' generator turns a
// last bit into a different piece (a stroke split one point later). Accurate to about 1 ulp for
// the angles used here (|x| < 1e5).
#pragma once

#include <cmath>

namespace emboss {

// floor and ceil of a double as an integer, the same value as std::floor or std::ceil then the
// cast, for |v| below the integer type's range, without the libm call that baseline x86-64 makes
// for std::floor and std::ceil (no SSE4.1 rounding instruction): the field tracer finds a column
// block and a grid point this way several times a ray.
inline int floorToInt(double v) {
  const int i = static_cast<int>(v);
  return i - (v < static_cast<double>(i));
}
inline long floorToLong(double v) {
  const long i = static_cast<long>(v);
  return i - (v < static_cast<double>(i));
}
inline long ceilToLong(double v) {
  const long i = static_cast<long>(v);
  return i + (v > static_cast<double>(i));
}

namespace portable_detail {

// x = k pi/2 + r, |r| <= pi/4 (Cody-Waite reduction with fdlibm's two-part pi/2).
inline double reduce(double x, long& k) {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00;  // the first 33 bits of pi/2
  constexpr double kPio2Lo = 6.07710050650619224932e-11;  // pi/2 - kPio2Hi
  const double fk = std::nearbyint(x * kTwoOverPi);
  k = static_cast<long>(fk);
  return (x - fk * kPio2Hi) - fk * kPio2Lo;
}

// fdlibm's kernels on [-pi/4, pi/4].
inline double sinKernel(double r) {
  const double z = r * r;
  return r + r * z * (-1.66666666666666324348e-01 +
                      z * (8.33333333332248946124e-03 +
                           z * (-1.98412698298579493134e-04 +
                                z * (2.75573137070700676789e-06 + z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
}
inline double cosKernel(double r) {
  const double z = r * r;
  return 1.0 - 0.5 * z +
         z * z * (4.16666666666666019037e-02 +
                  z * (-1.38888888888741095749e-03 +
                       z * (2.48015872894767294178e-05 +
                            z * (-2.75573143513906633035e-07 + z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
}

}  // namespace portable_detail

inline double portableSin(double x) {
  long k;
  const double r = portable_detail::reduce(x, k);
  switch (k & 3) {
    case 0: return portable_detail::sinKernel(r);
    case 1: return portable_detail::cosKernel(r);
    case 2: return -portable_detail::sinKernel(r);
    default: return -portable_detail::cosKernel(r);
  }
}

inline double portableCos(double x) {
  long k;
  const double r = portable_detail::reduce(x, k);
  switch (k & 3) {
    case 0: return portable_detail::cosKernel(r);
    case 1: return -portable_detail::sinKernel(r);
    case 2: return -portable_detail::cosKernel(r);
    default: return portable_detail::sinKernel(r);
  }
}

// sqrt(x^2 + y^2) without hypot()'s machine-dependent last bit (lengths in mm: no overflow).
inline double portableHypot(double x, double y) { return std::sqrt(x * x + y * y); }

}  // namespace emboss

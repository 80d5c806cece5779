// The scalar types the kernels are instantiated for, and the overloads they share.
#pragma once

#include <algorithm>
#include <cmath>

#include "frep/grad.h"
#include "frep/interval.h"

namespace emboss {

inline double sqr(double a) { return a * a; }
using std::abs;
using std::atan2;
using std::cos;
using std::exp;
using std::log;
using std::max;
using std::min;
using std::pow;
using std::sin;
using std::sqrt;

// The plain value of a scalar: the value, the value of a Grad, the midpoint of an interval.
inline double valueOf(double a) { return a; }
inline double valueOf(const Grad& a) { return a.v; }
inline double valueOf(const Interval& a) { return a.mid(); }

// A point of space in the scalar type T.
template <class T>
struct P3 {
  T x, y, z;
};

}  // namespace emboss

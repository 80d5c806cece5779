// The vm format's opcode table and the operations for each scalar type, shared by the parser,
// the evaluator, the POV-Ray writer and the bound search (internal to src/frep).
#pragma once

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "frep/grad.h"
#include "frep/interval.h"
#include "frep/vm_model.h"

namespace emboss::vm_detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kPi = std::numbers::pi;

// ---- opcode table

struct OpInfo {
  std::string_view name;
  VmOp op;
  int arity;
};

constexpr std::array<OpInfo, 33> kOps{{
    {"const", VmOp::kConst, 0},   {"var-x", VmOp::kVarX, 0},     {"var-y", VmOp::kVarY, 0},
    {"var-z", VmOp::kVarZ, 0},    {"neg", VmOp::kNeg, 1},        {"abs", VmOp::kAbs, 1},
    {"recip", VmOp::kRecip, 1},   {"sqrt", VmOp::kSqrt, 1},      {"square", VmOp::kSquare, 1},
    {"floor", VmOp::kFloor, 1},   {"ceil", VmOp::kCeil, 1},      {"round", VmOp::kRound, 1},
    {"sin", VmOp::kSin, 1},       {"cos", VmOp::kCos, 1},        {"tan", VmOp::kTan, 1},
    {"asin", VmOp::kAsin, 1},     {"acos", VmOp::kAcos, 1},      {"atan", VmOp::kAtan, 1},
    {"exp", VmOp::kExp, 1},       {"ln", VmOp::kLn, 1},          {"not", VmOp::kNot, 1},
    {"add", VmOp::kAdd, 2},       {"sub", VmOp::kSub, 2},        {"mul", VmOp::kMul, 2},
    {"div", VmOp::kDiv, 2},       {"min", VmOp::kMin, 2},        {"max", VmOp::kMax, 2},
    {"atan2", VmOp::kAtan2, 2},   {"pow", VmOp::kPow, 2},        {"mod", VmOp::kMod, 2},
    {"compare", VmOp::kCompare, 2}, {"and", VmOp::kAnd, 2},      {"or", VmOp::kOr, 2},
}};

inline const OpInfo* findOp(std::string_view name) {
  for (const OpInfo& o : kOps) {
    if (o.name == name) return &o;
  }
  if (name == "log") return findOp("ln");  // libfive's name for the natural logarithm
  return nullptr;
}

inline const OpInfo& infoOf(VmOp op) {
  for (const OpInfo& o : kOps) {
    if (o.op == op) return o;
  }
  return kOps[0];
}

inline bool isLeaf(VmOp op) { return op == VmOp::kConst || op == VmOp::kVarX || op == VmOp::kVarY || op == VmOp::kVarZ; }

// ---- the operations for each scalar type. The double versions define the semantics (Fidget's);
// the Grad versions give exactly the same value plus the derivative; the Interval versions are
// conservative (up to rounding) and never NaN (fix() turns NaN into the whole line).

inline double dMin(double a, double b) {
  if (a < b) return a;
  if (b < a) return b;
  return std::isnan(a) ? a : b;
}
inline double dMax(double a, double b) {
  if (a > b) return a;
  if (b > a) return b;
  return std::isnan(a) ? a : b;
}
// Euclidean remainder (Rust's rem_euclid): in [0, |b|).
inline double dMod(double a, double b) {
  const double r = std::fmod(a, b);
  return r < 0.0 ? r + std::fabs(b) : r;
}
inline double dCompare(double a, double b) {
  if (a < b) return -1.0;
  if (a > b) return 1.0;
  if (a == b) return 0.0;
  return kNaN;
}

inline double fix(double a) { return a; }
inline Grad fix(const Grad& a) { return a; }
inline Interval fix(Interval a) { return a.lo <= a.hi ? a : Interval::whole(); }

// double
inline double opNeg(double a) { return -a; }
inline double opAbs(double a) { return std::fabs(a); }
inline double opRecip(double a) { return 1.0 / a; }
inline double opSqrt(double a) { return std::sqrt(a); }
inline double opSquare(double a) { return a * a; }
inline double opFloor(double a) { return std::floor(a); }
inline double opCeil(double a) { return std::ceil(a); }
inline double opRound(double a) { return std::round(a); }
inline double opSin(double a) { return std::sin(a); }
inline double opCos(double a) { return std::cos(a); }
inline double opTan(double a) { return std::tan(a); }
inline double opAsin(double a) { return std::asin(a); }
inline double opAcos(double a) { return std::acos(a); }
inline double opAtan(double a) { return std::atan(a); }
inline double opExp(double a) { return std::exp(a); }
inline double opLn(double a) { return std::log(a); }
inline double opNot(double a) { return a == 0.0 ? 1.0 : 0.0; }
inline double opAdd(double a, double b) { return a + b; }
inline double opSub(double a, double b) { return a - b; }
inline double opMul(double a, double b) { return a * b; }
inline double opDiv(double a, double b) { return a / b; }
inline double opMin(double a, double b) { return dMin(a, b); }
inline double opMax(double a, double b) { return dMax(a, b); }
inline double opAtan2(double a, double b) { return std::atan2(a, b); }
inline double opPow(double a, double b) { return std::pow(a, b); }
inline double opMod(double a, double b) { return dMod(a, b); }
inline double opCompare(double a, double b) { return dCompare(a, b); }
inline double opAnd(double a, double b) { return a == 0.0 ? a : b; }
inline double opOr(double a, double b) { return a != 0.0 ? a : b; }

// Grad: value as the double version, derivative by the chain rule.
inline bool constantGrad(const Grad& a) { return a.dx == 0.0 && a.dy == 0.0 && a.dz == 0.0; }
inline Grad opNeg(const Grad& a) { return -a; }
inline Grad opAbs(const Grad& a) {
  Grad r = a.v < 0.0 ? -a : a;
  r.v = std::fabs(a.v);
  return r;
}
inline Grad opRecip(const Grad& a) {
  const double v = 1.0 / a.v;
  return chain(a, v, -v * v);
}
inline Grad opSqrt(const Grad& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, s > 0.0 ? 0.5 / s : 0.0);
}
inline Grad opSquare(const Grad& a) { return chain(a, a.v * a.v, 2.0 * a.v); }
inline Grad opFloor(const Grad& a) { return Grad(std::floor(a.v)); }
inline Grad opCeil(const Grad& a) { return Grad(std::ceil(a.v)); }
inline Grad opRound(const Grad& a) { return Grad(std::round(a.v)); }
inline Grad opSin(const Grad& a) { return chain(a, std::sin(a.v), std::cos(a.v)); }
inline Grad opCos(const Grad& a) { return chain(a, std::cos(a.v), -std::sin(a.v)); }
inline Grad opTan(const Grad& a) {
  const double t = std::tan(a.v);
  return chain(a, t, 1.0 + t * t);
}
inline Grad opAsin(const Grad& a) { return chain(a, std::asin(a.v), 1.0 / std::sqrt(1.0 - a.v * a.v)); }
inline Grad opAcos(const Grad& a) { return chain(a, std::acos(a.v), -1.0 / std::sqrt(1.0 - a.v * a.v)); }
inline Grad opAtan(const Grad& a) { return chain(a, std::atan(a.v), 1.0 / (1.0 + a.v * a.v)); }
inline Grad opExp(const Grad& a) {
  const double e = std::exp(a.v);
  return chain(a, e, e);
}
inline Grad opLn(const Grad& a) { return chain(a, std::log(a.v), 1.0 / a.v); }
inline Grad opNot(const Grad& a) { return Grad(opNot(a.v)); }
inline Grad opAdd(const Grad& a, const Grad& b) { return a + b; }
inline Grad opSub(const Grad& a, const Grad& b) { return a - b; }
inline Grad opMul(const Grad& a, const Grad& b) { return a * b; }
inline Grad opDiv(const Grad& a, const Grad& b) {
  const double q = a.v / b.v;
  const double inv = 1.0 / b.v;
  return {q, (a.dx - q * b.dx) * inv, (a.dy - q * b.dy) * inv, (a.dz - q * b.dz) * inv};
}
inline Grad opMin(const Grad& a, const Grad& b) {
  if (a.v < b.v) return a;
  if (b.v < a.v) return b;
  return std::isnan(a.v) ? a : b;
}
inline Grad opMax(const Grad& a, const Grad& b) {
  if (a.v > b.v) return a;
  if (b.v > a.v) return b;
  return std::isnan(a.v) ? a : b;
}
inline Grad opAtan2(const Grad& a, const Grad& b) {
  // d atan2(a, b) = (b da - a db) / (a^2 + b^2)
  const double r2 = a.v * a.v + b.v * b.v;
  const double inv = r2 > 0.0 ? 1.0 / r2 : 0.0;
  return {std::atan2(a.v, b.v), (b.v * a.dx - a.v * b.dx) * inv, (b.v * a.dy - a.v * b.dy) * inv,
          (b.v * a.dz - a.v * b.dz) * inv};
}
inline Grad opPow(const Grad& a, const Grad& b) {
  const double v = std::pow(a.v, b.v);
  // Skip a term whose variable is constant, so inf * 0 does not turn the gradient into NaN.
  const double ca = constantGrad(a) ? 0.0 : b.v * std::pow(a.v, b.v - 1.0);
  const double cb = constantGrad(b) || !(a.v > 0.0) ? 0.0 : v * std::log(a.v);
  return {v, ca * a.dx + cb * b.dx, ca * a.dy + cb * b.dy, ca * a.dz + cb * b.dz};
}
inline Grad opMod(const Grad& a, const Grad& b) {
  // r = a - q b with q an integer, constant where r is differentiable.
  const double r = dMod(a.v, b.v);
  const double q = std::round((a.v - r) / b.v);
  if (constantGrad(b)) return {r, a.dx, a.dy, a.dz};
  return {r, a.dx - q * b.dx, a.dy - q * b.dy, a.dz - q * b.dz};
}
inline Grad opCompare(const Grad& a, const Grad& b) { return Grad(dCompare(a.v, b.v)); }
inline Grad opAnd(const Grad& a, const Grad& b) { return a.v == 0.0 ? a : b; }
inline Grad opOr(const Grad& a, const Grad& b) { return a.v != 0.0 ? a : b; }

// Interval
inline Interval opNeg(Interval a) { return -a; }
inline Interval opAbs(Interval a) { return abs(a); }
inline Interval opRecip(Interval a) { return Interval(1.0) / a; }
inline Interval opSqrt(Interval a) { return sqrt(a); }
inline Interval opSquare(Interval a) { return sqr(a); }
inline Interval opFloor(Interval a) { return {std::floor(a.lo), std::floor(a.hi)}; }
inline Interval opCeil(Interval a) { return {std::ceil(a.lo), std::ceil(a.hi)}; }
inline Interval opRound(Interval a) { return {std::round(a.lo), std::round(a.hi)}; }
inline Interval opSin(Interval a) { return sin(a); }
inline Interval opCos(Interval a) { return cos(a); }
inline Interval opTan(Interval a) {
  // Monotone between poles at pi/2 + k pi; anything wider or far out (where the pole position is
  // lost to rounding) may contain one.
  if (!(a.width() < kPi) || !(std::fabs(a.lo) < 1e9) || !(std::fabs(a.hi) < 1e9)) return Interval::whole();
  const double k = std::ceil((a.lo - kPi / 2) / kPi);
  if (kPi / 2 + k * kPi <= a.hi) return Interval::whole();
  return {std::tan(a.lo), std::tan(a.hi)};
}
inline Interval opAsin(Interval a) {
  if (a.hi < -1.0 || a.lo > 1.0) return Interval::whole();  // NaN everywhere
  return {std::asin(std::max(a.lo, -1.0)), std::asin(std::min(a.hi, 1.0))};
}
inline Interval opAcos(Interval a) {
  if (a.hi < -1.0 || a.lo > 1.0) return Interval::whole();
  return {std::acos(std::min(a.hi, 1.0)), std::acos(std::max(a.lo, -1.0))};
}
inline Interval opAtan(Interval a) { return {std::atan(a.lo), std::atan(a.hi)}; }
inline Interval opExp(Interval a) { return exp(a); }
// ln 0 is -inf exactly (as the double version gives, e.g. the log of an exp that underflowed); the
// whole line would lose it, and with it every bound of a log-sum-exp blend far from the model.
inline Interval opLn(Interval a) {
  if (a.hi == 0.0 && a.lo <= 0.0) return {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  return log(a);
}
inline Interval opNot(Interval a) {
  if (!a.contains(0.0)) return {0.0, 0.0};
  if (a.lo == 0.0 && a.hi == 0.0) return {1.0, 1.0};
  return {0.0, 1.0};
}
inline Interval opAdd(Interval a, Interval b) { return a + b; }
inline Interval opSub(Interval a, Interval b) { return a - b; }
inline Interval opMul(Interval a, Interval b) { return a * b; }
inline Interval opDiv(Interval a, Interval b) { return a / b; }
inline Interval opMin(Interval a, Interval b) { return min(a, b); }
inline Interval opMax(Interval a, Interval b) { return max(a, b); }
inline Interval opAtan2(Interval a, Interval b) { return atan2(a, b); }
inline Interval opPow(Interval a, Interval b) {
  if (b.lo == b.hi) {
    const double e = b.lo;
    if (!std::isfinite(e)) return Interval::whole();
    // emboss::pow casts integral exponents to long: only hand it ones that fit.
    if (e == std::floor(e) && std::fabs(e) > 1e9) {
      if (a.lo >= 1.0) return e > 0 ? Interval(std::pow(a.lo, e), std::pow(a.hi, e)) : Interval(0.0, 1.0);
      return Interval::whole();
    }
    return pow(a, e);
  }
  if (a.lo > 0.0) return exp(b * log(a));
  return Interval::whole();
}
inline Interval opMod(Interval a, Interval b) {
  const double m = std::max(std::fabs(b.lo), std::fabs(b.hi));
  if (b.lo == b.hi && m > 0.0 && std::isfinite(a.lo) && std::isfinite(a.hi) && a.hi - a.lo < m) {
    // Within one period the remainder is a + const: monotone. A wrap shows as rl > rh.
    const double rl = dMod(a.lo, b.lo), rh = dMod(a.hi, b.lo);
    if (rl <= rh) return {rl, rh};
  }
  return {0.0, m};
}
inline Interval opCompare(Interval a, Interval b) {
  if (a.hi < b.lo) return {-1.0, -1.0};
  if (a.lo > b.hi) return {1.0, 1.0};
  if (a.lo == a.hi && b.lo == b.hi && a.lo == b.lo) return {0.0, 0.0};
  return {-1.0, 1.0};
}
inline Interval opAnd(Interval a, Interval b) {
  if (a.lo == 0.0 && a.hi == 0.0) return {0.0, 0.0};
  if (!a.contains(0.0)) return b;
  return {std::min(0.0, b.lo), std::max(0.0, b.hi)};
}
inline Interval opOr(Interval a, Interval b) {
  if (!a.contains(0.0)) return a;
  if (a.lo == 0.0 && a.hi == 0.0) return b;
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

// The double value of one operation (constant folding).
inline double applyDouble(VmOp op, double a, double b) {
  switch (op) {
    case VmOp::kNeg: return opNeg(a);
    case VmOp::kAbs: return opAbs(a);
    case VmOp::kRecip: return opRecip(a);
    case VmOp::kSqrt: return opSqrt(a);
    case VmOp::kSquare: return opSquare(a);
    case VmOp::kFloor: return opFloor(a);
    case VmOp::kCeil: return opCeil(a);
    case VmOp::kRound: return opRound(a);
    case VmOp::kSin: return opSin(a);
    case VmOp::kCos: return opCos(a);
    case VmOp::kTan: return opTan(a);
    case VmOp::kAsin: return opAsin(a);
    case VmOp::kAcos: return opAcos(a);
    case VmOp::kAtan: return opAtan(a);
    case VmOp::kExp: return opExp(a);
    case VmOp::kLn: return opLn(a);
    case VmOp::kNot: return opNot(a);
    case VmOp::kAdd: return opAdd(a, b);
    case VmOp::kSub: return opSub(a, b);
    case VmOp::kMul: return opMul(a, b);
    case VmOp::kDiv: return opDiv(a, b);
    case VmOp::kMin: return opMin(a, b);
    case VmOp::kMax: return opMax(a, b);
    case VmOp::kAtan2: return opAtan2(a, b);
    case VmOp::kPow: return opPow(a, b);
    case VmOp::kMod: return opMod(a, b);
    case VmOp::kCompare: return opCompare(a, b);
    case VmOp::kAnd: return opAnd(a, b);
    case VmOp::kOr: return opOr(a, b);
    case VmOp::kConst:
    case VmOp::kVarX:
    case VmOp::kVarY:
    case VmOp::kVarZ: break;
  }
  return kNaN;
}

// One node of a program's SSA graph for any scalar type, its operands' values in v (by node).
// Always inlined: it is the inner loop of the bench's baseline and of specialisation.
template <class T>
[[gnu::always_inline]] inline T applyNode(const VmProgram::Node& n, const T* v, T x, T y, T z) {
  switch (n.op) {
    case VmOp::kConst: return T(n.imm);
    case VmOp::kVarX: return x;
    case VmOp::kVarY: return y;
    case VmOp::kVarZ: return z;
    case VmOp::kNeg: return fix(opNeg(v[n.a]));
    case VmOp::kAbs: return fix(opAbs(v[n.a]));
    case VmOp::kRecip: return fix(opRecip(v[n.a]));
    case VmOp::kSqrt: return fix(opSqrt(v[n.a]));
    case VmOp::kSquare: return fix(opSquare(v[n.a]));
    case VmOp::kFloor: return fix(opFloor(v[n.a]));
    case VmOp::kCeil: return fix(opCeil(v[n.a]));
    case VmOp::kRound: return fix(opRound(v[n.a]));
    case VmOp::kSin: return fix(opSin(v[n.a]));
    case VmOp::kCos: return fix(opCos(v[n.a]));
    case VmOp::kTan: return fix(opTan(v[n.a]));
    case VmOp::kAsin: return fix(opAsin(v[n.a]));
    case VmOp::kAcos: return fix(opAcos(v[n.a]));
    case VmOp::kAtan: return fix(opAtan(v[n.a]));
    case VmOp::kExp: return fix(opExp(v[n.a]));
    case VmOp::kLn: return fix(opLn(v[n.a]));
    case VmOp::kNot: return fix(opNot(v[n.a]));
    case VmOp::kAdd: return fix(opAdd(v[n.a], v[n.b]));
    case VmOp::kSub: return fix(opSub(v[n.a], v[n.b]));
    case VmOp::kMul: return fix(opMul(v[n.a], v[n.b]));
    case VmOp::kDiv: return fix(opDiv(v[n.a], v[n.b]));
    case VmOp::kMin: return fix(opMin(v[n.a], v[n.b]));
    case VmOp::kMax: return fix(opMax(v[n.a], v[n.b]));
    case VmOp::kAtan2: return fix(opAtan2(v[n.a], v[n.b]));
    case VmOp::kPow: return fix(opPow(v[n.a], v[n.b]));
    case VmOp::kMod: return fix(opMod(v[n.a], v[n.b]));
    case VmOp::kCompare: return fix(opCompare(v[n.a], v[n.b]));
    case VmOp::kAnd: return fix(opAnd(v[n.a], v[n.b]));
    case VmOp::kOr: return fix(opOr(v[n.a], v[n.b]));
  }
  return T(0.0);
}

// ---- tape pruning (VmProgram::specialised, the bench's baseline)

// Which operand decides a min or max over a box, from their intervals there: 1 a, 2 b, 0 either
// may (or not a min or max). The intervals' rounding is not directed, so one operand must be
// below the other by a margin; non-finite bounds decide nothing.
inline std::uint8_t decidingOperand(VmOp op, const Interval& a, const Interval& b) {
  if (op != VmOp::kMin && op != VmOp::kMax) return 0;
  if (!std::isfinite(a.lo) || !std::isfinite(a.hi) || !std::isfinite(b.lo) || !std::isfinite(b.hi)) return 0;
  // Below by the margin: checked only once plainly below (the common undecided case stays cheap).
  const auto below = [](const Interval& u, const Interval& v) {
    return u.hi < v.lo && u.hi + 1e-9 * (1.0 + std::max(std::fabs(u.hi), std::fabs(v.lo))) < v.lo;
  };
  if (below(a, b)) return op == VmOp::kMin ? 1 : 2;
  if (below(b, a)) return op == VmOp::kMin ? 2 : 1;
  return 0;
}

// Buffers pruneNodes reuses from call to call.
struct PruneScratch {
  std::vector<std::uint32_t> alias, remap;
  std::vector<char> live;
};

// The tape t with every node whose choice (decidingOperand) is 1 or 2 replaced by that operand,
// and what no longer reaches the last node dropped, into out (t's order kept).
void pruneNodes(const std::vector<VmProgram::Node>& t, const std::vector<std::uint8_t>& choice, PruneScratch& s,
                std::vector<VmProgram::Node>& out);
// t into out with every node computed from constants alone by an operation that gives the same
// bits in every arithmetic (add, sub, mul, neg, abs, square, min, max; a finite result) made a
// constant, and every x - (+0) marked in choice as standing for x: what decided mins and maxes
// leave behind (a smooth union whose blend is decided computes m - square(0) * c).
void foldConstants(const std::vector<VmProgram::Node>& t, std::vector<std::uint8_t>& choice,
                   std::vector<VmProgram::Node>& out);

// ---- text shared by the messages and writers

// A token as it may appear in a message: quoted, printable, not too long.
inline std::string shown(std::string_view tok) {
  constexpr std::size_t kMaxShown = 40;
  std::string s = "'";
  for (std::size_t i = 0; i < tok.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(tok[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      s += static_cast<char>(c);
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 15];
    }
  }
  if (tok.size() > kMaxShown) s += "...";
  s += "'";
  return s;
}

// Shortest text that reads back as v (finite v only).
inline std::string formatNumber(double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec != std::errc()) return "0";
  return std::string(buf, ptr);
}

}  // namespace emboss::vm_detail

// Importer, compiler and evaluator for vm-format F-rep models, their workpiece and POV-Ray output.
#include "frep/vm_model.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <sstream>
#include <system_error>
#include <unordered_map>
#include <utility>

namespace emboss {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;
// Refuse texts with more clauses than this (slots are 32-bit; memory stays bounded).
constexpr std::size_t kMaxClauses = 20'000'000;
// Refuse files larger than this (bytes) before reading them.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;

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

const OpInfo* findOp(std::string_view name) {
  for (const OpInfo& o : kOps) {
    if (o.name == name) return &o;
  }
  if (name == "log") return findOp("ln");  // libfive's name for the natural logarithm
  return nullptr;
}

const OpInfo& infoOf(VmOp op) {
  for (const OpInfo& o : kOps) {
    if (o.op == op) return o;
  }
  return kOps[0];
}

bool isLeaf(VmOp op) { return op == VmOp::kConst || op == VmOp::kVarX || op == VmOp::kVarY || op == VmOp::kVarZ; }

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
Interval opTan(Interval a) {
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
inline Interval opLn(Interval a) { return log(a); }
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
Interval opPow(Interval a, Interval b) {
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
Interval opMod(Interval a, Interval b) {
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
double applyDouble(VmOp op, double a, double b) {
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

// ---- messages

// A token as it may appear in a message: quoted, printable, not too long.
std::string shown(std::string_view tok) {
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

std::string placeOf(std::string_view source, std::size_t line) {
  if (source.empty()) return "line " + std::to_string(line);
  return std::string(source) + ":" + std::to_string(line);
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Parses a whole token as a finite double (an optional leading '+' allowed).
std::optional<double> parseNumber(std::string_view tok) {
  if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-') tok.remove_prefix(1);
  double v = 0.0;
  const char* end = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(tok.data(), end, v, std::chars_format::general);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Shortest text that reads back as v (finite v only).
std::string formatNumber(double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec != std::errc()) return "0";
  return std::string(buf, ptr);
}

}  // namespace

std::string_view vmOpName(VmOp op) { return infoOf(op).name; }
int vmOpArity(VmOp op) {
  // The enum lists leaves, then unary, then binary operations (called per node while compiling).
  if (op >= VmOp::kAdd) return 2;
  if (op >= VmOp::kNeg) return 1;
  return 0;
}

// ---- parsing and compiling

Result<VmProgram> VmProgram::parse(std::string_view text, std::string_view sourceName) {
  struct Parsed {
    VmOp op;
    std::uint32_t a, b;
    double imm;
  };
  struct Defined {
    std::uint32_t index;
    std::size_t line;
  };
  std::vector<Parsed> all;
  std::unordered_map<std::string_view, Defined> ids;
  {
    const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    const std::size_t guess = std::min<std::size_t>(lines, 1u << 22);  // a hint only
    all.reserve(guess);
    ids.reserve(guess);
  }

  const auto failAt = [&](std::size_t line, const std::string& message) {
    return fail(placeOf(sourceName, line) + ": " + message);
  };

  std::size_t lineNo = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++lineNo;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);

    // Tokens: ID OPCODE [ARG...]; keep one more than any opcode takes, to report extras.
    std::array<std::string_view, 5> tok;
    std::size_t count = 0;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && isBlank(line[i])) ++i;
      if (i >= line.size()) break;
      const std::size_t start = i;
      while (i < line.size() && !isBlank(line[i])) ++i;
      if (count < tok.size()) tok[count] = line.substr(start, i - start);
      ++count;
    }
    if (count == 0) continue;
    if (count == 1) return failAt(lineNo, shown(tok[0]) + " has no opcode");

    const OpInfo* info = findOp(tok[1]);
    if (!info) return failAt(lineNo, "unknown opcode " + shown(tok[1]));
    const std::size_t args = count - 2;
    Parsed p{info->op, 0, 0, 0.0};
    if (info->op == VmOp::kConst) {
      if (args != 1) return failAt(lineNo, "'const' takes one number, got " + std::to_string(args) + " arguments");
      const std::optional<double> v = parseNumber(tok[2]);
      if (!v) return failAt(lineNo, shown(tok[2]) + " is not a finite number");
      p.imm = *v;
    } else {
      if (args != static_cast<std::size_t>(info->arity)) {
        const std::string name(info->name);
        if (info->arity == 0) return failAt(lineNo, "'" + name + "' takes no operands, got " + std::to_string(args));
        return failAt(lineNo, "'" + name + "' takes " + std::to_string(info->arity) + " operand" +
                                  (info->arity == 1 ? "" : "s") + ", got " + std::to_string(args));
      }
      for (int k = 0; k < info->arity; ++k) {
        const auto it = ids.find(tok[2 + k]);
        if (it == ids.end()) return failAt(lineNo, shown(tok[2 + k]) + " used before it is defined");
        (k == 0 ? p.a : p.b) = it->second.index;
      }
    }
    if (all.size() >= kMaxClauses) return failAt(lineNo, "too many clauses (the limit is " + std::to_string(kMaxClauses) + ")");
    const auto [it, inserted] = ids.try_emplace(tok[0], Defined{static_cast<std::uint32_t>(all.size()), lineNo});
    if (!inserted) {
      return failAt(lineNo, shown(tok[0]) + " is already defined on line " + std::to_string(it->second.line));
    }
    all.push_back(p);
    if (eol == text.size()) break;
  }
  if (all.empty()) {
    return fail(sourceName.empty() ? std::string("empty model (no clauses)")
                                   : std::string(sourceName) + ": empty model (no clauses)");
  }

  // Dead-clause removal and constant folding, in one forward pass over the live clauses (operands
  // come first, so a folded operand is known when its user is reached).
  const std::size_t n = all.size();
  std::vector<char> live(n, 0);
  live[n - 1] = 1;
  for (std::size_t i = n; i-- > 0;) {
    if (!live[i]) continue;
    const int arity = vmOpArity(all[i].op);
    if (arity >= 1) live[all[i].a] = 1;
    if (arity >= 2) live[all[i].b] = 1;
  }
  std::vector<Node> folded;
  std::vector<std::uint32_t> newIndex(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!live[i]) continue;
    Node nd{all[i].op, 0, 0, all[i].imm};
    const int arity = vmOpArity(nd.op);
    if (arity >= 1) nd.a = newIndex[all[i].a];
    if (arity >= 2) nd.b = newIndex[all[i].b];
    if (arity >= 1) {
      const bool constA = folded[nd.a].op == VmOp::kConst;
      const bool constB = arity < 2 || folded[nd.b].op == VmOp::kConst;
      if (constA && constB) {
        const double v = applyDouble(nd.op, folded[nd.a].imm, arity >= 2 ? folded[nd.b].imm : 0.0);
        if (std::isfinite(v)) nd = Node{VmOp::kConst, 0, 0, v};  // keep non-finite ones as written
      }
    }
    newIndex[i] = static_cast<std::uint32_t>(folded.size());
    folded.push_back(nd);
  }
  std::vector<char>().swap(live);
  std::vector<Parsed>().swap(all);

  // Folding may leave constants unused: drop dead nodes again.
  VmProgram prog;
  prog.sourceName_ = std::string(sourceName);
  prog.clauseCount_ = n;
  {
    const std::size_t m = folded.size();
    std::vector<char> used(m, 0);
    used[m - 1] = 1;
    for (std::size_t i = m; i-- > 0;) {
      if (!used[i]) continue;
      const int arity = vmOpArity(folded[i].op);
      if (arity >= 1) used[folded[i].a] = 1;
      if (arity >= 2) used[folded[i].b] = 1;
    }
    std::vector<std::uint32_t> remap(m, 0);
    prog.nodes_.reserve(m);
    for (std::size_t i = 0; i < m; ++i) {
      if (!used[i]) continue;
      Node nd = folded[i];
      const int arity = vmOpArity(nd.op);
      if (arity >= 1) nd.a = remap[nd.a];
      if (arity >= 2) nd.b = remap[nd.b];
      remap[i] = static_cast<std::uint32_t>(prog.nodes_.size());
      prog.nodes_.push_back(nd);
      if (nd.op == VmOp::kVarZ) prog.usesZ_ = true;
    }
  }

  // Slot allocation: a node's slot is freed after its last use and reused (LIFO, so recently
  // touched memory stays hot). An instruction reads its operands before writing its result, so
  // the result may take an operand's freed slot.
  const std::vector<Node>& nodes = prog.nodes_;
  const std::size_t m = nodes.size();
  std::vector<std::uint32_t> lastUse(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const int arity = vmOpArity(nodes[i].op);
    if (arity >= 1) lastUse[nodes[i].a] = static_cast<std::uint32_t>(i);
    if (arity >= 2) lastUse[nodes[i].b] = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t> slot(m, 0);
  std::vector<std::uint32_t> freeSlots;
  std::uint32_t slots = 0;
  prog.code_.reserve(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Node& nd = nodes[i];
    const int arity = vmOpArity(nd.op);
    if (arity >= 1 && lastUse[nd.a] == i) freeSlots.push_back(slot[nd.a]);
    if (arity >= 2 && nd.b != nd.a && lastUse[nd.b] == i) freeSlots.push_back(slot[nd.b]);
    if (!freeSlots.empty()) {
      slot[i] = freeSlots.back();
      freeSlots.pop_back();
    } else {
      slot[i] = slots++;
    }
    Instr in;
    in.op = nd.op;
    in.out = slot[i];
    in.a = arity >= 1 ? slot[nd.a] : 0;
    in.b = arity >= 2 ? slot[nd.b] : 0;
    in.imm = nd.imm;
    prog.code_.push_back(in);
  }
  prog.slotCount_ = slots;
  prog.resultSlot_ = slot[m - 1];
  return prog;
}

Result<VmProgram> VmProgram::load(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) return fail("cannot read '" + name + "': it is a folder");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) return fail("cannot read '" + name + "': " + ec.message());
  if (bytes > kMaxFileBytes) return fail("cannot read '" + name + "': the file is too large for a model");
  std::ifstream in(file, std::ios::binary);
  if (!in) return fail("cannot open '" + name + "'");
  std::string text(static_cast<std::size_t>(bytes), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.gcount() != static_cast<std::streamsize>(text.size())) return fail("cannot read '" + name + "': read failed");
  return parse(text, name);
}

// ---- evaluation

template <class T>
T VmProgram::run(T x, T y, T z, T* s) const {
  for (const Instr& in : code_) {
    switch (in.op) {
      case VmOp::kConst: s[in.out] = T(in.imm); break;
      case VmOp::kVarX: s[in.out] = x; break;
      case VmOp::kVarY: s[in.out] = y; break;
      case VmOp::kVarZ: s[in.out] = z; break;
      case VmOp::kNeg: s[in.out] = fix(opNeg(s[in.a])); break;
      case VmOp::kAbs: s[in.out] = fix(opAbs(s[in.a])); break;
      case VmOp::kRecip: s[in.out] = fix(opRecip(s[in.a])); break;
      case VmOp::kSqrt: s[in.out] = fix(opSqrt(s[in.a])); break;
      case VmOp::kSquare: s[in.out] = fix(opSquare(s[in.a])); break;
      case VmOp::kFloor: s[in.out] = fix(opFloor(s[in.a])); break;
      case VmOp::kCeil: s[in.out] = fix(opCeil(s[in.a])); break;
      case VmOp::kRound: s[in.out] = fix(opRound(s[in.a])); break;
      case VmOp::kSin: s[in.out] = fix(opSin(s[in.a])); break;
      case VmOp::kCos: s[in.out] = fix(opCos(s[in.a])); break;
      case VmOp::kTan: s[in.out] = fix(opTan(s[in.a])); break;
      case VmOp::kAsin: s[in.out] = fix(opAsin(s[in.a])); break;
      case VmOp::kAcos: s[in.out] = fix(opAcos(s[in.a])); break;
      case VmOp::kAtan: s[in.out] = fix(opAtan(s[in.a])); break;
      case VmOp::kExp: s[in.out] = fix(opExp(s[in.a])); break;
      case VmOp::kLn: s[in.out] = fix(opLn(s[in.a])); break;
      case VmOp::kNot: s[in.out] = fix(opNot(s[in.a])); break;
      case VmOp::kAdd: s[in.out] = fix(opAdd(s[in.a], s[in.b])); break;
      case VmOp::kSub: s[in.out] = fix(opSub(s[in.a], s[in.b])); break;
      case VmOp::kMul: s[in.out] = fix(opMul(s[in.a], s[in.b])); break;
      case VmOp::kDiv: s[in.out] = fix(opDiv(s[in.a], s[in.b])); break;
      case VmOp::kMin: s[in.out] = fix(opMin(s[in.a], s[in.b])); break;
      case VmOp::kMax: s[in.out] = fix(opMax(s[in.a], s[in.b])); break;
      case VmOp::kAtan2: s[in.out] = fix(opAtan2(s[in.a], s[in.b])); break;
      case VmOp::kPow: s[in.out] = fix(opPow(s[in.a], s[in.b])); break;
      case VmOp::kMod: s[in.out] = fix(opMod(s[in.a], s[in.b])); break;
      case VmOp::kCompare: s[in.out] = fix(opCompare(s[in.a], s[in.b])); break;
      case VmOp::kAnd: s[in.out] = fix(opAnd(s[in.a], s[in.b])); break;
      case VmOp::kOr: s[in.out] = fix(opOr(s[in.a], s[in.b])); break;
    }
  }
  return s[resultSlot_];
}

template <class T>
T VmProgram::runWithThreadScratch(T x, T y, T z) const {
  // One buffer per thread and scalar type; it grows to the largest program seen, then never
  // allocates again.
  thread_local std::vector<T> scratch;
  if (scratch.size() < slotCount_) scratch.resize(slotCount_);
  return run(x, y, z, scratch.data());
}

double VmProgram::eval(double x, double y, double z) const {
  if (code_.empty()) return kNaN;
  return runWithThreadScratch(x, y, z);
}
Grad VmProgram::eval(Grad x, Grad y, Grad z) const {
  if (code_.empty()) return Grad(kNaN);
  return runWithThreadScratch(x, y, z);
}
Interval VmProgram::eval(Interval x, Interval y, Interval z) const {
  if (code_.empty()) return Interval::whole();
  return runWithThreadScratch(x, y, z);
}
double VmProgram::eval(double x, double y, double z, std::span<double> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return kNaN;
  return run(x, y, z, scratch.data());
}
Grad VmProgram::eval(Grad x, Grad y, Grad z, std::span<Grad> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return Grad(kNaN);
  return run(x, y, z, scratch.data());
}
Interval VmProgram::eval(Interval x, Interval y, Interval z, std::span<Interval> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return Interval::whole();
  return run(x, y, z, scratch.data());
}

// ---- POV-Ray output

namespace {

// POV-Ray text of each operation: @0 / @1 stand for the operands (each already self-delimiting:
// a number in parentheses if negative, a variable, a parameter, a call or a parenthesised
// expression). POV's select(a,b,c) is b if a < 0 else c; select(a,b,c,d) is b if a < 0, c if
// a = 0, else d.
std::string_view povTemplate(VmOp op) {
  switch (op) {
    case VmOp::kNeg: return "(-@0)";
    case VmOp::kAbs: return "abs(@0)";
    case VmOp::kRecip: return "(1/@0)";
    case VmOp::kSqrt: return "sqrt(@0)";
    case VmOp::kSquare: return "pow(@0,2)";
    case VmOp::kFloor: return "floor(@0)";
    case VmOp::kCeil: return "ceil(@0)";
    case VmOp::kRound: return "select(@0,(-floor(0.5-@0)),floor(@0+0.5))";  // half away from zero
    case VmOp::kSin: return "sin(@0)";
    case VmOp::kCos: return "cos(@0)";
    case VmOp::kTan: return "tan(@0)";
    case VmOp::kAsin: return "asin(@0)";
    case VmOp::kAcos: return "acos(@0)";
    case VmOp::kAtan: return "atan(@0)";
    case VmOp::kExp: return "exp(@0)";
    case VmOp::kLn: return "ln(@0)";  // POV's log is base 10
    case VmOp::kNot: return "select(@0,0,1,0)";
    case VmOp::kAdd: return "(@0+@1)";
    case VmOp::kSub: return "(@0-@1)";
    case VmOp::kMul: return "(@0*@1)";
    case VmOp::kDiv: return "(@0/@1)";
    case VmOp::kMin: return "min(@0,@1)";
    case VmOp::kMax: return "max(@0,@1)";
    case VmOp::kAtan2: return "atan2(@0,@1)";
    case VmOp::kPow: return "pow(@0,@1)";
    // Euclidean remainder from POV's fmod-like mod: r < 0 ? r + |b| : r.
    case VmOp::kMod: return "select(mod(@0,@1),mod(@0,@1)+abs(@1),mod(@0,@1))";
    case VmOp::kCompare: return "select(@0-@1,-1,0,1)";
    case VmOp::kAnd: return "select(-abs(@0),@1,0)";
    case VmOp::kOr: return "select(-abs(@0),@0,@1)";
    case VmOp::kConst:
    case VmOp::kVarX:
    case VmOp::kVarY:
    case VmOp::kVarZ: break;
  }
  return "";
}

struct TemplateShape {
  std::size_t fixedChars = 0;  // characters other than the @k markers
  int uses[2] = {0, 0};        // how often @0 / @1 appear
  int depth = 0;               // deepest parenthesis nesting
};

TemplateShape shapeOf(std::string_view t) {
  TemplateShape s;
  int open = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '@' && i + 1 < t.size()) {
      ++s.uses[t[i + 1] - '0'];
      ++i;
      continue;
    }
    ++s.fixedChars;
    if (t[i] == '(') s.depth = std::max(s.depth, ++open);
    if (t[i] == ')') --open;
  }
  return s;
}

bool isIdentifier(std::string_view s) {
  if (s.empty() || s.size() > 24) return false;
  const auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!alpha(s[0])) return false;
  return std::all_of(s.begin(), s.end(), [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}

std::size_t satAdd(std::size_t a, std::size_t b, std::size_t cap) { return a >= cap || b >= cap - a ? cap : a + b; }
std::size_t satMul(std::size_t a, std::size_t k, std::size_t cap) {
  return k == 0 ? 0 : (a >= cap / k ? cap : a * k);
}

using PovNode = VmProgram::Node;

// x, y, z or a number (negative ones in parentheses); an empty string for a non-finite constant.
std::string povLeafText(const PovNode& nd) {
  switch (nd.op) {
    case VmOp::kVarX: return "x";
    case VmOp::kVarY: return "y";
    case VmOp::kVarZ: return "z";
    default: break;
  }
  if (!std::isfinite(nd.imm)) return {};
  const std::string s = formatNumber(nd.imm);
  return std::signbit(nd.imm) ? "(" + s + ")" : s;
}

Status checkConstants(const std::vector<PovNode>& nodes, const std::string& where) {
  for (const PovNode& nd : nodes) {
    if (nd.op == VmOp::kConst && !std::isfinite(nd.imm)) {
      return fail(where + ": constant " + formatNumber(nd.imm) + " cannot be written for POV-Ray");
    }
  }
  return Ok{};
}

// One self-contained expression: every use repeats its operand's text. Sizes are computed first
// (saturating), so an exponential expansion is refused before anything is built.
Result<PovFunction> povInline(const std::vector<PovNode>& nodes, const PovOptions& o, const std::string& where) {
  const std::size_t m = nodes.size();
  const std::size_t root = m - 1;
  const std::size_t cap = o.maxChars + 1;
  std::vector<std::size_t> len(m, 0);
  std::vector<int> depth(m, 0);
  std::vector<std::uint32_t> uses(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const PovNode& nd = nodes[i];
    if (isLeaf(nd.op)) {
      len[i] = povLeafText(nd).size();
      continue;
    }
    const TemplateShape sh = shapeOf(povTemplate(nd.op));
    std::size_t l = satAdd(sh.fixedChars, satMul(len[nd.a], static_cast<std::size_t>(sh.uses[0]), cap), cap);
    int d = depth[nd.a];
    uses[nd.a] += static_cast<std::uint32_t>(sh.uses[0]);
    if (vmOpArity(nd.op) == 2) {
      l = satAdd(l, satMul(len[nd.b], static_cast<std::size_t>(sh.uses[1]), cap), cap);
      d = std::max(d, depth[nd.b]);
      uses[nd.b] += static_cast<std::uint32_t>(sh.uses[1]);
    }
    len[i] = l;
    depth[i] = d + sh.depth;
  }
  if (len[root] > o.maxChars) {
    return fail(where + ": the POV-Ray expression would exceed " + std::to_string(o.maxChars) +
                " characters (shared sub-expressions repeat without declarations)");
  }
  if (depth[root] > o.maxDepth) {
    return fail(where + ": the POV-Ray expression would nest " + std::to_string(depth[root]) +
                " levels deep, over the limit of " + std::to_string(o.maxDepth) + " (allow declarations)");
  }
  std::vector<std::string> text(m);
  for (std::size_t i = 0; i < m; ++i) {
    const PovNode& nd = nodes[i];
    if (isLeaf(nd.op)) {
      text[i] = povLeafText(nd);
      continue;
    }
    const std::string_view t = povTemplate(nd.op);
    const std::uint32_t operands[2] = {nd.a, nd.b};
    std::string s;
    s.reserve(len[i]);
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k] == '@' && k + 1 < t.size()) {
        const std::uint32_t j = operands[t[k + 1] - '0'];
        s += text[j];
        if (--uses[j] == 0) std::string().swap(text[j]);  // its last user has copied it
        ++k;
      } else {
        s += t[k];
      }
    }
    text[i] = std::move(s);
  }
  PovFunction out;
  out.expression = std::move(text[root]);
  out.callDepth = 1;  // the function the expression goes into
  return out;
}

// Text in the let-by-parameter scheme, with the bound values it refers to by parameter name.
struct PovText {
  std::string s;
  std::vector<std::uint32_t> free;  // bound nodes it names, ascending
  int nesting = 0;                  // parse nesting depth of s
  int calls = 0;                    // function-call depth POV-Ray needs to evaluate s
};

void addFree(std::vector<std::uint32_t>& into, std::uint32_t v) {
  const auto it = std::lower_bound(into.begin(), into.end(), v);
  if (it == into.end() || *it != v) into.insert(it, v);
}
void addFree(std::vector<std::uint32_t>& into, const std::vector<std::uint32_t>& from) {
  if (from.empty()) return;
  if (into.empty()) {
    into = from;
    return;
  }
  std::vector<std::uint32_t> merged;
  merged.reserve(into.size() + from.size());
  std::set_union(into.begin(), into.end(), from.begin(), from.end(), std::back_inserter(merged));
  into.swap(merged);
}

// Shared sub-expressions become function parameters: a value used more than once is bound at
// its immediate post-dominator p (the first node every path from it to the result passes), as
// p's text = P_k(x,y,z, ..., <the value's text>, ...) with P_k's body using the parameter. Its
// text sits inside every use's scope there, and each value is computed once per evaluation.
// Values bound at the same node that depend on each other get nested functions. Expressions
// nested deeper than maxDepth move into a function of their own (with their free parameters).
class PovLetWriter {
 public:
  PovLetWriter(const std::vector<PovNode>& nodes, const PovOptions& o, std::string where)
      : nodes_(nodes), o_(o), where_(std::move(where)) {}

  Result<PovFunction> write() {
    const std::size_t m = nodes_.size();
    const std::uint32_t root = static_cast<std::uint32_t>(m - 1);
    if (Status s = findPostDominators(); !s) return fail(s.error());
    std::vector<PovText> t(m);
    std::vector<char> bound(m, 0);
    std::vector<std::uint32_t> remaining = uses_;
    std::vector<std::uint32_t> seen(m, std::numeric_limits<std::uint32_t>::max());
    std::vector<std::int32_t> groupOf(m, -1);

    for (std::uint32_t v = 0; v < m; ++v) {
      const PovNode& nd = nodes_[v];
      if (isLeaf(nd.op)) {
        t[v].s = povLeafText(nd);
        continue;
      }
      // The node's own expression over its operands (inline texts or parameter names).
      PovText raw;
      const std::string_view tmpl = povTemplate(nd.op);
      const TemplateShape sh = shapeOf(tmpl);
      const std::uint32_t operands[2] = {nd.a, nd.b};
      int nest = 0;
      for (std::size_t k = 0; k < tmpl.size(); ++k) {
        if (!(tmpl[k] == '@' && k + 1 < tmpl.size())) {
          raw.s += tmpl[k];
          continue;
        }
        const std::uint32_t j = operands[tmpl[k + 1] - '0'];
        ++k;
        if (bound[j]) {
          raw.s += paramName(j);
          addFree(raw.free, j);
          continue;
        }
        raw.s += t[j].s;
        addFree(raw.free, t[j].free);
        nest = std::max(nest, t[j].nesting);
        raw.calls = std::max(raw.calls, t[j].calls);
        if (--remaining[j] == 0) t[j] = PovText{};  // its last user has copied it
      }
      raw.nesting = sh.depth + nest;

      // The bound values whose uses all meet here: from the references of this text, and
      // transitively of those values' own texts.
      std::vector<std::uint32_t> here;
      std::vector<std::uint32_t> todo;
      for (const std::uint32_t b : raw.free) {
        if (ipdom_[b] == v) todo.push_back(b);
      }
      while (!todo.empty()) {
        const std::uint32_t b = todo.back();
        todo.pop_back();
        if (seen[b] == v) continue;
        seen[b] = v;
        here.push_back(b);
        for (const std::uint32_t c : t[b].free) {
          if (ipdom_[c] == v && seen[c] != v) todo.push_back(c);
        }
      }
      if (here.empty()) {
        t[v] = std::move(raw);
      } else {
        Result<PovText> let = bindHere(std::move(raw), std::move(here), t, groupOf);
        if (!let) return fail(let.error());
        t[v] = std::move(*let);
      }

      if (t[v].nesting >= o_.maxDepth) {
        Result<PovText> cut = ownFunction(std::move(t[v]));
        if (!cut) return fail(cut.error());
        t[v] = std::move(*cut);
      }
      // Bind a shared value unless it is short and free of calls (then repeating it is cheaper).
      bound[v] = v != root && uses_[v] > 1 && (t[v].s.size() > kShareInlineChars || t[v].calls > 0);
      if (out_.declarations.size() + t[v].s.size() > o_.maxChars) return tooLong();
    }
    if (!t[root].free.empty()) return fail(where_ + ": internal error writing POV-Ray text (unbound value)");
    out_.expression = std::move(t[root].s);
    out_.callDepth = t[root].calls + 1;  // the function the expression goes into
    if (out_.callDepth > o_.maxCallDepth) {
      return fail(where_ + ": POV-Ray would nest function calls " + std::to_string(out_.callDepth) +
                  " deep, over the limit of " + std::to_string(o_.maxCallDepth));
    }
    if (out_.declarations.size() + out_.expression.size() > o_.maxChars) return tooLong();
    return std::move(out_);
  }

 private:
  static constexpr std::size_t kShareInlineChars = 24;
  static constexpr std::size_t kMaxParams = 56 - 3;  // POV-Ray's limit, less x, y, z

  Error tooLong() const {
    return fail(where_ + ": the POV-Ray function would exceed " + std::to_string(o_.maxChars) + " characters");
  }
  std::string paramName(std::uint32_t j) const { return o_.prefix + "_v" + std::to_string(j); }

  // Textual uses, users and immediate post-dominators (users come later in the order, so one
  // backward pass with the Cooper-Harvey-Kennedy intersection suffices).
  Status findPostDominators() {
    const std::size_t m = nodes_.size();
    const std::uint32_t root = static_cast<std::uint32_t>(m - 1);
    uses_.assign(m, 0);
    std::vector<std::uint32_t> start(m + 1, 0);
    for (const PovNode& nd : nodes_) {
      if (isLeaf(nd.op)) continue;
      const TemplateShape sh = shapeOf(povTemplate(nd.op));
      uses_[nd.a] += static_cast<std::uint32_t>(sh.uses[0]);
      ++start[nd.a + 1];
      if (vmOpArity(nd.op) == 2) {
        uses_[nd.b] += static_cast<std::uint32_t>(sh.uses[1]);
        if (nd.b != nd.a) ++start[nd.b + 1];
      }
    }
    for (std::size_t i = 0; i < m; ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> users(start[m]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t u = 0; u < m; ++u) {
      const PovNode& nd = nodes_[u];
      if (isLeaf(nd.op)) continue;
      users[fill[nd.a]++] = u;
      if (vmOpArity(nd.op) == 2 && nd.b != nd.a) users[fill[nd.b]++] = u;
    }
    ipdom_.assign(m, root);
    // A budget against quadratic walks on pathological graphs.
    std::size_t steps = 0;
    const std::size_t budget = 64 * m + 100'000'000;
    for (std::uint32_t v = root; v-- > 0;) {
      if (isLeaf(nodes_[v].op) || start[v] == start[v + 1]) continue;  // leaves are never bound
      std::uint32_t d = users[start[v]];
      for (std::uint32_t k = start[v] + 1; k < start[v + 1]; ++k) {
        std::uint32_t a = d, b = users[k];
        while (a != b) {
          while (a < b) a = ipdom_[a], ++steps;
          while (b < a) b = ipdom_[b], ++steps;
        }
        d = a;
        if (steps > budget) return fail(where_ + ": the model's sharing is too tangled to write for POV-Ray");
      }
      ipdom_[v] = d;
    }
    return Ok{};
  }

  // Declares a function of x, y, z and `params` with `body`; returns its name.
  std::string declare(const std::vector<std::uint32_t>& params, const std::string& body) {
    const std::string name = o_.prefix + "_" + std::to_string(++out_.declarationCount);
    out_.declarations += "#declare ";
    out_.declarations += name;
    out_.declarations += " = function(x,y,z";
    for (const std::uint32_t p : params) (out_.declarations += ',') += paramName(p);
    out_.declarations += "){ ";
    out_.declarations += body;
    out_.declarations += " }\n";
    return name;
  }

  Error tooManyParams(std::size_t n) const {
    return fail(where_ + ": writing for POV-Ray needs " + std::to_string(n) +
                " shared values at once; POV-Ray functions take at most " + std::to_string(kMaxParams) +
                " besides x, y, z");
  }

  // Binds `here` (ascending) around `raw`: groups of mutually independent values, each group one
  // function whose call passes the group's texts as arguments.
  Result<PovText> bindHere(PovText raw, std::vector<std::uint32_t> here, std::vector<PovText>& t,
                           std::vector<std::int32_t>& groupOf) {
    std::sort(here.begin(), here.end());
    std::vector<std::vector<std::uint32_t>> groups;
    for (const std::uint32_t b : here) {
      bool dependent = groups.empty();
      if (!dependent) {
        const std::int32_t current = static_cast<std::int32_t>(groups.size()) - 1;
        for (const std::uint32_t c : t[b].free) {
          if (groupOf[c] == current) dependent = true;
        }
      }
      if (dependent) groups.emplace_back();
      groups.back().push_back(b);
      groupOf[b] = static_cast<std::int32_t>(groups.size()) - 1;
    }
    PovText body = std::move(raw);
    for (std::size_t gi = groups.size(); gi-- > 0;) {
      const std::vector<std::uint32_t>& params = body.free;
      if (params.size() > kMaxParams) return tooManyParams(params.size());
      const std::string name = declare(params, body.s);
      PovText call;
      call.s = name + "(x,y,z";
      call.nesting = 1;
      call.calls = 1 + body.calls;
      for (const std::uint32_t p : params) {
        call.s += ',';
        if (groupOf[p] == static_cast<std::int32_t>(gi)) {
          call.s += t[p].s;
          addFree(call.free, t[p].free);
          call.nesting = std::max(call.nesting, 1 + t[p].nesting);
          call.calls = std::max(call.calls, t[p].calls);
        } else {
          call.s += paramName(p);
          addFree(call.free, p);
        }
      }
      call.s += ')';
      body = std::move(call);
    }
    for (const std::uint32_t b : here) {
      groupOf[b] = -1;
      t[b] = PovText{};  // consumed: computed once, here
    }
    return body;
  }

  // Moves a deeply nested text into a function of its own.
  Result<PovText> ownFunction(PovText text) {
    if (text.free.size() > kMaxParams) return tooManyParams(text.free.size());
    const std::string name = declare(text.free, text.s);
    PovText call;
    call.s = name + "(x,y,z";
    for (const std::uint32_t p : text.free) (call.s += ',') += paramName(p);
    call.s += ')';
    call.free = std::move(text.free);
    call.nesting = 1;
    call.calls = 1 + text.calls;
    return call;
  }

  const std::vector<PovNode>& nodes_;
  const PovOptions& o_;
  std::string where_;
  std::vector<std::uint32_t> uses_;
  std::vector<std::uint32_t> ipdom_;
  PovFunction out_;
};

}  // namespace

Result<PovFunction> VmProgram::povFunction(const PovOptions& options) const {
  if (nodes_.empty()) return fail("the model is empty");
  if (!isIdentifier(options.prefix)) {
    return fail("POV-Ray name prefix " + shown(options.prefix) +
                " is not an identifier (a letter or _, then letters, digits, _; at most 24)");
  }
  const std::string where = sourceName_.empty() ? std::string("the model") : "'" + sourceName_ + "'";
  if (Status s = checkConstants(nodes_, where); !s) return fail(s.error());
  PovOptions o = options;
  o.maxDepth = std::max(o.maxDepth, 4);
  if (!o.allowDeclarations) return povInline(nodes_, o, where);
  return PovLetWriter(nodes_, o, where).write();
}

// ---- bounds by interval subdivision

namespace {

struct Cell {
  double lo[3] = {0, 0, 0};
  double hi[3] = {0, 0, 0};
};

class BoundsSearch {
 public:
  BoundsSearch(const VmProgram& program, int dims) : program_(program), dims_(dims), scratch_(program.slotCount()) {}

  // Proven outside: the model (negative inside) is > 0 on the whole cell.
  bool provenOutside(const Cell& c) {
    ++evaluations_;
    const Interval z = dims_ == 3 ? Interval(c.lo[2], c.hi[2]) : Interval(0.0);
    const Interval v = program_.eval(Interval(c.lo[0], c.hi[0]), Interval(c.lo[1], c.hi[1]), z, scratch_);
    return v.lo > 0.0;
  }

  // The largest (upper) or smallest coordinate along `axis` of the part of `region` not proven
  // outside, to within about `tol`; nullopt when all of it is proven outside. Branch and bound:
  // the cell reaching furthest is refined first, so when the furthest one is small and unproven
  // everything beyond it has been proven outside. When the budget runs out the furthest open
  // cell's edge is returned (still conservative, only less tight).
  std::optional<double> extreme(const Cell& region, int axis, bool upper, double tol, std::size_t budget) {
    const auto key = [&](const Cell& c) { return upper ? c.hi[axis] : -c.lo[axis]; };
    const auto less = [&](const Cell& p, const Cell& q) { return key(p) < key(q); };
    std::priority_queue<Cell, std::vector<Cell>, decltype(less)> open(less);
    open.push(region);
    std::size_t spent = 0;
    while (!open.empty()) {
      const Cell c = open.top();
      if (spent++ >= budget) return upper ? c.hi[axis] : c.lo[axis];
      open.pop();
      if (provenOutside(c)) continue;
      int longest = 0;
      for (int k = 1; k < dims_; ++k) {
        if (c.hi[k] - c.lo[k] > c.hi[longest] - c.lo[longest]) longest = k;
      }
      if (c.hi[longest] - c.lo[longest] <= tol) return upper ? c.hi[axis] : c.lo[axis];
      const double mid = 0.5 * (c.lo[longest] + c.hi[longest]);
      Cell a = c, b = c;
      a.hi[longest] = mid;
      b.lo[longest] = mid;
      open.push(a);
      open.push(b);
    }
    return std::nullopt;
  }

  std::size_t evaluations() const { return evaluations_; }

 private:
  const VmProgram& program_;
  int dims_;
  std::vector<Interval> scratch_;
  std::size_t evaluations_ = 0;
};

}  // namespace

Result<Box3> vmModelBounds(const VmProgram& program, double halfWidth) {
  if (program.size() == 0) return fail("the model is empty");
  if (!(halfWidth > 0.0) || !std::isfinite(halfWidth)) return fail("the search box must have a positive size");
  const int dims = program.usesZ() ? 3 : 2;
  const std::string where = program.sourceName().empty() ? std::string("the model") : "'" + program.sourceName() + "'";
  BoundsSearch search(program, dims);
  // Cell evaluations per extreme and phase: bounds the time for huge or pathological models.
  constexpr std::size_t kBudget = 20000;

  Cell region;
  for (int k = 0; k < dims; ++k) region.lo[k] = -halfWidth, region.hi[k] = halfWidth;
  // Phase 1 finds a coarse box in the whole search box; phase 2 refines inside it to a tolerance
  // relative to the model's own size.
  double tol = 2.0 * halfWidth / 4096.0;
  for (int phase = 0; phase < 2; ++phase) {
    Cell next = region;
    for (int k = 0; k < dims; ++k) {
      for (const bool upper : {false, true}) {
        const std::optional<double> e = search.extreme(region, k, upper, tol, kBudget);
        if (!e) {
          return fail(where + ": the model has no inside (it is positive everywhere within +-" +
                      formatNumber(halfWidth) + " units)");
        }
        (upper ? next.hi[k] : next.lo[k]) = *e;
        if (phase == 0 && (upper ? *e >= halfWidth : *e <= -halfWidth)) {
          return fail(where + ": the model's inside reaches the edge of the +-" + formatNumber(halfWidth) +
                      "-unit search box: it is unbounded or too large (check its sign: negative is inside)");
        }
      }
    }
    region = next;
    double extent = 0.0;
    for (int k = 0; k < dims; ++k) extent = std::max(extent, region.hi[k] - region.lo[k]);
    tol = std::max(extent * 1e-3, halfWidth * 1e-12);
  }
  // A margin of the final tolerance so surfaces never touch the box.
  Box3 box;
  box.x0 = region.lo[0] - tol, box.x1 = region.hi[0] + tol;
  box.y0 = region.lo[1] - tol, box.y1 = region.hi[1] + tol;
  if (dims == 3) box.z0 = region.lo[2] - tol, box.z1 = region.hi[2] + tol;
  return box;
}

// ---- the workpiece

VmWorkpiece::VmWorkpiece(VmProgram program, std::string file, double scale, double d)
    : program_(std::move(program)), file_(std::move(file)), scale_(scale), invScale_(1.0 / scale), d_(d) {}

Result<std::shared_ptr<VmWorkpiece>> VmWorkpiece::open(const std::filesystem::path& file, std::string fileAsWritten,
                                                       double scale, double d) {
  Result<VmProgram> program = VmProgram::load(file);
  if (!program) {
    // Name the file as the scene wrote it, not as it was resolved.
    const std::string resolved = file.string();
    std::string message = program.error();
    if (!fileAsWritten.empty() && message.rfind(resolved, 0) == 0 && message.size() > resolved.size() &&
        message[resolved.size()] == ':') {
      message = fileAsWritten + message.substr(resolved.size());
    }
    return fail(message);
  }
  return create(std::move(*program), std::move(fileAsWritten), scale, d);
}

Result<std::shared_ptr<VmWorkpiece>> VmWorkpiece::create(VmProgram program, std::string fileAsWritten, double scale,
                                                         double d) {
  const std::string what = fileAsWritten.empty() ? std::string("vm model") : "vm model '" + fileAsWritten + "'";
  if (!(scale > 0.0) || !std::isfinite(scale)) return fail(what + ": scale must be a positive number of mm per unit");
  if (!(d > 0.0) || !std::isfinite(d)) return fail(what + ": half thickness d must be a positive number of mm");
  Result<Box3> model = vmModelBounds(program);
  if (!model) return fail(model.error());
  std::shared_ptr<VmWorkpiece> w(new VmWorkpiece(std::move(program), std::move(fileAsWritten), scale, d));
  Box3 b = *model;
  b.x0 *= scale, b.x1 *= scale, b.y0 *= scale, b.y1 *= scale;
  if (w->program_.usesZ()) {
    b.z0 *= scale, b.z1 *= scale;
  } else {
    b.z0 = -d, b.z1 = d;
  }
  w->bounds_ = b;
  return w;
}

template <class T>
T VmWorkpiece::valueT(const P3<T>& p) const {
  const T s(invScale_);
  const T m = -program_.eval(p.x * s, p.y * s, p.z * s) * T(scale_);
  if (program_.usesZ()) return m;
  return min(m, T(d_) - abs(p.z));
}

double VmWorkpiece::value(const P3<double>& p) const { return valueT(p); }
Grad VmWorkpiece::value(const P3<Grad>& p) const { return valueT(p); }
Interval VmWorkpiece::value(const P3<Interval>& p) const { return valueT(p); }

nlohmann::json VmWorkpiece::toJson() const {
  return nlohmann::json{{"type", "vm"}, {"file", file_}, {"scale", scale_}, {"d", d_}};
}

}  // namespace emboss

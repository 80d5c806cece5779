// Generator of large synthetic vm-format models (medallion outlines) for stress tests and benchmarks.
#include "frep/vm_generate.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string_view>
#include <vector>

namespace emboss {

namespace {

// Appends clauses with fresh IDs (_0, _1, ... in hex, as Fidget writes them).
class VmWriter {
 public:
  std::string emit(std::string_view op, std::string_view a = {}, std::string_view b = {}) {
    std::string id = "_";
    char buf[24];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, lines_, 16);
    id.append(buf, end);
    text_ += id;
    text_ += ' ';
    text_ += op;
    if (!a.empty()) (text_ += ' ') += a;
    if (!b.empty()) (text_ += ' ') += b;
    text_ += '\n';
    ++lines_;
    return id;
  }
  std::string constant(double v) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return emit("const", std::string_view(buf, static_cast<std::size_t>(end - buf)));
  }
  int lines() const { return static_cast<int>(lines_); }
  std::string& text() { return text_; }

 private:
  std::string text_;
  unsigned long lines_ = 0;
};

// Uniform in [lo, hi) from the raw engine output (std distributions differ between libraries),
// rounded to 4 decimals so the text stays readable.
class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) {
    const double u = static_cast<double>(engine_() >> 5) * (1.0 / 134217728.0);
    return std::round((lo + (hi - lo) * u) * 1e4) / 1e4;
  }
  bool chance(double p) { return static_cast<double>(engine_() >> 5) * (1.0 / 134217728.0) < p; }
  unsigned below(unsigned n) { return static_cast<unsigned>(engine_() % n); }

 private:
  std::mt19937 engine_;
};

struct Frame {
  std::string u, v;
};

}  // namespace

std::string generateVmRelief(int clauses, unsigned seed) {
  VmWriter w;
  Random rnd(seed);
  w.text() = "# Generated medallion outline: ~" + std::to_string(clauses) + " clauses, seed " + std::to_string(seed) +
             " (negative inside)\n";

  const std::string x = w.emit("var-x");
  const std::string y = w.emit("var-y");
  const std::string zero = w.constant(0.0);
  std::vector<Frame> frames{{x, y}};

  // Every emit and random draw is its own statement: argument evaluation order is unspecified,
  // and the text must not depend on the compiler.
  const auto circle = [&](const Frame& f, double cx, double cy, double r) {
    const std::string ccx = w.constant(cx);
    const std::string dx = w.emit("sub", f.u, ccx);
    const std::string ccy = w.constant(cy);
    const std::string dy = w.emit("sub", f.v, ccy);
    const std::string dx2 = w.emit("square", dx);
    const std::string dy2 = w.emit("square", dy);
    const std::string len = w.emit("sqrt", w.emit("add", dx2, dy2));
    const std::string cr = w.constant(r);
    return w.emit("sub", len, cr);
  };
  const auto roundedBox = [&](const Frame& f, double cx, double cy, double hx, double hy, double r) {
    const std::string ccx = w.constant(cx);
    const std::string ax = w.emit("abs", w.emit("sub", f.u, ccx));
    const std::string chx = w.constant(hx);
    const std::string qx = w.emit("sub", ax, chx);
    const std::string ccy = w.constant(cy);
    const std::string ay = w.emit("abs", w.emit("sub", f.v, ccy));
    const std::string chy = w.constant(hy);
    const std::string qy = w.emit("sub", ay, chy);
    const std::string mx = w.emit("max", qx, zero);
    const std::string my = w.emit("max", qy, zero);
    const std::string mx2 = w.emit("square", mx);
    const std::string my2 = w.emit("square", my);
    const std::string outside = w.emit("sqrt", w.emit("add", mx2, my2));
    const std::string inside = w.emit("min", w.emit("max", qx, qy), zero);
    const std::string sum = w.emit("add", outside, inside);
    const std::string cr = w.constant(r);
    return w.emit("sub", sum, cr);
  };
  // Polynomial smooth minimum: min(a, b) - h^2 / (4k), h = max(k - |a - b|, 0).
  const auto smoothUnion = [&](const std::string& a, const std::string& b, double k) {
    const std::string ad = w.emit("abs", w.emit("sub", a, b));
    const std::string ck = w.constant(k);
    const std::string h = w.emit("max", w.emit("sub", ck, ad), zero);
    const std::string h2 = w.emit("square", h);
    const std::string c4 = w.constant(0.25 / k);
    const std::string corr = w.emit("mul", h2, c4);
    const std::string m = w.emit("min", a, b);
    return w.emit("sub", m, corr);
  };
  std::string mirrorU;  // the ID of |x| once the mirror frame exists
  const auto pickFrame = [&]() -> Frame {
    if (mirrorU.empty() && rnd.chance(0.3)) {
      mirrorU = w.emit("abs", x);
      frames.push_back({mirrorU, y});
    } else if (frames.size() < 8 && rnd.chance(0.15)) {
      const double a = rnd.uniform(0.0, std::numbers::pi);
      const std::string c = w.constant(std::cos(a));
      const std::string s = w.constant(std::sin(a));
      const std::string xc = w.emit("mul", x, c);
      const std::string ys = w.emit("mul", y, s);
      const std::string u = w.emit("sub", xc, ys);
      const std::string xs = w.emit("mul", x, s);
      const std::string yc = w.emit("mul", y, c);
      const std::string v = w.emit("add", xs, yc);
      frames.push_back({u, v});
    }
    return frames[rnd.below(static_cast<unsigned>(frames.size()))];
  };

  // Central disc, then blended primitives and a few holes until the budget is used up.
  const double r0 = rnd.uniform(0.35, 0.5);
  std::string acc = circle(frames[0], 0.0, 0.0, r0);
  constexpr int kLargestStep = 22 + 10 + 8;  // rounded box + smooth union + a new rotated frame
  while (w.lines() + kLargestStep <= clauses) {
    if (rnd.chance(0.1)) {
      const double a = rnd.uniform(0.0, 2.0 * std::numbers::pi);
      const double r = rnd.uniform(0.1, 0.6);
      const double rh = rnd.uniform(0.02, 0.06);
      const std::string hole = circle(frames[0], r * std::cos(a), r * std::sin(a), rh);
      acc = w.emit("max", acc, w.emit("neg", hole));
      continue;
    }
    const Frame f = pickFrame();
    const double a = rnd.uniform(0.0, 2.0 * std::numbers::pi);
    const double r = rnd.uniform(0.1, 0.7);
    double cx = r * std::cos(a);
    const double cy = r * std::sin(a);
    if (f.u == mirrorU) cx = std::fabs(cx);  // u = |x| >= 0: keep the primitive where it shows
    std::string prim;
    if (rnd.chance(0.5)) {
      const double rc = rnd.uniform(0.04, 0.18);
      prim = circle(f, cx, cy, rc);
    } else {
      const double hx = rnd.uniform(0.03, 0.15);
      const double hy = rnd.uniform(0.03, 0.15);
      const double rr = rnd.uniform(0.005, 0.04);
      prim = roundedBox(f, cx, cy, hx, hy, rr);
    }
    const double k = rnd.uniform(0.02, 0.08);
    acc = smoothUnion(acc, prim, k);
  }
  return std::move(w.text());
}

}  // namespace emboss

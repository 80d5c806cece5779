// Tests of the vm-format importer: values, gradients, interval bounds, plates, errors, size, POV-Ray.
#include "frep/vm_model.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <time.h>
#include <unordered_map>
#include <vector>

#include "frep/vm_generate.h"
#include "test_support.h"

namespace emboss {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

VmProgram parseOk(std::string_view text, std::string_view name = "test.vm") {
  Result<VmProgram> p = VmProgram::parse(text, name);
  EXPECT_TRUE(p.ok()) << p.error();
  if (!p) return VmProgram{};
  return std::move(*p);
}

std::string parseError(std::string_view text, std::string_view name = "") {
  Result<VmProgram> p = VmProgram::parse(text, name);
  EXPECT_FALSE(p.ok()) << "parsed unexpectedly: " << text;
  return p.ok() ? std::string() : p.error();
}

// Distance to the unit circle (2D) and the unit sphere (3D): negative inside.
constexpr std::string_view kUnitDisc = "x var-x\ny var-y\nx2 square x\ny2 square y\ns add x2 y2\nr sqrt s\n"
                                       "one const 1\nout sub r one\n";
constexpr std::string_view kUnitBall = "x var-x\ny var-y\nz var-z\nx2 square x\ny2 square y\nz2 square z\n"
                                       "s add x2 y2\nt add s z2\nr sqrt t\none const 1\nout sub r one\n";

// Smooth in x, y, z over [-1, 1]^3: every differentiable opcode, for gradient checks.
constexpr std::string_view kSmoothModel = R"(# every smooth opcode
x var-x
y var-y
z var-z
half const 0.5
two const 2
s sin x
c cos y
hx mul x half
t tan hx
as asin hx
ac acos hx
at atan y
e exp z
r add two s        # in [1, 3]
l ln r
q sqrt r
rc recip r
p pow r hx
a2 atan2 y two
sq square c
ng neg at
dv div q r
m1 mul t as
s1 add m1 ac
s2 sub s1 e
s3 add s2 l
s4 mul s3 q
s5 add s4 rc
s6 sub s5 p
s7 add s6 a2
s8 add s7 sq
s9 add s8 ng
out add s9 dv
)";

// Every opcode, including the discontinuous ones; finite over [-1, 1]^3 (except where noted).
constexpr std::string_view kAllOpsModel = R"(
x var-x
y var-y
z var-z
half const 0.5
two const 2
s sin x
c cos y
hx mul x half
t tan hx
as asin hx
ac acos hx
at atan y
e exp z
r add two s
l ln r
q sqrt r
rc recip r
p pow r hx
a2 atan2 y x
ab abs z
ng neg ab
sq square c
fl floor x
ce ceil y
ro round z
md mod x half
mn mod y z           # NaN when z = 0 only
cm compare x y
an and cm y
o1 or md z
nt not cm
mi min fl ce
ma max ro md
v1 add t as
v2 add v1 ac
v3 add v2 at
v4 add v3 e
v5 add v4 l
v6 add v5 q
v7 add v6 rc
v8 add v7 p
v9 add v8 a2
w1 add v9 ng
w2 add w1 sq
w3 add w2 mi
w4 add w3 ma
w5 add w4 an
w6 add w5 o1
w7 add w6 nt
w8 div w7 r
w9 sub w8 mn
out mul w9 half
)";

// ---- a reference evaluator: its own parser and a recursive, memoised evaluation, written
// independently of the importer (only for modest depths).

class ReferenceModel {
 public:
  explicit ReferenceModel(std::string_view text) {
    std::istringstream in{std::string(text)};
    std::string line;
    while (std::getline(in, line)) {
      if (const auto h = line.find('#'); h != std::string::npos) line.resize(h);
      std::istringstream ls(line);
      std::string id, op;
      if (!(ls >> id >> op)) continue;
      Node n;
      n.op = op;
      std::string arg;
      if (op == "const") {
        ls >> n.value;
      } else {
        while (ls >> arg) n.args.push_back(index_.at(arg));
      }
      index_[id] = static_cast<int>(nodes_.size());
      nodes_.push_back(n);
    }
  }
  double eval(double x, double y, double z) const {
    std::vector<double> memo(nodes_.size());
    std::vector<char> done(nodes_.size(), 0);
    const std::function<double(int)> at = [&](int i) -> double {
      if (done[i]) return memo[i];
      const Node& n = nodes_[i];
      const double a = n.args.size() > 0 ? at(n.args[0]) : 0.0;
      const double b = n.args.size() > 1 ? at(n.args[1]) : 0.0;
      double v = kNaN;
      const std::string& o = n.op;
      if (o == "const") v = n.value;
      else if (o == "var-x") v = x;
      else if (o == "var-y") v = y;
      else if (o == "var-z") v = z;
      else if (o == "neg") v = -a;
      else if (o == "abs") v = std::fabs(a);
      else if (o == "recip") v = 1.0 / a;
      else if (o == "sqrt") v = std::sqrt(a);
      else if (o == "square") v = a * a;
      else if (o == "add") v = a + b;
      else if (o == "sub") v = a - b;
      else if (o == "mul") v = a * b;
      else if (o == "div") v = a / b;
      else if (o == "min") v = std::isnan(a) || std::isnan(b) ? kNaN : (a < b ? a : b);
      else if (o == "max") v = std::isnan(a) || std::isnan(b) ? kNaN : (a > b ? a : b);
      memo[i] = v;
      done[i] = 1;
      return v;
    };
    return at(static_cast<int>(nodes_.size()) - 1);
  }

 private:
  struct Node {
    std::string op;
    std::vector<int> args;
    double value = 0.0;
  };
  std::vector<Node> nodes_;
  std::unordered_map<std::string, int> index_;
};

// ---- a small evaluator of the POV-Ray function text povFunction writes, to check it computes
// the same values with work linear in the model. Each function body compiles once to postfix
// code; calls recurse only as deep as POV-Ray's own calls would.

class PovEvaluator {
 public:
  explicit PovEvaluator(const PovFunction& f) {
    std::istringstream in(f.declarations);
    std::string line;
    const std::string head = "#declare ", mid = " = function(", open = "){ ";
    while (std::getline(in, line) && error.empty()) {
      const auto m = line.find(mid);
      const auto o = line.find(open);
      if (line.rfind(head, 0) != 0 || m == std::string::npos || o == std::string::npos || line.size() < 2 ||
          line.substr(line.size() - 2) != " }") {
        error = "bad declaration line: " + line.substr(0, 80);
        return;
      }
      Function fn;
      std::stringstream ps(line.substr(m + mid.size(), o - m - mid.size()));
      for (std::string p; std::getline(ps, p, ',');) fn.params.push_back(p);
      compile(fn, line.substr(o + open.size(), line.size() - 2 - o - open.size()));
      fnIndex_[line.substr(head.size(), m - head.size())] = static_cast<int>(fns_.size());
      fns_.push_back(std::move(fn));
    }
    top_.params = {"x", "y", "z"};
    if (error.empty()) compile(top_, f.expression);
  }
  double eval(double x, double y, double z) {
    ops = 0;
    deepest = 0;
    if (!error.empty()) return kNaN;
    const double args[3] = {x, y, z};
    return run(top_, args, 1);
  }
  std::string error;
  long ops = 0;      // operations executed by the last eval
  int deepest = 0;   // deepest call nesting of the last eval

 private:
  enum class Kind { kNum, kParam, kNeg, kAdd, kSub, kMul, kDiv, kBuiltin, kCall };
  struct Op {
    Kind kind;
    double num = 0.0;
    int index = 0;  // parameter, builtin or function
    int argc = 0;
  };
  struct Function {
    std::vector<std::string> params;
    std::vector<Op> code;
  };
  static const std::vector<std::string>& builtins() {
    static const std::vector<std::string> names = {"abs", "sqrt", "sin",  "cos", "tan", "asin",  "acos",
                                                   "atan", "exp", "ln",   "floor", "ceil", "pow", "min",
                                                   "max",  "atan2", "mod", "select"};
    return names;
  }

  void compile(Function& fn, const std::string& text) {
    s_ = text;
    p_ = 0;
    fn_ = &fn;
    expr();
    if (p_ != s_.size() && error.empty()) error = "trailing text at " + std::to_string(p_) + ": " + s_.substr(p_, 40);
  }
  void emit(Kind k, double num = 0.0, int index = 0, int argc = 0) { fn_->code.push_back(Op{k, num, index, argc}); }
  bool eat(char c) {
    if (p_ < s_.size() && s_[p_] == c) return ++p_, true;
    return false;
  }
  void expect(char c) {
    if (!eat(c) && error.empty()) error = std::string("expected '") + c + "' at " + std::to_string(p_) + ": " + s_.substr(p_, 40);
  }
  void expr() {
    term();
    for (;;) {
      if (eat('+')) term(), emit(Kind::kAdd);
      else if (eat('-')) term(), emit(Kind::kSub);
      else return;
    }
  }
  void term() {
    unary();
    for (;;) {
      if (eat('*')) unary(), emit(Kind::kMul);
      else if (eat('/')) unary(), emit(Kind::kDiv);
      else return;
    }
  }
  void unary() {
    if (eat('-')) {
      unary();
      emit(Kind::kNeg);
      return;
    }
    primary();
  }
  void primary() {
    if (eat('(')) {
      expr();
      expect(')');
      return;
    }
    const std::size_t start = p_;
    if (p_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[p_])) || s_[p_] == '.')) {
      while (p_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[p_])) || s_[p_] == '.' ||
                                ((s_[p_] == '-' || s_[p_] == '+') && (s_[p_ - 1] == 'e' || s_[p_ - 1] == 'E')))) {
        ++p_;
      }
      emit(Kind::kNum, std::stod(s_.substr(start, p_ - start)));
      return;
    }
    while (p_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[p_])) || s_[p_] == '_')) ++p_;
    const std::string name = s_.substr(start, p_ - start);
    if (name.empty()) {
      if (error.empty()) error = "unexpected text at " + std::to_string(p_) + ": " + s_.substr(p_, 40);
      ++p_;
      return;
    }
    const auto param = std::find(fn_->params.begin(), fn_->params.end(), name);
    if (param != fn_->params.end()) {
      emit(Kind::kParam, 0.0, static_cast<int>(param - fn_->params.begin()));
      return;
    }
    expect('(');
    int argc = 0;
    if (!eat(')')) {
      do {
        expr();
        ++argc;
      } while (eat(',') && error.empty());
      expect(')');
    }
    if (const auto it = fnIndex_.find(name); it != fnIndex_.end()) {
      if (argc != static_cast<int>(fns_[it->second].params.size()) && error.empty()) error = name + ": wrong argc";
      emit(Kind::kCall, 0.0, it->second, argc);
      return;
    }
    const auto b = std::find(builtins().begin(), builtins().end(), name);
    if (b == builtins().end()) {
      if (error.empty()) error = "unknown function " + name;
      return;
    }
    emit(Kind::kBuiltin, 0.0, static_cast<int>(b - builtins().begin()), argc);
  }

  double run(const Function& fn, const double* args, int depth) {
    deepest = std::max(deepest, depth);
    std::vector<double> st;
    st.reserve(16);
    const auto pop = [&] {
      const double v = st.back();
      st.pop_back();
      return v;
    };
    for (const Op& op : fn.code) {
      ++ops;
      switch (op.kind) {
        case Kind::kNum: st.push_back(op.num); break;
        case Kind::kParam: st.push_back(args[op.index]); break;
        case Kind::kNeg: st.back() = -st.back(); break;
        case Kind::kAdd: { const double b = pop(); st.back() += b; break; }
        case Kind::kSub: { const double b = pop(); st.back() -= b; break; }
        case Kind::kMul: { const double b = pop(); st.back() *= b; break; }
        case Kind::kDiv: { const double b = pop(); st.back() /= b; break; }
        case Kind::kCall: {
          std::vector<double> a(st.end() - op.argc, st.end());
          st.resize(st.size() - static_cast<std::size_t>(op.argc));
          st.push_back(run(fns_[static_cast<std::size_t>(op.index)], a.data(), depth + 1));
          break;
        }
        case Kind::kBuiltin: {
          std::vector<double> a(st.end() - op.argc, st.end());
          st.resize(st.size() - static_cast<std::size_t>(op.argc));
          a.resize(4, 0.0);
          const std::string& n = builtins()[static_cast<std::size_t>(op.index)];
          double v = kNaN;
          if (n == "abs") v = std::fabs(a[0]);
          else if (n == "sqrt") v = std::sqrt(a[0]);
          else if (n == "sin") v = std::sin(a[0]);
          else if (n == "cos") v = std::cos(a[0]);
          else if (n == "tan") v = std::tan(a[0]);
          else if (n == "asin") v = std::asin(a[0]);
          else if (n == "acos") v = std::acos(a[0]);
          else if (n == "atan") v = std::atan(a[0]);
          else if (n == "exp") v = std::exp(a[0]);
          else if (n == "ln") v = std::log(a[0]);
          else if (n == "floor") v = std::floor(a[0]);
          else if (n == "ceil") v = std::ceil(a[0]);
          else if (n == "pow") v = std::pow(a[0], a[1]);
          else if (n == "min") v = std::min(a[0], a[1]);
          else if (n == "max") v = std::max(a[0], a[1]);
          else if (n == "atan2") v = std::atan2(a[0], a[1]);
          else if (n == "mod") v = std::fmod(a[0], a[1]);
          else if (n == "select") v = op.argc == 3 ? (a[0] < 0 ? a[1] : a[2]) : (a[0] < 0 ? a[1] : a[0] == 0 ? a[2] : a[3]);
          st.push_back(v);
          break;
        }
      }
    }
    return st.empty() ? kNaN : st.back();
  }

  std::vector<Function> fns_;
  std::unordered_map<std::string, int> fnIndex_;
  Function top_;
  std::string s_;
  std::size_t p_ = 0;
  Function* fn_ = nullptr;
};

bool closeEnough(double a, double b, double rel) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::fabs(a - b) <= rel * (1.0 + std::fabs(a) + std::fabs(b));
}

std::string chainText(int n) {
  std::string t = "c const 0.5\nn0 var-x\n";
  t.reserve(static_cast<std::size_t>(n) * 24);
  for (int i = 1; i <= n; ++i) t += "n" + std::to_string(i) + " add n" + std::to_string(i - 1) + " c\n";
  return t;
}

// ---- values

TEST(VmModel, QuarterValuesAtHandComputedPoints) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  Result<VmProgram> p = VmProgram::load(dir / "vm" / "quarter.vm");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_FALSE(p->usesZ());
  // out = max(max(x, y), x^2 + y^2 - 0.5)
  EXPECT_NEAR(p->eval(-0.3, -0.3, 0.0), -0.3, 1e-15);  // max(-0.3, 0.18 - 0.5)
  EXPECT_NEAR(p->eval(0.5, -0.2, 0.0), 0.5, 1e-15);
  EXPECT_NEAR(p->eval(-0.6, -0.6, 7.0), 0.22, 1e-15);  // outside the circle; z is ignored
  EXPECT_NEAR(p->eval(-0.1, -0.5, 0.0), -0.1, 1e-15);  // max(-0.1, 0.26 - 0.5)

  // The workpiece flips the sign (f >= 0 inside); scale 1, a thick plate so the outline decides.
  auto w = VmWorkpiece::open(dir / "vm" / "quarter.vm", "vm/quarter.vm", 1.0, 10.0);
  ASSERT_TRUE(w.ok()) << w.error();
  EXPECT_NEAR((*w)->value(P3<double>{-0.3, -0.3, 0.0}), 0.3, 1e-15);
  EXPECT_NEAR((*w)->value(P3<double>{0.5, -0.2, 0.0}), -0.5, 1e-15);
  EXPECT_NEAR((*w)->value(P3<double>{-0.6, -0.6, 0.0}), -0.22, 1e-15);
}

TEST(VmModel, TanglecubeValuesAtHandComputedPoints) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  Result<VmProgram> p = VmProgram::load(dir / "vm" / "tanglecube.vm");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_TRUE(p->usesZ());
  // x^4 - 5x^2 + y^4 - 5y^2 + z^4 - 5z^2 + 10
  EXPECT_DOUBLE_EQ(p->eval(0, 0, 0), 10.0);
  EXPECT_DOUBLE_EQ(p->eval(1, 1, 1), -2.0);
  EXPECT_DOUBLE_EQ(p->eval(2, 0, 0), 6.0);
  EXPECT_DOUBLE_EQ(p->eval(0, -2, 1), 2.0);  // 16 - 20 + 1 - 5 + 10
  const double x = 1.5, y = 0.5, z = -0.25;
  const auto g = [](double t) { return t * t * t * t - 5 * t * t; };
  EXPECT_NEAR(p->eval(x, y, z), g(x) + g(y) + g(z) + 10.0, 1e-12);

  auto w = VmWorkpiece::open(dir / "vm" / "tanglecube.vm", "tanglecube.vm", 1.0, 0.5);
  ASSERT_TRUE(w.ok()) << w.error();
  EXPECT_FALSE((*w)->isPlate());
  EXPECT_DOUBLE_EQ((*w)->value(P3<double>{1, 1, 1}), 2.0);
  EXPECT_DOUBLE_EQ((*w)->value(P3<double>{0, 0, 0}), -10.0);
}

TEST(VmModel, HiParsesAsAPlanarModel) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  Result<VmProgram> p = VmProgram::load(dir / "vm" / "hi.vm");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_FALSE(p->usesZ());
  EXPECT_GT(p->size(), 10u);
  // The letters are in the upper-right quadrant.
  Result<Box3> b = vmModelBounds(*p);
  ASSERT_TRUE(b.ok()) << b.error();
  EXPECT_GE(b->x0, -0.01);
  EXPECT_GE(b->y0, -0.01);
  EXPECT_LE(b->x1, 1.5);
  EXPECT_LE(b->y1, 1.5);
}

TEST(VmModel, EveryOpcodeFollowsFidgetSemantics) {
  struct Case {
    std::string op;
    double a, b, expected;
  };
  const double pi = std::numbers::pi;
  const std::vector<Case> cases = {
      {"neg", 2, 0, -2},          {"abs", -3, 0, 3},          {"recip", 4, 0, 0.25},
      {"sqrt", 9, 0, 3},          {"square", -3, 0, 9},       {"floor", -1.5, 0, -2},
      {"ceil", -1.5, 0, -1},      {"round", 2.5, 0, 3},       {"round", -2.5, 0, -3},
      {"sin", pi / 2, 0, 1},      {"cos", 0, 0, 1},           {"tan", pi / 4, 0, 1},
      {"asin", 1, 0, pi / 2},     {"acos", 1, 0, 0},          {"atan", 1, 0, pi / 4},
      {"exp", 0, 0, 1},           {"ln", std::exp(2.0), 0, 2}, {"not", 0, 0, 1},
      {"not", -3, 0, 0},          {"add", 2, 3, 5},           {"sub", 2, 3, -1},
      {"mul", 2, 3, 6},           {"div", 3, 2, 1.5},         {"min", 2, 3, 2},
      {"max", 2, 3, 3},           {"atan2", 1, -1, 3 * pi / 4}, {"pow", 2, 10, 1024},
      {"mod", -1, 3, 2},          {"mod", 7, -3, 1},          {"mod", 7.5, 2, 1.5},
      {"compare", 1, 2, -1},      {"compare", 2, 2, 0},       {"compare", 3, 2, 1},
      {"compare", kNaN, 2, kNaN}, {"and", 0, 5, 0},           {"and", 2, 5, 5},
      {"or", 0, 5, 5},            {"or", 2, 5, 2},            {"min", kNaN, 1, kNaN},
      {"max", 1, kNaN, kNaN},     {"log", 1, 0, 0},
  };
  for (const Case& c : cases) {
    const bool binary = c.op == "add" || c.op == "sub" || c.op == "mul" || c.op == "div" || c.op == "min" ||
                         c.op == "max" || c.op == "atan2" || c.op == "pow" || c.op == "mod" || c.op == "compare" ||
                         c.op == "and" || c.op == "or";
    const std::string args = binary ? " a b" : " a";
    // Evaluated by the interpreter (operands are variables) ...
    const VmProgram viaVars = parseOk("a var-x\nb var-y\nr " + c.op + args + "\n");
    const double v = viaVars.eval(c.a, c.b, 0.0);
    EXPECT_TRUE(closeEnough(v, c.expected, 1e-15)) << c.op << "(" << c.a << ", " << c.b << ") = " << v;
    // ... Grad gives the very same value ...
    const Grad g = viaVars.eval(Grad(c.a, 1, 0, 0), Grad(c.b, 0, 1, 0), Grad(0.0));
    EXPECT_TRUE(closeEnough(g.v, v, 0.0)) << c.op << ": grad value " << g.v << " vs " << v;
    // ... the degenerate interval contains it ...
    const Interval iv = viaVars.eval(Interval(c.a), Interval(c.b), Interval(0.0));
    if (!std::isnan(v)) {
      EXPECT_TRUE(iv.lo <= v && v <= iv.hi) << c.op << ": [" << iv.lo << ", " << iv.hi << "]";
    }
    // ... and constant folding agrees (where the inputs are finite constants).
    if (std::isfinite(c.a) && std::isfinite(c.b)) {
      char text[200];
      std::snprintf(text, sizeof text, "a const %.17g\nb const %.17g\nx var-x\nr %s%s\nout add r x\n", c.a, c.b,
                    c.op.c_str(), args.c_str());
      const VmProgram folded = parseOk(text);
      EXPECT_TRUE(closeEnough(folded.eval(0.0, 0.0, 0.0), v, 0.0)) << c.op << " folded";
      if (std::isfinite(v)) {
        EXPECT_EQ(folded.size(), 3u) << c.op << ": the constant part should fold";
      }
    }
  }
}

TEST(VmModel, OpcodeNamesRoundTrip) {
  for (int i = 0; i <= static_cast<int>(VmOp::kOr); ++i) {
    const VmOp op = static_cast<VmOp>(i);
    EXPECT_FALSE(vmOpName(op).empty());
    if (op == VmOp::kConst) continue;
    std::string text = "x var-x\ny var-y\nr " + std::string(vmOpName(op));
    for (int k = 0; k < vmOpArity(op); ++k) text += k == 0 ? " x" : " y";
    EXPECT_TRUE(VmProgram::parse(text, "").ok()) << text;
  }
}

// ---- gradients and intervals

TEST(VmModel, GradientEqualsCentralDifference) {
  std::vector<std::pair<std::string, VmProgram>> models;
  models.emplace_back("smooth", parseOk(kSmoothModel));
  models.emplace_back("disc", parseOk(kUnitDisc));
  models.emplace_back("ball", parseOk(kUnitBall));
  if (auto dir = test::fixturesDir()) {
    if (auto t = VmProgram::load(*dir / "vm" / "tanglecube.vm")) models.emplace_back("tanglecube", std::move(*t));
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  const double h = 1e-6;
  for (const auto& [name, p] : models) {
    for (int i = 0; i < 200; ++i) {
      const double x = u(rng), y = u(rng), z = u(rng);
      const Grad g = p.eval(Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, 1));
      const double v = p.eval(x, y, z);
      ASSERT_EQ(g.v, v) << name;
      const double dx = (p.eval(x + h, y, z) - p.eval(x - h, y, z)) / (2 * h);
      const double dy = (p.eval(x, y + h, z) - p.eval(x, y - h, z)) / (2 * h);
      const double dz = (p.eval(x, y, z + h) - p.eval(x, y, z - h)) / (2 * h);
      EXPECT_NEAR(g.dx, dx, 1e-5 * (1 + std::fabs(dx))) << name << " at " << x << "," << y << "," << z;
      EXPECT_NEAR(g.dy, dy, 1e-5 * (1 + std::fabs(dy))) << name << " at " << x << "," << y << "," << z;
      EXPECT_NEAR(g.dz, dz, 1e-5 * (1 + std::fabs(dz))) << name << " at " << x << "," << y << "," << z;
    }
  }
}

// Property: for random boxes, the interval result contains the value at every sampled point.
void expectIntervalsContainSamples(const std::string& name, const VmProgram& p, unsigned seed, double spread) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> centre(-spread, spread), unit(0.0, 1.0);
  int checked = 0;
  for (int box = 0; box < 300; ++box) {
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const double c = centre(rng);
      const double r = std::pow(10.0, -6.0 + 6.5 * unit(rng));  // 1e-6 .. ~3
      lo[k] = c - r, hi[k] = c + r;
    }
    const Interval iv = p.eval(Interval(lo[0], hi[0]), Interval(lo[1], hi[1]), Interval(lo[2], hi[2]));
    ASSERT_LE(iv.lo, iv.hi) << name;
    for (int s = 0; s < 40; ++s) {
      double q[3];
      for (int k = 0; k < 3; ++k) {
        // The first 8 samples are the corners.
        q[k] = s < 8 ? ((s >> k) & 1 ? hi[k] : lo[k]) : lo[k] + (hi[k] - lo[k]) * unit(rng);
      }
      const double v = p.eval(q[0], q[1], q[2]);
      if (std::isnan(v)) continue;
      // Rounding is not directed: allow a relative hair.
      const double tol = 1e-9 * (1.0 + std::fabs(v));
      EXPECT_TRUE(iv.lo - tol <= v && v <= iv.hi + tol)
          << name << ": f(" << q[0] << ", " << q[1] << ", " << q[2] << ") = " << v << " outside [" << iv.lo << ", "
          << iv.hi << "] for box [" << lo[0] << "," << hi[0] << "]x[" << lo[1] << "," << hi[1] << "]x[" << lo[2]
          << "," << hi[2] << "]";
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000) << name;
}

TEST(VmModel, IntervalBoundsContainSampledValues) {
  expectIntervalsContainSamples("smooth", parseOk(kSmoothModel), 1, 1.0);
  expectIntervalsContainSamples("all ops", parseOk(kAllOpsModel), 2, 1.5);
  expectIntervalsContainSamples("all ops, wide", parseOk(kAllOpsModel), 3, 20.0);
  expectIntervalsContainSamples("generated", parseOk(generateVmRelief(2000, 5)), 4, 1.2);
  if (auto dir = test::fixturesDir()) {
    for (const char* f : {"quarter.vm", "hi.vm", "tanglecube.vm"}) {
      Result<VmProgram> p = VmProgram::load(*dir / "vm" / f);
      ASSERT_TRUE(p.ok()) << p.error();
      expectIntervalsContainSamples(f, *p, 9, 2.0);
    }
  }
}

TEST(VmModel, CallerScratchGivesTheSameValues) {
  const VmProgram p = parseOk(kAllOpsModel);
  std::vector<double> d(p.slotCount());
  std::vector<Grad> g(p.slotCount());
  std::vector<Interval> iv(p.slotCount());
  EXPECT_EQ(p.eval(0.3, -0.2, 0.7, d), p.eval(0.3, -0.2, 0.7));
  EXPECT_EQ(p.eval(Grad(0.3, 1, 0, 0), Grad(-0.2), Grad(0.7), g).dx, p.eval(Grad(0.3, 1, 0, 0), Grad(-0.2), Grad(0.7)).dx);
  const Interval a = p.eval(Interval(0.1, 0.2), Interval(0.3), Interval(0.5, 0.6), iv);
  const Interval b = p.eval(Interval(0.1, 0.2), Interval(0.3), Interval(0.5, 0.6));
  EXPECT_EQ(a.lo, b.lo);
  EXPECT_EQ(a.hi, b.hi);
  // Too small a buffer is refused, not overrun.
  std::vector<double> small(p.slotCount() - 1);
  EXPECT_TRUE(std::isnan(p.eval(0.3, -0.2, 0.7, small)));
  // Slots are reused: far fewer than instructions.
  EXPECT_LT(p.slotCount(), p.size() / 2);
}

TEST(VmModel, DeadClausesAreDroppedAndZUseIsDetected) {
  const VmProgram p = parseOk("z var-z\nunused sin z\nx var-x\ny var-y\nout add x y\n");
  EXPECT_EQ(p.clauseCount(), 5u);
  EXPECT_EQ(p.size(), 3u);
  EXPECT_FALSE(p.usesZ());  // var-z is defined but the result does not depend on it
  EXPECT_EQ(p.eval(1, 2, 3), 3.0);
  const VmProgram q = parseOk("z var-z\nx var-x\nout add x z\n");
  EXPECT_TRUE(q.usesZ());
}

TEST(VmModel, ConcurrentEvaluationIsSafe) {
  const VmProgram p = parseOk(generateVmRelief(3000, 11));
  std::vector<double> expected(2000);
  for (int i = 0; i < 2000; ++i) expected[i] = p.eval(std::sin(i) * 1.1, std::cos(i * 1.3) * 1.1, 0.0);
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 2000; ++i) {
        if (p.eval(std::sin(i) * 1.1, std::cos(i * 1.3) * 1.1, 0.0) != expected[i]) ++mismatches;
        (void)p.eval(Interval(-0.1, 0.1), Interval(0.2, 0.3), Interval(0.0));
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(mismatches.load(), 0);
}

// ---- the workpiece: plate conversion, scale, bounds, json


TEST(VmModel, PlanarModelBecomesAPlate) {
  auto w = VmWorkpiece::create(parseOk(kUnitDisc), "disc.vm", 10.0, 1.0);
  ASSERT_TRUE(w.ok()) << w.error();
  const VmWorkpiece& p = **w;
  EXPECT_TRUE(p.isPlate());
  EXPECT_EQ(p.halfThickness(), 1.0);
  // f = min(10 - |(x, y)|, 1 - |z|) in mm.
  EXPECT_NEAR(p.value(P3<double>{3, 4, 0}), 1.0, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{3, 4, 0.25}), 0.75, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{6, 8, 0}), 0.0, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{0, 9.5, 0.2}), 0.5, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{12, 0, 0}), -2.0, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{0, 0, -3}), -2.0, 1e-12);
  // Gradients: through the faces -z direction, through the rim radially.
  const Grad face = p.value(P3<Grad>{Grad(1, 1, 0, 0), Grad(1, 0, 1, 0), Grad(0.5, 0, 0, 1)});
  EXPECT_NEAR(face.v, 0.5, 1e-12);
  EXPECT_NEAR(face.dz, -1.0, 1e-12);
  EXPECT_NEAR(face.dx, 0.0, 1e-12);
  const Grad rim = p.value(P3<Grad>{Grad(9.5, 1, 0, 0), Grad(0, 0, 1, 0), Grad(0.1, 0, 0, 1)});
  EXPECT_NEAR(rim.v, 0.5, 1e-12);
  EXPECT_NEAR(rim.dx, -1.0, 1e-12);
  EXPECT_NEAR(rim.dz, 0.0, 1e-12);
  // Intervals contain the values.
  const Interval iv = p.value(P3<Interval>{Interval(2, 4), Interval(3, 5), Interval(-0.5, 0.1)});
  EXPECT_LE(iv.lo, p.value(P3<double>{4, 5, -0.5}));
  EXPECT_GE(iv.hi, p.value(P3<double>{2, 3, 0}));
  // Bounds: the disc of radius 10 mm, z = +-d.
  const Box3 b = p.bounds();
  EXPECT_NEAR(b.x0, -10.0, 0.1);
  EXPECT_NEAR(b.x1, 10.0, 0.1);
  EXPECT_NEAR(b.y0, -10.0, 0.1);
  EXPECT_NEAR(b.y1, 10.0, 0.1);
  EXPECT_LE(b.x0, -10.0);
  EXPECT_GE(b.y1, 10.0);
  EXPECT_EQ(b.z0, -1.0);
  EXPECT_EQ(b.z1, 1.0);
}

TEST(VmModel, ScaleMapsModelUnitsToMillimetres) {
  auto w = VmWorkpiece::create(parseOk(kUnitBall), "ball.vm", 5.0, 0.5);
  ASSERT_TRUE(w.ok()) << w.error();
  const VmWorkpiece& p = **w;
  EXPECT_FALSE(p.isPlate());
  // f = 5 - |P| (mm): distance-like in mm.
  EXPECT_NEAR(p.value(P3<double>{0, 0, 0}), 5.0, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{3, 0, 4}), 0.0, 1e-12);
  EXPECT_NEAR(p.value(P3<double>{0, 7, 0}), -2.0, 1e-12);
  const Grad g = p.value(P3<Grad>{Grad(3, 1, 0, 0), Grad(0, 0, 1, 0), Grad(4, 0, 0, 1)});
  EXPECT_NEAR(g.dx, -0.6, 1e-12);
  EXPECT_NEAR(g.dy, 0.0, 1e-12);
  EXPECT_NEAR(g.dz, -0.8, 1e-12);
  const Box3 b = p.bounds();
  EXPECT_NEAR(b.z0, -5.0, 0.05);
  EXPECT_NEAR(b.z1, 5.0, 0.05);
  EXPECT_NEAR(b.x1, 5.0, 0.05);
}

// Samples points outside the box (near each face and far away) and requires f < 0 there.
void expectNegativeOutsideBounds(const std::string& name, const Workpiece& w, unsigned seed) {
  const Box3 b = w.bounds();
  ASSERT_LT(b.x0, b.x1) << name;
  ASSERT_LT(b.y0, b.y1) << name;
  ASSERT_LT(b.z0, b.z1) << name;
  const double ext[3] = {b.x1 - b.x0, b.y1 - b.y0, b.z1 - b.z0};
  const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    // A random point of the box grown by 50%, pushed out through one face: just outside (within
    // 1e-6 .. 10% of the extent) or anywhere beyond.
    double p[3];
    for (int k = 0; k < 3; ++k) p[k] = lo[k] - 0.5 * ext[k] + 2.0 * ext[k] * unit(rng);
    const int face = static_cast<int>(unit(rng) * 6) % 6;
    const int axis = face / 2;
    const double out = i % 2 ? ext[axis] * std::pow(10.0, -6.0 + 5.0 * unit(rng)) : ext[axis] * unit(rng);
    p[axis] = face % 2 ? hi[axis] + out : lo[axis] - out;
    const double v = w.value(P3<double>{p[0], p[1], p[2]});
    EXPECT_LT(v, 0.0) << name << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    ++checked;
  }
  EXPECT_EQ(checked, 20000);
}

// Also requires the box to be tight: for a plate, some point of a fine grid in the z = 0 plane
// within `slack` (relative) of each side is inside.
void expectTightPlateBounds(const std::string& name, const Workpiece& w, double slack) {
  const Box3 b = w.bounds();
  double seen[4] = {1e300, -1e300, 1e300, -1e300};
  const int n = 250;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double x = b.x0 + (b.x1 - b.x0) * i / n, y = b.y0 + (b.y1 - b.y0) * j / n;
      if (w.value(P3<double>{x, y, 0.0}) >= 0.0) {
        seen[0] = std::min(seen[0], x), seen[1] = std::max(seen[1], x);
        seen[2] = std::min(seen[2], y), seen[3] = std::max(seen[3], y);
      }
    }
  }
  EXPECT_LT(seen[0] - b.x0, slack * (b.x1 - b.x0)) << name;
  EXPECT_LT(b.x1 - seen[1], slack * (b.x1 - b.x0)) << name;
  EXPECT_LT(seen[2] - b.y0, slack * (b.y1 - b.y0)) << name;
  EXPECT_LT(b.y1 - seen[3], slack * (b.y1 - b.y0)) << name;
}

TEST(VmModel, BoundsAreTightAndEverythingOutsideIsNegative) {
  std::vector<std::pair<std::string, std::shared_ptr<VmWorkpiece>>> pieces;
  const auto add = [&](const std::string& name, Result<std::shared_ptr<VmWorkpiece>> w) {
    ASSERT_TRUE(w.ok()) << name << ": " << w.error();
    pieces.emplace_back(name, *w);
  };
  add("disc", VmWorkpiece::create(parseOk(kUnitDisc), "disc.vm", 7.0, 0.8));
  add("ball", VmWorkpiece::create(parseOk(kUnitBall), "ball.vm", 3.0, 0.8));
  add("generated", VmWorkpiece::create(parseOk(generateVmRelief(1500, 3)), "gen.vm", 20.0, 1.0));
  if (auto dir = test::fixturesDir()) {
    add("quarter", VmWorkpiece::open(*dir / "vm" / "quarter.vm", "quarter.vm", 25.0, 1.0));
    add("hi", VmWorkpiece::open(*dir / "vm" / "hi.vm", "hi.vm", 40.0, 1.5));
    add("tanglecube", VmWorkpiece::open(*dir / "vm" / "tanglecube.vm", "tanglecube.vm", 4.0, 1.0));
  }
  unsigned seed = 1;
  for (const auto& [name, w] : pieces) {
    expectNegativeOutsideBounds(name, *w, seed++);
    if (w->isPlate()) expectTightPlateBounds(name, *w, 0.01);
  }
  // 3D: the ball of radius 3 mm; the tanglecube reaches y^4 - 5y^2 = 2.5 (at x^2 = z^2 = 2.5).
  const Box3 ball = pieces[1].second->bounds();
  for (const double e : {ball.x0, ball.y0, ball.z0}) EXPECT_NEAR(e, -3.0, 0.03);
  for (const double e : {ball.x1, ball.y1, ball.z1}) EXPECT_NEAR(e, 3.0, 0.03);
  if (pieces.size() > 5) {
    const double reach = 4.0 * std::sqrt((5.0 + std::sqrt(35.0)) / 2.0);
    const Box3 t = pieces[5].second->bounds();
    // Interval arithmetic overestimates x^4 - 5x^2 (the dependency problem), so in 3D the box is
    // a few per cent loose; it must never be too small.
    for (const double e : {t.x0, t.y0, t.z0}) EXPECT_NEAR(e, -reach, 0.08 * reach);
    for (const double e : {t.x1, t.y1, t.z1}) EXPECT_NEAR(e, reach, 0.08 * reach);
    for (const double e : {t.x1, t.y1, t.z1}) EXPECT_GE(e, reach);
    for (const double e : {t.x0, t.y0, t.z0}) EXPECT_LE(e, -reach);
  }
  // The generated outline stays within about +-1 unit.
  const Box3 g = pieces[2].second->bounds();
  EXPECT_GT(g.x0, -1.2 * 20.0);
  EXPECT_LT(g.x1, 1.2 * 20.0);
  EXPECT_GT(g.y0, -1.2 * 20.0);
  EXPECT_LT(g.y1, 1.2 * 20.0);
}

// A bounded 3D model of every opcode: two unit spheres blended by a log-sum-exp smooth minimum
// (ln, exp, div: far from them both exp terms underflow to 0 and ln 0 is -inf, as in Fidget's
// bear), max'ed with a term of all the other opcodes that stays within -2 +- 0.002.
constexpr const char* kEveryOpcode = R"(x var-x
y var-y
z var-z
x2 square x
y2 square y
z2 square z
r2 add x2 y2
r2z add r2 z2
r sqrt r2z
one const 1
a sub r one
xm sub x one
xm2 square xm
s2 add xm2 y2
s2z add s2 z2
rb sqrt s2z
b sub rb one
k const -8
ka mul k a
kb mul k b
ea exp ka
eb exp kb
sum add ea eb
l ln sum
nl neg l
eight const 8
blend div nl eight
t1 sin x
t2 cos y
t3 atan z
half const 0.5
t3h mul t3 half
t4 tan t3h
t5 asin t1
t6 acos t2
t7 abs z
two const 2
t8 add two x2
t9 recip t8
t10 floor x
t11 ceil y
t12 round z
t13 not x
t14 compare x y
t15 and x y
t16 or y z
three const 3
t17 mod x three
t18 add two y2
t19 pow t18 half
t20 atan2 y x
t21 min t1 t2
u1 add t1 t2
u2 add u1 t4
u3 add u2 t5
u4 add u3 t6
u5 add u4 t7
u6 add u5 t9
u7 add u6 t10
u8 add u7 t11
u9 add u8 t12
u10 add u9 t13
u11 add u10 t14
u12 add u11 t15
u13 add u12 t16
u14 add u13 t17
u15 add u14 t19
u16 add u15 t20
u17 add u16 t21
u18 atan u17
milli const 0.001
u19 mul u18 milli
h sub u19 two
out max blend h
)";

double everyOpcode(double x, double y, double z) {
  const double a = std::sqrt(x * x + y * y + z * z) - 1, b = std::sqrt((x - 1) * (x - 1) + y * y + z * z) - 1;
  const double blend = -std::log(std::exp(-8 * a) + std::exp(-8 * b)) / 8;
  const double t1 = std::sin(x), t2 = std::cos(y);
  const double t13 = x == 0 ? 1 : 0, t14 = x < y ? -1 : x > y ? 1 : 0, t15 = x == 0 ? x : y, t16 = y != 0 ? y : z;
  double t17 = std::fmod(x, 3.0);
  if (t17 < 0) t17 += 3;
  double u = t1 + t2 + std::tan(std::atan(z) * 0.5) + std::asin(t1) + std::acos(t2) + std::abs(z) + 1 / (2 + x * x) +
             std::floor(x) + std::ceil(y) + std::round(z) + t13 + t14 + t15 + t16 + t17 + std::pow(2 + y * y, 0.5) +
             std::atan2(y, x) + std::min(t1, t2);
  const double h = std::atan(u) * 0.001 - 2;
  return std::max(blend, h);
}

TEST(VmModel, BoundedModelOfEveryOpcodeLoadsAndEvaluates) {
  VmProgram p = parseOk(kEveryOpcode);
  ASSERT_TRUE(p.usesZ());
  std::set<VmOp> used;
  for (const auto& n : p.nodes()) used.insert(n.op);
  EXPECT_EQ(used.size(), 33u) << "every opcode of the format is in the model";
  auto w = VmWorkpiece::create(p, "every.vm", 10.0, 1.0);
  ASSERT_TRUE(w.ok()) << w.error();
  // The blend's inside: about [-1, 2] x [-1, 1]^2 units, 10 mm each.
  const Box3 b = (*w)->bounds();
  EXPECT_LT(b.x0, -10.0);
  EXPECT_GT(b.x1, 20.0);
  EXPECT_GT(b.x0, -12.0);
  EXPECT_LT(b.x1, 22.0);
  EXPECT_LT(b.z0, -10.0);
  EXPECT_GT(b.z1, 10.0);
  EXPECT_LT(b.z1, 12.0);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 500; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng);
    EXPECT_NEAR(p.eval(x, y, z), everyOpcode(x, y, z), 1e-12) << x << " " << y << " " << z;
    // The workpiece: mm, positive inside.
    EXPECT_NEAR((*w)->value(P3<double>{10 * x, 10 * y, 10 * z}), -10 * everyOpcode(x, y, z), 1e-10);
  }
}

TEST(VmModel, FixtureModelsLoad) {
  EMBOSS_REQUIRE_FIXTURES(fixtures);
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(fixtures / "vm")) {
    if (e.path().extension() != ".vm") continue;
    auto w = VmWorkpiece::open(e.path(), e.path().filename().string(), 1.0, 1.0);
    EXPECT_TRUE(w.ok()) << w.error();
    ++n;
  }
  EXPECT_GT(n, 0) << "no .vm models in the fixtures";
}

TEST(VmModel, UnboundedOrEmptyModelsAreRefused) {
  auto half = VmWorkpiece::create(parseOk("x var-x\n"), "half.vm", 1.0, 1.0);
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.error().find("the model's inside reaches the edge of the +-1000-unit search box: it is unbounded"),
            std::string::npos)
      << half.error();
  // A 3D half-space below a wavy floor: still refused.
  auto floor3 = VmWorkpiece::create(parseOk("x var-x\nz var-z\ns sin x\nout sub z s\n"), "floor.vm", 1.0, 1.0);
  ASSERT_FALSE(floor3.ok());
  EXPECT_NE(floor3.error().find("unbounded"), std::string::npos) << floor3.error();
  auto inverted = VmWorkpiece::create(parseOk("x var-x\ny var-y\nx2 square x\ny2 square y\ns add x2 y2\n"
                                              "one const 1\nout sub one s\n"),
                                      "inverted.vm", 1.0, 1.0);
  ASSERT_FALSE(inverted.ok());
  EXPECT_NE(inverted.error().find("unbounded"), std::string::npos) << inverted.error();
  auto nothing = VmWorkpiece::create(parseOk("c const 1\n"), "nothing.vm", 1.0, 1.0);
  ASSERT_FALSE(nothing.ok());
  EXPECT_NE(nothing.error().find("no inside"), std::string::npos) << nothing.error();
  EXPECT_FALSE(VmWorkpiece::create(parseOk(kUnitDisc), "disc.vm", 0.0, 1.0).ok());
  EXPECT_FALSE(VmWorkpiece::create(parseOk(kUnitDisc), "disc.vm", 1.0, -1.0).ok());
  EXPECT_FALSE(VmWorkpiece::create(parseOk(kUnitDisc), "disc.vm", kNaN, 1.0).ok());
}

TEST(VmModel, JsonKeepsTheFileAsWritten) {
  const std::filesystem::path dir = test::scratchDir("vm_json");
  {
    std::ofstream(dir / "disc.vm") << kUnitDisc;
  }
  auto w = VmWorkpiece::open(dir / "disc.vm", "models/../disc.vm", 12.5, 0.75);
  ASSERT_TRUE(w.ok()) << w.error();
  const nlohmann::json j = (*w)->toJson();
  EXPECT_EQ(j, (nlohmann::json{{"type", "vm"}, {"file", "models/../disc.vm"}, {"scale", 12.5}, {"d", 0.75}}));
  EXPECT_EQ((*w)->file(), "models/../disc.vm");
  EXPECT_EQ((*w)->scale(), 12.5);
}

// ---- malformed input

TEST(VmModel, MalformedInputGivesMessagesNamingTheLine) {
  EXPECT_EQ(parseError("a var-x\nb foo a\n", "hi.vm"), "hi.vm:2: unknown opcode 'foo'");
  EXPECT_EQ(parseError("x var-x\n# comment\ny add x x2\nx2 var-y\n"), "line 3: 'x2' used before it is defined");
  EXPECT_EQ(parseError("x var-x\ny sin nothing\n", "m.vm"), "m.vm:2: 'nothing' used before it is defined");
  EXPECT_EQ(parseError("", "e.vm"), "e.vm: empty model (no clauses)");
  EXPECT_EQ(parseError("# just a comment\n\n   \n"), "empty model (no clauses)");
  EXPECT_EQ(parseError("c const abc\n"), "line 1: 'abc' is not a finite number");
  EXPECT_EQ(parseError("c const 1e999\n"), "line 1: '1e999' is not a finite number");
  EXPECT_EQ(parseError("c const nan\n"), "line 1: 'nan' is not a finite number");
  EXPECT_EQ(parseError("c const 1.5x\n"), "line 1: '1.5x' is not a finite number");
  EXPECT_EQ(parseError("c const\n"), "line 1: 'const' takes one number, got 0 arguments");
  EXPECT_EQ(parseError("x var-x\ny add x\n"), "line 2: 'add' takes 2 operands, got 1");
  EXPECT_EQ(parseError("x var-x\ny neg x x\n"), "line 2: 'neg' takes 1 operand, got 2");
  EXPECT_EQ(parseError("x var-x 3\n"), "line 1: 'var-x' takes no operands, got 1");
  EXPECT_EQ(parseError("x var-x\nx var-y\n"), "line 2: 'x' is already defined on line 1");
  EXPECT_EQ(parseError("x var-x\nlonely\n"), "line 2: 'lonely' has no opcode");
  EXPECT_EQ(parseError("x var-x\ny add x x x x x x\n"), "line 2: 'add' takes 2 operands, got 6");
  // Unprintable bytes are escaped and long tokens shortened in messages.
  EXPECT_EQ(parseError(std::string("x v\x01\xff\n", 6)), "line 1: unknown opcode 'v\\x01\\xff'");
  const std::string longName(100, 'q');
  EXPECT_EQ(parseError("x " + longName + "\n"), "line 1: unknown opcode '" + std::string(40, 'q') + "...'");
  // Windows line ends, tabs, comments after clauses and a leading '+' are fine.
  const VmProgram ok = parseOk("x\tvar-x\r\nc const +2.5 # two and a half\r\nout mul x c\r\n");
  EXPECT_EQ(ok.eval(2, 0, 0), 5.0);
}

TEST(VmModel, MissingFilesAreReportedByName) {
  Result<VmProgram> p = VmProgram::load("/nonexistent/folder/model.vm");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().find("/nonexistent/folder/model.vm"), std::string::npos) << p.error();
  const std::filesystem::path dir = test::scratchDir("vm_errors");
  {
    std::ofstream(dir / "bad.vm") << "x var-x\ny bogus x\n";
  }
  auto w = VmWorkpiece::open(dir / "bad.vm", "models/bad.vm", 1.0, 1.0);
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.error(), "models/bad.vm:2: unknown opcode 'bogus'");
  Result<VmProgram> folder = VmProgram::load(dir);
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.error().find("folder"), std::string::npos) << folder.error();
}

TEST(VmModel, ArbitraryBytesNeverCrash) {
  // A cheap in-process fuzz: mutations of a valid model and random token soup.
  const std::string base(kAllOpsModel);
  std::mt19937 rng(1234);
  const char* words[] = {"add", "x", "y", "const", "var-x", "1e308", "-0", "sqrt", "#", "\n", " ", "div", "z", "mod"};
  int parsed = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string t = base;
    if (i % 3 == 0) {
      t[rng() % t.size()] = static_cast<char>(rng() & 0xff);
    } else if (i % 3 == 1) {
      for (int k = 0; k < 5; ++k) t[rng() % t.size()] = static_cast<char>(rng() & 0xff);
    } else {
      t.clear();
      for (int k = 0; k < 30; ++k) t += std::string(words[rng() % std::size(words)]) + (rng() % 3 ? " " : "\n");
    }
    Result<VmProgram> p = VmProgram::parse(t, "fuzz.vm");
    if (!p) {
      EXPECT_FALSE(p.error().empty());
      continue;
    }
    ++parsed;
    (void)p->eval(0.1, 0.2, 0.3);
    (void)p->eval(Grad(0.1, 1, 0, 0), Grad(0.2), Grad(0.3));
    const Interval iv = p->eval(Interval(-1, 1), Interval(-1, 1), Interval(-1, 1));
    EXPECT_FALSE(std::isnan(iv.lo) || std::isnan(iv.hi));
    (void)p->povFunction();
  }
  EXPECT_GT(parsed, 20);
}

// ---- size

TEST(VmModel, GeneratedModelMatchesAReferenceEvaluator) {
  const std::string text = generateVmRelief(5000, 42);
  EXPECT_EQ(text, generateVmRelief(5000, 42)) << "the generator must be deterministic";
  const auto t0 = std::chrono::steady_clock::now();
  const VmProgram p = parseOk(text, "generated.vm");
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_GT(p.clauseCount(), 4900u);
  EXPECT_LE(p.clauseCount(), 5000u);
  EXPECT_FALSE(p.usesZ());
  EXPECT_LT(p.slotCount(), 64u);
  const ReferenceModel ref(text);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  int inside = 0;
  for (int i = 0; i < 500; ++i) {
    const double x = u(rng), y = u(rng);
    const double v = p.eval(x, y, 0.0);
    const double r = ref.eval(x, y, 0.0);
    EXPECT_NEAR(v, r, 1e-12 * (1 + std::fabs(r))) << "at " << x << ", " << y;
    EXPECT_EQ(p.eval(Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(0.0)).v, v);
    inside += v < 0.0;
  }
  // A realistic outline: a good part of the square is inside, a good part outside.
  EXPECT_GT(inside, 50);
  EXPECT_LT(inside, 450);
  std::cout << "[ info     ] parsed " << p.clauseCount() << " clauses into " << p.size() << " instructions, "
            << p.slotCount() << " slots, in " << std::chrono::duration<double, std::milli>(t1 - t0).count()
            << " ms\n";
}

TEST(VmModel, HundredThousandLongChainNeedsNoRecursion) {
  const int n = 100000;
  const std::string text = chainText(n);
  const auto t0 = std::chrono::steady_clock::now();
  const VmProgram p = parseOk(text, "chain.vm");
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_EQ(p.clauseCount(), static_cast<std::size_t>(n + 2));
  EXPECT_LE(p.slotCount(), 3u);
  EXPECT_EQ(p.eval(1.0, 0.0, 0.0), 1.0 + 0.5 * n);
  const Grad g = p.eval(Grad(1.0, 1, 0, 0), Grad(0.0), Grad(0.0));
  EXPECT_EQ(g.v, 1.0 + 0.5 * n);
  EXPECT_EQ(g.dx, 1.0);
  const Interval iv = p.eval(Interval(-1, 1), Interval(0.0), Interval(0.0));
  EXPECT_EQ(iv.lo, -1.0 + 0.5 * n);
  EXPECT_EQ(iv.hi, 1.0 + 0.5 * n);
  // POV-Ray text stays shallow: the chain is cut into declarations.
  Result<PovFunction> pov = p.povFunction();
  ASSERT_TRUE(pov.ok()) << pov.error();
  EXPECT_GE(pov->declarationCount, static_cast<std::size_t>(n / 400));
  EXPECT_LT(pov->callDepth, 400);
  PovEvaluator e(*pov);
  EXPECT_EQ(e.eval(1.0, 0.0, 0.0), 1.0 + 0.5 * n) << e.error;
  EXPECT_TRUE(e.error.empty()) << e.error;
  EXPECT_EQ(e.deepest, pov->callDepth);
  std::cout << "[ info     ] parsed a " << n << "-clause chain in "
            << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms\n";
}

// ---- POV-Ray output

TEST(VmModel, PovFunctionComputesTheSameValues) {
  std::vector<std::pair<std::string, VmProgram>> models;
  models.emplace_back("smooth", parseOk(kSmoothModel));
  models.emplace_back("all ops", parseOk(kAllOpsModel));
  models.emplace_back("generated", parseOk(generateVmRelief(3000, 8)));
  models.emplace_back("negative constants", parseOk("x var-x\nc const -2.5e-7\nd const -0\ne add x c\nout sub e d\n"));
  models.emplace_back("leaf only", parseOk("x var-y\n"));
  if (auto dir = test::fixturesDir()) {
    for (const char* f : {"quarter.vm", "hi.vm", "tanglecube.vm"}) {
      if (auto p = VmProgram::load(*dir / "vm" / f)) models.emplace_back(f, std::move(*p));
    }
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (const auto& [name, p] : models) {
    for (const int mode : {0, 1, 2}) {  // declarations with the default depth, a small one; inline
      PovOptions o;
      o.prefix = "T_vm";
      o.allowDeclarations = mode != 2;
      o.maxDepth = mode == 0 ? PovOptions{}.maxDepth : mode == 1 ? 8 : 100000;
      Result<PovFunction> f = p.povFunction(o);
      if (mode == 2 && name == "generated") {
        // Smooth unions use both operands twice: inlined, the text doubles with every primitive.
        ASSERT_FALSE(f.ok());
        EXPECT_NE(f.error().find("exceed"), std::string::npos) << f.error();
        continue;
      }
      ASSERT_TRUE(f.ok()) << name << ": " << f.error();
      if (mode == 2) {
        EXPECT_TRUE(f->declarations.empty());
      }
      PovEvaluator e(*f);
      ASSERT_TRUE(e.error.empty()) << name << ": " << e.error;
      for (int i = 0; i < 100; ++i) {
        const double x = u(rng), y = u(rng), z = u(rng);
        const double want = p.eval(x, y, z);
        const double got = e.eval(x, y, z);
        EXPECT_TRUE(closeEnough(got, want, 1e-13)) << name << " mode " << mode << " at " << x << "," << y << ","
                                                   << z << ": " << got << " vs " << want;
        // Every node is computed once: POV-Ray's work is linear in the model.
        if (mode != 2) {
          EXPECT_LT(e.ops, static_cast<long>(40 * p.nodes().size() + 50)) << name << " mode " << mode;
        }
        EXPECT_EQ(e.deepest, f->callDepth) << name << " mode " << mode;
      }
    }
  }
}

TEST(VmModel, PovFunctionRefusesExponentialBlowUp) {
  // Each clause doubles the inlined size: 2^200 characters without declarations.
  std::string text = "a0 var-x\n";
  for (int i = 1; i <= 200; ++i) text += "a" + std::to_string(i) + " mul a" + std::to_string(i - 1) + " a" +
                                        std::to_string(i - 1) + "\n";
  const VmProgram p = parseOk(text, "doubling.vm");
  PovOptions inlineOnly;
  inlineOnly.allowDeclarations = false;
  inlineOnly.maxDepth = 1000;
  const auto t0 = std::chrono::steady_clock::now();
  Result<PovFunction> f = p.povFunction(inlineOnly);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().find("doubling.vm"), std::string::npos) << f.error();
  EXPECT_NE(f.error().find("exceed"), std::string::npos) << f.error();
  // With declarations it is linear.
  Result<PovFunction> g = p.povFunction();
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_LT(g->declarations.size() + g->expression.size(), 40000u);
  PovEvaluator e(*g);
  EXPECT_EQ(e.eval(-1.0, 0, 0), 1.0) << e.error;
  EXPECT_EQ(e.eval(1.0000001, 0, 0), p.eval(1.0000001, 0, 0)) << e.error;
  EXPECT_LT(e.ops, 40 * 200);
  // A small explicit limit applies to declarations too; a deep expression without declarations
  // is refused; so is a prefix POV-Ray cannot take.
  PovOptions tiny;
  tiny.maxChars = 100;
  EXPECT_FALSE(p.povFunction(tiny).ok());
  PovOptions shallow;
  shallow.allowDeclarations = false;
  shallow.maxDepth = 10;
  Result<PovFunction> deep = parseOk(chainText(50)).povFunction(shallow);
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.error().find("nest"), std::string::npos) << deep.error();
  PovOptions badPrefix;
  badPrefix.prefix = "1 bad";
  EXPECT_FALSE(p.povFunction(badPrefix).ok());
}

// Runs the real POV-Ray on the generated text and compares its values with eval.
TEST(VmModelGolden, PovRayAgreesWithEval) {
  if (std::system("command -v povray >/dev/null 2>&1") != 0) GTEST_SKIP() << "povray not installed";
  std::vector<std::pair<std::string, VmProgram>> models;
  models.emplace_back("all_ops", parseOk(kAllOpsModel));
  models.emplace_back("generated", parseOk(generateVmRelief(3000, 8)));
  models.emplace_back("chain", parseOk(chainText(20000)));
  if (auto dir = test::fixturesDir()) {
    if (auto p = VmProgram::load(*dir / "vm" / "tanglecube.vm")) models.emplace_back("tanglecube", std::move(*p));
  }
  const std::filesystem::path dir = test::scratchDir("vm_povray");
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (const auto& [name, p] : models) {
    PovOptions o;
    o.prefix = "M_" + name;
    Result<PovFunction> f = p.povFunction(o);
    ASSERT_TRUE(f.ok()) << f.error();
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < 30; ++i) points.push_back({u(rng), u(rng), u(rng)});
    const std::filesystem::path pov = dir / (name + ".pov");
    {
      std::ofstream out(pov);
      out << "#version 3.7;\n" << f->declarations << "#declare F = function(x,y,z){ " << f->expression << " }\n";
      char line[256];
      for (const auto& q : points) {
        std::snprintf(line, sizeof line, "#debug concat(\"V \", str(F(%.17g,%.17g,%.17g),0,17), \"\\n\")\n", q[0],
                      q[1], q[2]);
        out << line;
      }
    }
    const std::filesystem::path log = dir / (name + ".log");
    const std::string cmd = "cd '" + dir.string() + "' && HOME='" + dir.string() + "' timeout 120 povray +I'" +
                            pov.string() + "' -D +W1 +H1 -F +WT1 >'" + log.string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << name << ": povray failed, see " << log;
    std::ifstream in(log);
    std::string text;
    std::vector<double> got;
    while (std::getline(in, text)) {
      if (text.rfind("V ", 0) == 0) got.push_back(std::stod(text.substr(2)));
    }
    ASSERT_EQ(got.size(), points.size()) << name << ": see " << log;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double want = p.eval(points[i][0], points[i][1], points[i][2]);
      EXPECT_NEAR(got[i], want, 1e-9 * (1 + std::fabs(want))) << name << " point " << i;
    }
  }
}

// ---- timings (seconds): evaluation throughput of a 5000-clause model

TEST(VmModelSlow, ThroughputOfAFiveThousandClauseModel) {
  const std::string text = generateVmRelief(5000, 1);
  const VmProgram p = parseOk(text);
  // CPU time of this thread: the machine may be shared, wall time would measure the neighbours.
  const auto cpuSeconds = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  };
  const auto rate = [&](auto one) {
    const double t0 = cpuSeconds();
    long n = 0;
    double sink = 0.0;
    while (cpuSeconds() - t0 < 0.3) {
      for (int i = 0; i < 200; ++i, ++n) sink += one(0.001 * static_cast<double>(n % 1000) - 0.5);
    }
    const double s = cpuSeconds() - t0;
    EXPECT_FALSE(std::isnan(sink));
    return static_cast<double>(n) / s;
  };
  const double d = rate([&](double t) { return p.eval(t, 0.3, 0.0); });
  const double g = rate([&](double t) { return p.eval(Grad(t, 1, 0, 0), Grad(0.3, 0, 1, 0), Grad(0.0)).dx; });
  const double iv = rate([&](double t) { return p.eval(Interval(t, t + 0.01), Interval(0.3, 0.31), Interval(0.0)).lo; });
  double t0 = cpuSeconds();
  const VmProgram again = parseOk(text);
  const double parseMs = 1e3 * (cpuSeconds() - t0);
  t0 = cpuSeconds();
  auto w = VmWorkpiece::create(VmProgram(p), "gen.vm", 20.0, 1.0);
  const double boundsMs = 1e3 * (cpuSeconds() - t0);
  ASSERT_TRUE(w.ok()) << w.error();
  t0 = cpuSeconds();
  Result<PovFunction> pov = p.povFunction();
  const double povMs = 1e3 * (cpuSeconds() - t0);
  ASSERT_TRUE(pov.ok()) << pov.error();
  std::cout << "[ info     ] " << p.size() << " instructions (CPU time): " << d << " double/s, " << g << " grad/s, "
            << iv << " interval/s (" << 1e9 / (d * static_cast<double>(p.size())) << " ns per instruction); parse "
            << parseMs << " ms, bounds " << boundsMs << " ms, POV-Ray text " << povMs << " ms ("
            << pov->declarationCount << " functions, call depth " << pov->callDepth << ")\n";
  EXPECT_GT(d, 1000.0);
}

}  // namespace
}  // namespace emboss

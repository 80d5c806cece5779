// The plain interval-pruning 2D renderer (baseline_2d.h), over the program's SSA graph (its nodes)
// with the format's own operations (frep/vm_ops.h), so that it computes what VmProgram computes.
// Its node loop and tape pruning are its own, not the product's (VmProgram::specialised): the
// yardstick must not move when the product's evaluator changes.
#include "bench/baseline_2d.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>

#include "frep/vm_ops.h"

namespace emboss {

namespace {

using Node = VmProgram::Node;
using namespace vm_detail;

constexpr int kTile = 64;  // the threads' unit of work
constexpr int kLeaf = 8;   // cells this small are evaluated pixel by pixel

template <class T>
T apply(const Node& n, const T* v, T x, T y, T z) {
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

bool finite(const Interval& i) { return std::isfinite(i.lo) && std::isfinite(i.hi); }

// Per thread: the value buffers and the tapes of each level of the recursion.
struct Scratch {
  std::vector<Interval> iv;
  std::vector<double> dv;
  std::vector<std::uint8_t> choice;
  std::vector<std::uint32_t> alias, remap;
  std::vector<bool> live;
  std::vector<std::vector<Node>> tapes;  // tapes[d]: the tape pruned for depth d
};

// The tape's interval over the box; choice[i] says which operand of a min or max node decides it
// over the whole box (1: a, 2: b, 0: either may).
Interval evalInterval(const std::vector<Node>& t, Interval x, Interval y, Scratch& s) {
  s.iv.resize(t.size());
  s.choice.assign(t.size(), 0);
  for (size_t i = 0; i < t.size(); ++i) {
    const Node& n = t[i];
    s.iv[i] = apply<Interval>(n, s.iv.data(), x, y, Interval(0.0, 0.0));
    if (n.op == VmOp::kMin || n.op == VmOp::kMax) {
      const Interval& a = s.iv[n.a];
      const Interval& b = s.iv[n.b];
      if (!finite(a) || !finite(b)) continue;
      if (n.op == VmOp::kMin) s.choice[i] = a.hi < b.lo ? 1 : b.hi < a.lo ? 2 : 0;
      else s.choice[i] = a.lo > b.hi ? 1 : b.lo > a.hi ? 2 : 0;
    }
  }
  return s.iv.back();
}

// The tape with every decided min and max replaced by its deciding operand, and what no longer
// reaches the result dropped (libfive's and Fidget's tape simplification).
void prune(const std::vector<Node>& t, Scratch& s, std::vector<Node>& out) {
  const size_t n = t.size();
  s.alias.resize(n);
  for (size_t i = 0; i < n; ++i) {
    s.alias[i] = static_cast<std::uint32_t>(i);
    if (s.choice[i] == 1) s.alias[i] = s.alias[t[i].a];
    else if (s.choice[i] == 2) s.alias[i] = s.alias[t[i].b];
  }
  s.live.assign(n, false);
  s.live[s.alias[n - 1]] = true;
  for (size_t k = n; k-- > 0;) {
    if (!s.live[k] || s.alias[k] != k) continue;
    const int arity = vmOpArity(t[k].op);
    if (arity >= 1) s.live[s.alias[t[k].a]] = true;
    if (arity == 2) s.live[s.alias[t[k].b]] = true;
  }
  out.clear();
  s.remap.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (!s.live[i] || s.alias[i] != i) continue;
    Node nd = t[i];
    const int arity = vmOpArity(nd.op);
    if (arity >= 1) nd.a = s.remap[s.alias[nd.a]];
    if (arity == 2) nd.b = s.remap[s.alias[nd.b]];
    s.remap[i] = static_cast<std::uint32_t>(out.size());
    out.push_back(nd);
  }
}

struct Job {
  int size;
  double halfWidth, pixel;  // model units per pixel
  std::uint8_t* mask;
};

void fill(const Job& j, int x0, int y0, int n, std::uint8_t v) {
  for (int y = y0; y < y0 + n && y < j.size; ++y) std::memset(j.mask + static_cast<size_t>(y) * j.size + x0, v, std::min(n, j.size - x0));
}

struct Counts {
  long intervals = 0, points = 0, leaves = 0, leafNodes = 0;
};

// Nearly all of the baseline's time is here (everything it calls is inlined). Its start is aligned
// to a page so that its loops and its interpreter's indirect jump keep their place within a page
// whatever else the binary holds: left to the linker, the same code ran 10 to 20 % slower in one
// build than in another on the same machine, and the yardstick moved with it. A cache line was not
// enough: two builds with the function 64-byte aligned at different offsets in its page took 86 to
// 88 ms and 77 ms a frame, alternately on the same host; page-aligned, both 77 to 78 ms, and so
// did a third with the function three pages further on (performance.md, "Against the in-run
// baseline").
[[gnu::aligned(4096)]] void cell(const Job& j, int depth, int x0, int y0, int n, Scratch& s, Counts& c) {
  if (x0 >= j.size || y0 >= j.size) return;
  const std::vector<Node>& tape = s.tapes[depth];
  const Interval ix(-j.halfWidth + x0 * j.pixel, -j.halfWidth + (x0 + n) * j.pixel);
  const Interval iy(j.halfWidth - (y0 + n) * j.pixel, j.halfWidth - y0 * j.pixel);
  const Interval v = evalInterval(tape, ix, iy, s);
  ++c.intervals;
  if (v.lo > 0.0) return fill(j, x0, y0, n, 0);    // outside
  if (v.hi < 0.0) return fill(j, x0, y0, n, 255);  // inside
  prune(tape, s, s.tapes[depth + 1]);  // tapes has a level for every depth (kTile / kLeaf halvings)
  if (n > kLeaf) {
    const int h = n / 2;
    cell(j, depth + 1, x0, y0, h, s, c);
    cell(j, depth + 1, x0 + h, y0, h, s, c);
    cell(j, depth + 1, x0, y0 + h, h, s, c);
    cell(j, depth + 1, x0 + h, y0 + h, h, s, c);
    return;
  }
  const std::vector<Node>& leaf = s.tapes[depth + 1];
  ++c.leaves;
  c.leafNodes += static_cast<long>(leaf.size());
  s.dv.resize(leaf.size());
  for (int y = y0; y < y0 + n && y < j.size; ++y) {
    const double py = j.halfWidth - (y + 0.5) * j.pixel;
    for (int x = x0; x < x0 + n && x < j.size; ++x) {
      const double px = -j.halfWidth + (x + 0.5) * j.pixel;
      for (size_t i = 0; i < leaf.size(); ++i) s.dv[i] = apply<double>(leaf[i], s.dv.data(), px, py, 0.0);
      j.mask[static_cast<size_t>(y) * j.size + x] = s.dv.back() < 0.0 ? 255 : 0;
      ++c.points;
    }
  }
}

}  // namespace

Baseline2dResult renderBaseline2d(const VmProgram& program, int size, double halfWidth, ThreadPool& pool) {
  Baseline2dResult r;
  r.mask.assign(static_cast<size_t>(size) * size, 0);
  std::atomic<long> intervals{0}, points{0}, leaves{0}, leafNodes{0};
  const Job j{size, halfWidth, 2.0 * halfWidth / size, r.mask.data()};
  const auto t0 = std::chrono::steady_clock::now();
  pool.parallelFor2D(Rect{0, 0, size, size}, kTile, [&](const Rect& t) {
    thread_local Scratch s;
    if (s.tapes.empty()) s.tapes.resize(8);  // never resized again: cell() holds references into it
    s.tapes[0] = program.nodes();
    Counts c;
    cell(j, 0, t.x, t.y, kTile, s, c);
    intervals += c.intervals;
    points += c.points;
    leaves += c.leaves;
    leafNodes += c.leafNodes;
  });
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  r.intervalEvals = intervals;
  r.pointEvals = points;
  r.meanLeafTape = leaves ? static_cast<double>(leafNodes) / static_cast<double>(leaves) : 0.0;
  r.fullTape = program.nodes().size();
  for (std::uint8_t m : r.mask) r.insidePixels += m != 0;
  return r;
}

}  // namespace emboss

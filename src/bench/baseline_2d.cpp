// The plain interval-pruning 2D renderer (baseline_2d.h), over the program's SSA graph (its nodes)
// with the format's own operations (frep/vm_ops.h), so that it computes what VmProgram computes.
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

// Per thread: the value buffers and the tapes of each level of the recursion.
struct Scratch {
  std::vector<Interval> iv;
  std::vector<double> dv;
  std::vector<std::uint8_t> choice;
  PruneScratch prune;
  std::vector<std::vector<Node>> tapes;  // tapes[d]: the tape pruned for depth d
};

// The tape's interval over the box; choice[i] says which operand of a min or max node decides it
// over the whole box (1: a, 2: b, 0: either may).
Interval evalInterval(const std::vector<Node>& t, Interval x, Interval y, Scratch& s) {
  s.iv.resize(t.size());
  s.choice.assign(t.size(), 0);
  for (size_t i = 0; i < t.size(); ++i) {
    const Node& n = t[i];
    s.iv[i] = applyNode<Interval>(n, s.iv.data(), x, y, Interval(0.0, 0.0));
    if (n.op == VmOp::kMin || n.op == VmOp::kMax) s.choice[i] = decidingOperand(n.op, s.iv[n.a], s.iv[n.b]);
  }
  return s.iv.back();
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

void cell(const Job& j, int depth, int x0, int y0, int n, Scratch& s, Counts& c) {
  if (x0 >= j.size || y0 >= j.size) return;
  const std::vector<Node>& tape = s.tapes[depth];
  const Interval ix(-j.halfWidth + x0 * j.pixel, -j.halfWidth + (x0 + n) * j.pixel);
  const Interval iy(j.halfWidth - (y0 + n) * j.pixel, j.halfWidth - y0 * j.pixel);
  const Interval v = evalInterval(tape, ix, iy, s);
  ++c.intervals;
  if (v.lo > 0.0) return fill(j, x0, y0, n, 0);    // outside
  if (v.hi < 0.0) return fill(j, x0, y0, n, 255);  // inside
  pruneNodes(tape, s.choice, s.prune, s.tapes[depth + 1]);  // tapes has a level for every depth (kTile / kLeaf halvings)
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
      for (size_t i = 0; i < leaf.size(); ++i) s.dv[i] = applyNode<double>(leaf[i], s.dv.data(), px, py, 0.0);
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

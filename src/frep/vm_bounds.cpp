// The box outside which a vm model is proven outside, by interval subdivision.
#include "frep/vm_model.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>
#include <vector>

#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

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

}  // namespace emboss

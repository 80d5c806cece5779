// The box outside which a vm model is outside: interval subdivision, samples where intervals are too loose.
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

  // The sampling rule for a cell intervals could not prove outside: it is outside when the model
  // is positive at every point of a 3 x 3 (x 3) grid over it, corners included, and at its centre
  // exceeds twice the cell's half diagonal times the steepest gradient seen at those points (a
  // distance-like field that far above zero cannot come back below it within the cell).
  bool sampledOutside(const Cell& c) {
    std::vector<Grad>& s = gradScratch_;
    s.resize(program_.slotCount());
    const int nz = dims_ == 3 ? 3 : 1;
    double steepest = 0.0, centre = 0.0, halfDiagonal2 = 0.0;
    for (int k = 0; k < dims_; ++k) halfDiagonal2 += 0.25 * (c.hi[k] - c.lo[k]) * (c.hi[k] - c.lo[k]);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < nz; ++k) {
          const double x = c.lo[0] + 0.5 * i * (c.hi[0] - c.lo[0]), y = c.lo[1] + 0.5 * j * (c.hi[1] - c.lo[1]);
          const double z = dims_ == 3 ? c.lo[2] + 0.5 * k * (c.hi[2] - c.lo[2]) : 0.0;
          const Grad g = program_.eval(Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, dims_ == 3 ? 1 : 0), s);
          if (!(g.v > 0.0)) return false;
          const double slope = std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz);
          if (!std::isfinite(slope)) return false;
          steepest = std::max(steepest, slope);
          if (i == 1 && j == 1 && (k == 1 || nz == 1)) centre = g.v;
        }
      }
    }
    return centre > 2.0 * steepest * std::sqrt(halfDiagonal2);
  }

  // The cells, all of one size, that interval arithmetic could not prove outside: the search box
  // is split in halves along every axis, level by level, keeping only unproven cells, until the
  // cells are as small as `finest` or the next level would hold more than `maxCells`.
  std::vector<Cell> unprovenCells(const Cell& box, double finest, std::size_t maxCells) {
    std::vector<Cell> cells{box}, unproven;
    for (;;) {
      unproven.clear();
      for (const Cell& c : cells)
        if (!provenOutside(c)) unproven.push_back(c);
      const std::size_t children = unproven.size() << dims_;
      if (unproven.empty() || unproven.front().hi[0] - unproven.front().lo[0] <= finest || children > maxCells)
        return unproven;
      cells.clear();
      for (const Cell& c : unproven) {
        for (int m = 0; m < (1 << dims_); ++m) {
          Cell d = c;
          for (int k = 0; k < dims_; ++k) {
            const double mid = 0.5 * (c.lo[k] + c.hi[k]);
            (((m >> k) & 1) ? d.lo[k] : d.hi[k]) = mid;
          }
          cells.push_back(d);
        }
      }
    }
  }

  std::size_t evaluations() const { return evaluations_; }

 private:
  const VmProgram& program_;
  int dims_;
  std::vector<Interval> scratch_;
  std::vector<Grad> gradScratch_;
  std::size_t evaluations_ = 0;
};

}  // namespace

Result<Box3> vmModelBounds(const VmProgram& program, double halfWidth) {
  if (program.size() == 0) return fail("the model is empty");
  if (!(halfWidth > 0.0) || !std::isfinite(halfWidth)) return fail("the search box must have a positive size");
  const int dims = program.usesZ() ? 3 : 2;
  const std::string where = program.sourceName().empty() ? std::string("the model") : "'" + program.sourceName() + "'";
  BoundsSearch search(program, dims);
  // Cell evaluations per extreme in phase 2: bounds the time for huge or pathological models.
  constexpr std::size_t kBudget = 20000;
  // Cells of one level in phase 1 (a few seconds at most for a model of thousands of clauses).
  constexpr std::size_t kMaxCells = 32768;

  Cell box;
  for (int k = 0; k < dims; ++k) box.lo[k] = -halfWidth, box.hi[k] = halfWidth;
  // Phase 1: a coarse box. Interval arithmetic over the whole search box is loose (a blend of
  // distances, a max of mirrored terms: the interval of a cell far from the model can stay
  // around zero while the model is a constant 5 there), so after subdividing as far as the cell
  // budget allows, a cell intervals could not prove outside is judged by samples
  // (BoundsSearch::sampledOutside). The coarse box is the union of the cells that may hold the
  // model (of all unproven cells should the samples rule every one out).
  const std::vector<Cell> unproven = search.unprovenCells(box, 2.0 * halfWidth / 4096.0, kMaxCells);
  if (unproven.empty()) {
    return fail(where + ": the model has no inside (it is positive everywhere within +-" + formatNumber(halfWidth) +
                " units)");
  }
  Cell region;
  bool any = false;
  const auto add = [&](const Cell& c) {
    for (int k = 0; k < dims; ++k) {
      region.lo[k] = any ? std::min(region.lo[k], c.lo[k]) : c.lo[k];
      region.hi[k] = any ? std::max(region.hi[k], c.hi[k]) : c.hi[k];
    }
    any = true;
  };
  for (const Cell& c : unproven)
    if (!search.sampledOutside(c)) add(c);
  if (!any)
    for (const Cell& c : unproven) add(c);
  for (int k = 0; k < dims; ++k) {
    if (region.lo[k] <= -halfWidth || region.hi[k] >= halfWidth) {
      return fail(where + ": the model's inside reaches the edge of the +-" + formatNumber(halfWidth) +
                  "-unit search box: it is unbounded or too large (check its sign: negative is inside)");
    }
  }
  // Phase 2: within the coarse box, each extreme by branch and bound to a tolerance relative to
  // the model's own size (conservative when the budget runs out).
  double extent = 0.0;
  for (int k = 0; k < dims; ++k) extent = std::max(extent, region.hi[k] - region.lo[k]);
  const double tol = std::max(extent * 1e-3, halfWidth * 1e-12);
  Cell next = region;
  for (int k = 0; k < dims; ++k) {
    for (const bool upper : {false, true}) {
      const std::optional<double> e = search.extreme(region, k, upper, tol, kBudget);
      if (!e) {
        // Only sampled points were inside; keep the coarse box.
        next = region;
        k = dims;
        break;
      }
      (upper ? next.hi[k] : next.lo[k]) = *e;
    }
  }
  region = next;
  // A margin of the final tolerance so surfaces never touch the box.
  Box3 out;
  out.x0 = region.lo[0] - tol, out.x1 = region.hi[0] + tol;
  out.y0 = region.lo[1] - tol, out.y1 = region.hi[1] + tol;
  if (dims == 3) out.z0 = region.lo[2] - tol, out.z1 = region.hi[2] + tol;
  return out;
}

}  // namespace emboss

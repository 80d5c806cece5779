// The field tracer's Lipschitz walk for several rays at once, one ray a SIMD lane (Highway, the
// instruction set chosen at run time). A lane takes the walk's plainest step -- outside every
// window and skip, D from the field, f the workpiece's own -- with the same operations in the same
// order as Renderer::endWalk() takes it, and stops wherever that walk would do anything else (a
// hit, a near miss creeping, a window or skip ahead, the field's edge). Its ray's walk then goes
// on alone from where the lane stopped, so every ray finds the hit it finds alone, bit for bit
// (docs/rendering.md, "Rays in lanes"; tests/render/walk_lanes_test.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "frep/box.h"
#include "render/field_lanes.h"
#include "util/portable_math.h"

namespace emboss {

class HeightField;

inline constexpr int kMaxWalkLanes = 8;

// What a lane's step reads besides its ray: the field and the workpiece (a plate or a disc).
struct WalkSheet {
  SampleLattice lattice;        // the field's samples (HeightField::lattice())
  Box2 domain;                  // where the field holds D (HeightField::domain())
  const HeightField* field = nullptr;  // its slope bounds (HeightField::bound())
  // 1: a plate 2w x 2h x 2d; 2: a disc of radius w, 2d thick; 4: an outline sheet 2d thick (W the
  // slab d - |z'| where that is at most its column's bound lo, or the column's hi where that is
  // negative; elsewhere the outline's program, which the ray's own walk evaluates).
  int kind = 1;
  double w = 0, h = 0, d = 0;
  // Outline sheets: the column map (Renderer::ColumnMap), nx x ny blocks of `size` from (x0, y0).
  // A block the outline crosses or comes near (subOf[k] = s >= 0) has kSub x kSub sub-cells of
  // their own bounds, at subLo / subHi[s * kSub * kSub + sj * kSub + si].
  struct Columns {
    static constexpr int kSub = 8;
    double x0 = 0, y0 = 0, inv = 1;
    int nx = 0, ny = 0;
    const float* lo = nullptr;
    const float* hi = nullptr;
    const std::int32_t* subOf = nullptr;
    const float* subLo = nullptr;
    const float* subHi = nullptr;
    struct Bounds {
      float lo, hi;
    };
    // The bounds at (x, y): its sub-cell's where its block has them, else its block's; beyond the
    // map (-inf, -1) (W < 0 there). The one lookup of the scalar walk and the lanes.
    // (Inlined into the lanes' step, compiled for another instruction set: a call a lane cost 2 %
    // of a punch on an outline sheet.)
    [[gnu::always_inline]] Bounds at(double x, double y) const {
      const double u = (x - x0) * inv, v = (y - y0) * inv;
      const int i = floorToInt(u), j = floorToInt(v);
      if (i < 0 || j < 0 || i >= nx || j >= ny) return {-std::numeric_limits<float>::infinity(), -1.0f};
      const size_t k = static_cast<size_t>(j) * nx + i;
      const std::int32_t s = subOf ? subOf[k] : -1;
      if (s < 0) return {lo[k], hi[k]};
      const size_t c = subIndex(s, subCell(u, i), subCell(v, j));
      return {subLo[c], subHi[c]};
    }
    // Where sub-cell (si, sj) of the blocks' s-th set of sub-cells is held.
    static size_t subIndex(std::int32_t s, int si, int sj) {
      return static_cast<size_t>(s) * (kSub * kSub) + static_cast<size_t>(sj) * kSub + si;
    }
    // The sub-cell along one axis of a point at u blocks from the map's origin in block i.
    static int subCell(double u, int i) { return std::clamp(floorToInt((u - i) * kSub), 0, kSub - 1); }
  } columns;
};

// The rays in the lanes and their walks' states, a value per lane (unused lanes: state 0).
struct WalkLanes {
  // 0 empty; walking: 1 at q, 4 bracketing a hit at q; stopped: 2, 3 with f at q (in f).
  alignas(64) double state[kMaxWalkLanes];
  alignas(64) double ox[kMaxWalkLanes], oy[kMaxWalkLanes], oz[kMaxWalkLanes];  // the ray
  alignas(64) double dx[kMaxWalkLanes], dy[kMaxWalkLanes], dz[kMaxWalkLanes];
  alignas(64) double h8[kMaxWalkLanes];       // grid points at t = q h8
  alignas(64) double invStep[kMaxWalkLanes];  // 1 / (kStepRate h8)
  alignas(64) double invRay[kMaxWalkLanes];   // 1 / (lf h8), lf the ray's slope bound
  alignas(64) double q0[kMaxWalkLanes], q1[kMaxWalkLanes];  // the clip's start and end
  alignas(64) double window[kMaxWalkLanes];   // the next window's first point (q1 + 1: none)
  alignas(64) double end[kMaxWalkLanes];      // the lane stops on reaching it (a window, a skip, q1)
  // A ball's far window the lane walks through (farLo > farHi: none; Renderer::SetOp::farRaise):
  // inside it a step is shortened by farRaise (the window's raise and its margin, as the ray's own
  // walk has it) and goes at most to `after`, the first window point after it; where it cannot
  // step, and at a near miss creeping, the lane stops without f (f there is not W's: the ray's own
  // walk evaluates it). The lane ends at farHi + 1 at the latest.
  alignas(64) double farLo[kMaxWalkLanes], farHi[kMaxWalkLanes], farRaise[kMaxWalkLanes], after[kMaxWalkLanes];
  int farLanes = 0;  // how many lanes have a far window (none: the step reads none of the above)
  // lipschitzAlong()'s terms of the direction: d.x where d.x >= 0 (else 0), d.x where d.x < 0
  // (else 0), the same of d.y, and the workpiece's term of (d.x, d.y).
  alignas(64) double ax[kMaxWalkLanes], bx[kMaxWalkLanes], ay[kMaxWalkLanes], by[kMaxWalkLanes];
  alignas(64) double side[kMaxWalkLanes];
  // The walk's state (Renderer::Walk), integers held as doubles (exactly: below 2^53).
  alignas(64) double q[kMaxWalkLanes], prevQ[kMaxWalkLanes], prevF[kMaxWalkLanes], shortSteps[kMaxWalkLanes];
  alignas(64) double f[kMaxWalkLanes];  // f at q, in states 3 and 4
  alignas(64) double l[kMaxWalkLanes];  // the value f's Lipschitz bound holds for there (f, or the slab)
};

// How many rays a step walks at once here (1: no SIMD; the caller walks them alone).
int walkLaneCount();
// One step of each walking lane (states 1 and 4); a lane that stops gets state 2 or 3. Adds the
// steps taken and the function evaluations made to `steps` and `evaluations`, and the steps taken
// inside balls' far windows to `farSteps`.
void walkLanes(const WalkSheet& sheet, WalkLanes& lanes, std::uint64_t& steps, std::uint64_t& evaluations,
               std::uint64_t& farSteps);

// Renderer::fieldNormal() of a plate, a disc or an outline sheet (where W is its slab: the caller
// checks) where no set operation acts, at the hits (x[k],
// y[k], z[k]) with D and its slopes there (dv, dgx, dgy: HeightField::valuesAndGradients()), into
// (nx[k], ny[k], nz[k]), for the first whole vectors of lanes of the n hits; returns how many were
// done (the rest is the caller's). The same bits as fieldNormal() (tests/render/walk_lanes_test.cpp).
int sheetNormalLanes(const WalkSheet& sheet, const double* x, const double* y, const double* z, const double* dv,
                     const double* dgx, const double* dgy, int n, double* nx, double* ny, double* nz);

}  // namespace emboss

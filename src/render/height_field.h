// The renderer's cache of the sheet's displacement D(x, y): fine samples, C1 interpolation, bounds.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "frep/box.h"
#include "frep/operation.h"
#include "render/field_lanes.h"
#include "render/thread_pool.h"

namespace emboss {

// In the sheet model every offset moves the sheet along z by a function of (x, y) alone, and the
// model is f(P) = W(x, y, z - D(x, y)) (with the set operations on top), D being the sum of the
// active offsets. D changes only under a new stroke's support, so the renderer keeps it here
// instead of summing tens of kernels at every step of every ray (docs/rendering.md).
//
// Samples lie on a lattice x_i = x0 + i s, y_j = y0 + j s fixed by the workpiece alone. Each holds
// D, dD/dx and dD/dy summed in float from the exact kernels (PreparedOp::offset over Grad), in
// operation index order starting from 0, and a twist d2D/dxdy by central differences of the
// stored slopes. Between samples D is the bicubic Hermite patch of those four values per corner:
// C1, exact for cubics, error O(s^4) in value and O(s^3) in slope (measured in
// tests/render/height_field_test.cpp, documented in docs/rendering.md).
//
// Bit-exactness: a sample's bits depend only on its position and on the active offsets whose
// support contains it, summed in index order, whether it was filled by a full build, by
// appending operations one at a time (add()), or recomputed from scratch after an undo
// (recompute()). The bounds -- a min/max pyramid over blocks of 8 x 8 cells of the value and of
// both slopes, each cell bounded by the convex hull of its patch's Bezier net -- are
// conservative and only ever used to skip work.
//
// Not thread-safe against its own updates; the const queries may run concurrently.
class HeightField {
 public:
  // Rectangle of sample indices, inclusive.
  struct SampleRect {
    int i0 = 0, j0 = 0, i1 = -1, j1 = -1;
    bool empty() const { return i1 < i0 || j1 < j0; }
    long count() const { return empty() ? 0 : static_cast<long>(i1 - i0 + 1) * (j1 - j0 + 1); }
  };
  // Conservative bounds of the interpolated D and of its slopes over a box.
  struct Bound {
    double lo = 0, hi = 0;      // D
    double gxlo = 0, gxhi = 0;  // dD/dx
    double gylo = 0, gyhi = 0;  // dD/dy
  };

  static constexpr int kBlock = 8;  // cells per pyramid leaf, each way

  // Sets up an all-zero lattice of spacing `spacing` covering `domain`, its origin at the domain's
  // lower corner (so it depends on nothing but the domain). With `cavity`, the field also keeps the
  // shading's cavity depth per sample (cavityDepth()).
  void configure(const Box2& domain, double spacing, bool cavity = false);
  // Sets up an all-zero lattice covering `domain` whose samples are samples of `lattice` (the same
  // spacing, the same positions bit for bit: sampleX(i) is lattice.sampleX(i + its first column)),
  // so values found on that lattice can be added here (add(const OffsetValues&)).
  void configureOn(const HeightField& lattice, const Box2& domain);
  void clear();
  bool configured() const { return nx_ > 0; }

  double spacing() const { return s_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double sampleX(int i) const { return gx0_ + (i + gi_) * s_; }
  double sampleY(int j) const { return gy0_ + (j + gj_) * s_; }
  size_t memoryBytes() const;
  // The box the interpolation covers: D is defined (by the field) inside it.
  Box2 domain() const { return {x0_, y0_, x0_ + (nx_ - 1) * s_, y0_ + (ny_ - 1) * s_}; }
  bool contains(double x, double y) const { return x >= x0_ && y >= y0_ && x <= xMax_ && y <= yMax_; }
  bool containsBox(const Box2& b) const { return b.x0 >= x0_ && b.y0 >= y0_ && b.x1 <= xMax_ && b.y1 <= yMax_; }
  SampleRect all() const { return {0, 0, nx_ - 1, ny_ - 1}; }

  // The samples inside a box (the same rule for every caller, so an operation always touches the
  // same samples); empty when the box misses the lattice.
  SampleRect samplesIn(const Box2& b) const;
  static SampleRect intersect(const SampleRect& a, const SampleRect& b);
  static SampleRect grow(const SampleRect& r, int n);
  // The smallest rectangle holding both (an empty one holds nothing).
  static SampleRect unite(const SampleRect& a, const SampleRect& b);
  SampleRect clamp(const SampleRect& r) const;

  // An offset's values (D and its slopes, before they are rounded into a sample) at the samples of
  // a rectangle, in the lattice's indices; kept by add() for fields configureOn() that lattice.
  struct OffsetValues {
    double x0 = 0, y0 = 0, s = 0;  // the lattice: its origin and spacing
    SampleRect r;
    std::vector<Grad> g;  // row by row
  };
  // Adds an offset operation's contribution to the samples inside its support (an append).
  // With a pool, rows of samples are shared out (every sample's arithmetic is the same).
  void add(const PreparedOp& op, ThreadPool* pool = nullptr);
  // The same over the samples of `rows` only (those of its support within it): an append made a
  // band of rows at a time; every sample gets the bits add() gives it.
  // With `keep`, the values added are also kept there (on this field's lattice): they extend the
  // rows it holds when they are the next rows of the same columns, else replace them.
  void add(const PreparedOp& op, const SampleRect& rows, ThreadPool* pool = nullptr, OffsetValues* keep = nullptr);
  // Adds `values` (found for `op` on the lattice this field was configureOn()) to the samples of
  // `rows` that add(op, rows) would change: the same bits. False (and nothing added) when they do
  // not hold them all or were found on another lattice.
  bool add(const PreparedOp& op, const OffsetValues& values, const SampleRect& rows);
  // A rectangle of this field's samples in its lattice's indices, and back (clamped to this field).
  SampleRect toLattice(const SampleRect& r) const { return {r.i0 + gi_, r.j0 + gj_, r.i1 + gi_, r.j1 + gj_}; }
  SampleRect fromLattice(const SampleRect& r) const { return clamp({r.i0 - gi_, r.j0 - gj_, r.i1 - gi_, r.j1 - gj_}); }
  // Sets the samples of `r` to the sum of `ops` (the offsets that may reach r, ascending index).
  void recompute(const SampleRect& r, std::span<const PreparedOp* const> ops);
  // The samples of r as they are, and putting them back (then finish() over r): an append
  // undone exactly.
  struct Saved;
  void save(const SampleRect& r, Saved& out) const;
  void restore(const Saved& saved);
  // After add()/recompute() over r: refreshes the twists around r and the pyramid above it.
  void finish(const SampleRect& r, ThreadPool* pool = nullptr);
  // Right after configure() (every sample zero: no operation moves the sheet): the bounds that
  // recompute() and finish() over all() would give, without visiting the samples.
  void finishFlat();

  // D at (x, y) (inside domain()); with its gradient.
  double value(double x, double y) const;
  // A point's cell on this field's lattice and the Hermite basis there, found once for every field
  // on that lattice (this one and those configureOn() it): value(const LatticePoint&) of any of
  // them is its value(x, y), bit for bit, without finding them again.
  struct LatticePoint {
    double x = 0, y = 0;
    int ci = 0, cj = 0;  // the lattice's cell, unclamped
    double bu[4] = {}, bv[4] = {};  // the basis along x and y: h0, h1, g0, g1
  };
  LatticePoint latticePoint(double x, double y) const;
  double value(const LatticePoint& p) const;
  void valueAndGradient(double x, double y, double& v, double& gx, double& gy) const;
  // valueAndGradient() at n points at once (SIMD lanes where whole vectors of them fill; the same
  // bits).
  void valuesAndGradients(const double* x, const double* y, int n, double* v, double* gx, double* gy) const;
  // D bilinear between the four samples around (x, y) (clamped to the domain): about a third of
  // value()'s work, for what needs D only roughly (the shading's cavity term).
  double valueBilinear(double x, double y) const;
  // The shading's cavity depth (shading.h: the mean of D on the ring of six at kCavityReach, less D)
  // interpolated bilinearly from its values at the samples, which finish() keeps (when configured
  // with `cavity`; 0 otherwise). One lookup a hit instead of seven scattered ones. A sample's depth
  // reads D within cavityReachSamples() of it, so finish(r) refreshes it that far around r.
  double cavityDepth(double x, double y) const;
  int cavityReachSamples() const { return cavityReach_; }
  // cavityDepth() at n points at once (SIMD lanes where whole vectors of them fill; the same bits).
  void cavityDepths(const double* x, const double* y, int n, double* out) const;
  // The samples as the lanes read them (field_lanes.h; configured fields only).
  SampleLattice lattice() const { return {x0_, y0_, s_, invS_, nx_, ny_, &samples_[0].d}; }
  // The pyramid's leaves (kBlock x kBlock cells each) as bound() reads them: six floats a leaf
  // (the bounds of D, dD/dx and dD/dy, low and high), `width` leaves a row.
  const float* leaves(int& width) const {
    static_assert(sizeof(Node) == 6 * sizeof(float));
    width = levels_[0].w;
    return &levels_[0].nodes[0].lo;
  }
  // Bounds over a box inside domain() (callers check containsBox()).
  Bound bound(const Box2& b) const;
  // Bounds over a box inside domain() from every leaf under it: tighter than bound() (which reads
  // at most 2 x 2 nodes of the level where they hold the box), dearer for a wide box.
  Bound leafBound(const Box2& b) const;
  // Bounds over the whole lattice.
  Bound rootBound() const;

  // For tests: the stored sample (D, dD/dx, dD/dy, twist).
  struct Sample {
    float d = 0, dx = 0, dy = 0, dxy = 0;
  };
  const Sample& sample(int i, int j) const { return samples_[static_cast<size_t>(j) * nx_ + i]; }
  // For tests: the cavity depth kept at a sample (0 without `cavity`).
  float cavitySample(int i, int j) const { return cavity_.empty() ? 0.0f : cavity_[static_cast<size_t>(j) * nx_ + i]; }
  struct Saved {
    SampleRect r;
    std::vector<Sample> samples;
  };

 private:
  // The leaves under a box: columns a0..a1, rows b0..b1 of levels_[0] (clamped to the lattice).
  void leavesUnder(const Box2& b, int& a0, int& a1, int& b0, int& b1) const;
  struct Node {
    float lo, hi, gxlo, gxhi, gylo, gyhi;
  };
  struct Level {
    int w = 0, h = 0;
    std::vector<Node> nodes;
  };
  Sample& at(int i, int j) { return samples_[static_cast<size_t>(j) * nx_ + i]; }
  void cellOf(double x, double y, int& i, int& j, double& u, double& v) const;
  void addTo(const PreparedOp& op, const SampleRect& r, OffsetValues* keep = nullptr);
  void updateTwist(const SampleRect& r);
  void updateLeaves(int la0, int lb0, int la1, int lb1);
  void updateLevels(int la0, int lb0, int la1, int lb1);
  void updateCavity(const SampleRect& r);
  // A lattice's values (get(k) of sample k = j nx + i, a float) bilinear at (x, y), clamped to the
  // domain.
  template <class Get>
  double bilinear(double x, double y, const Get& get) const;
  // A leaf's bounds from the extremes of its patches' Bezier nets (values, u and v derivatives).
  Node leafNode(double lo, double hi, double uLo, double uHi, double vLo, double vHi) const;

  double x0_ = 0, y0_ = 0, s_ = 1, invS_ = 1, xMax_ = 0, yMax_ = 0;
  int nx_ = 0, ny_ = 0;
  // The samples' positions: sample (i, j) of this field is sample (i + gi_, j + gj_) of the lattice
  // whose origin is (gx0_, gy0_) (itself, gi_ = gj_ = 0, unless configureOn() another).
  double gx0_ = 0, gy0_ = 0;
  int gi_ = 0, gj_ = 0;
  std::vector<Sample> samples_;
  std::vector<Level> levels_;  // 0: leaves of kBlock x kBlock cells; the last: one node
  // The cavity depth per sample (empty without `cavity`), and the ring's bilinear taps in samples
  // (offsets and weights, the same for every sample away from the lattice's edges).
  struct Tap {
    int di, dj;
    float w;
  };
  std::vector<float> cavity_;
  std::vector<Tap> taps_;
  std::vector<float> tapWeights_;  // taps_'s weights alone, in their order (for tapSumsLanes())
  int tapLo_[2] = {0, 0}, tapHi_[2] = {0, 0};  // the taps' least and greatest offsets along i and j
  int cavityReach_ = 0;
};

}  // namespace emboss

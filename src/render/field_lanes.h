// The height field's reads at a row of hits at once, in SIMD lanes (Highway, the instruction set
// chosen at run time, as src/render/leaf_bounds.cpp): each lane the arithmetic of the one-point
// read in the same order, so the same bits (tests/render/field_lanes_test.cpp).
#pragma once

namespace emboss {

// A lattice of floats, one a sample, row by row: sample (i, j) at x0 + i / invS, y0 + j / invS.
struct FloatLattice {
  double x0 = 0, y0 = 0, invS = 1;
  int nx = 0, ny = 0;  // at least 2 each
  const float* values = nullptr;
};

// HeightField::bilinear over the lattice at (x[k], y[k]) into out[k], for the first whole vectors
// of lanes of the n points; returns how many points were done (the rest is the caller's).
int bilinearLanes(const FloatLattice& lattice, const double* x, const double* y, int n, double* out);

// The field's samples (d, dD/dx, dD/dy, twist: four floats a sample, row by row) on a lattice
// of spacing s = 1 / invS.
struct SampleLattice {
  double x0 = 0, y0 = 0, s = 1, invS = 1;
  int nx = 0, ny = 0;  // at least 2 each
  const float* samples = nullptr;
};

// HeightField::valueAndGradient at (x[k], y[k]) into v[k], gx[k], gy[k], for the first whole
// vectors of lanes of the n points; returns how many points were done (the rest is the caller's).
int hermiteLanes(const SampleLattice& lattice, const double* x, const double* y, int n, double* v, double* gx,
                 double* gy);

// A row of the field's cavity depths (HeightField::updateCavity): for every k < n, in float,
// out[k] = ((0 + w[0] rows[0][k]) + w[1] rows[1][k] + ... + w[taps - 1] rows[taps - 1][k]) - own[k],
// the taps summed in their order; whole vectors of lanes first, the rest one at a time with the
// same operations (no fused multiply-add: -ffp-contract=off), so the same bits wherever a sample
// falls.
void tapSumsLanes(const float* const* rows, const float* w, int taps, const float* own, int n, float* out);

}  // namespace emboss

// The height field's batch work after its samples, in SIMD lanes (Highway, the instruction set
// chosen at run time, as src/frep/path_rows.cpp): the bounds of a pyramid leaf (of its bicubic
// Hermite patches and their slopes, from the convex hulls of their Bezier nets; HeightField::
// updateLeaves) a row of patches at a time, the samples they read, and the twists a row at a time.
#pragma once

namespace emboss {

// One leaf's samples, by rows (c, then a): the value, a third of each scaled slope and a ninth of
// the scaled twist (s dx / 3, s dy / 3, s^2 dxy / 9), as HeightField computes them.
struct LeafSamples {
  static constexpr int kSide = 9;     // samples a leaf of 8 x 8 patches spans each way
  static constexpr int kStride = 16;  // a row's doubles (the widest loads end within it)
  alignas(64) double d[kSide][kStride];
  alignas(64) double x[kSide][kStride];
  alignas(64) double y[kSide][kStride];
  alignas(64) double t[kSide][kStride];
};

// The net's values' and its differences' extremes over the leaf's patches (patchesU x patchesV,
// 1 to 8 each): the same numbers, bit for bit, as the nets worked out patch by patch.
struct LeafNetBounds {
  double lo, hi;    // the net's values
  double uLo, uHi;  // 3 (b[u + 1][v] - b[u][v])
  double vLo, vHi;  // 3 (b[u][v + 1] - b[u][v])
};
LeafNetBounds leafNetBounds(const LeafSamples& s, int patchesU, int patchesV);

// Fills s from a leaf's samples as the height field stores them (d, dx, dy, dxy floats in a row,
// `rowFloats` floats from a row to the next), (samplesU x samplesV, 1 to 9 each), spacing `spacing`:
// d, spacing dx / 3, spacing dy / 3 and spacing^2 dxy / 9 in doubles, the operations in that order
// (the same bits as one sample at a time).
void loadLeafSamples(const float* first, long rowFloats, int samplesU, int samplesV, double spacing, LeafSamples& s);

// The twists of n samples inside a row, from their neighbours' slopes (samples stored as above:
// `row` the first of them, `below` and `above` the samples under it in the rows j - 1 and j + 1):
// out[k] = float(0.5 ((above.dx - below.dx) / den + (next.dy - previous.dy) / den)), in doubles in
// that order (the same bits as one sample at a time).
void twistRow(const float* below, const float* row, const float* above, int n, double den, float* out);

}  // namespace emboss

// The metal's shading for a row of hits at once, in SIMD lanes (Highway, the instruction set chosen
// at run time, as src/render/leaf_bounds.cpp): shadeMetal() without a patina, lane by lane the same
// arithmetic in the same order, so the same bits as one call a hit (tests/render/shade_lanes_test.cpp).
#pragma once

#include <cmath>
#include <cstdint>

namespace emboss {

// The planishing hammer's dimples, as shading.cpp's hammerGradient() and the lanes both work them
// out: one shallow round dent a cell of a kCell lattice, of radius kRadius, its centre at
// (i + kOffset + kJitter (h & 0xFFFF), j + kOffset + kJitter (h >> 16)) kCell for the cell's hash h
// (kHash: the multipliers of the indices, then of the two mixing steps).
struct Hammer {
  static constexpr double kCell = 1.6, kRadius = 1.25, kOffset = 0.15;
  static constexpr double kInvR2 = 1.0 / (kRadius * kRadius), kJitter = 0.7 / 65535.0;
  static constexpr std::uint32_t kHash[4] = {0x9E3779B1u, 0x85EBCA77u, 0x2C1B3C6Du, 0x297A2D39u};
  // The dimples' profile h(d) = -A (1 - d^2/R^2)^2 has its largest slope 16 A / (3 sqrt(3) R) at
  // d = R / sqrt(3): for dimples of largest slope `slope`, their gradient is k0 (1 - d^2/R^2) d.
  static double k0(double slope) {
    const double amp = slope * 3.0 * std::sqrt(3.0) * kRadius / 16.0;
    return 4.0 * amp * kInvR2;
  }
};

// Hits to shade, as arrays of their coordinates (the renderer fills one a tile row at a time).
// Every array holds kCapacity doubles, so that whole vectors of lanes can be read past n.
struct ShadeBatch {
  static constexpr int kCapacity = 64;
  int n = 0;
  alignas(64) double px[kCapacity], py[kCapacity], pz[kCapacity];  // the point
  alignas(64) double nx[kCapacity], ny[kCapacity], nz[kCapacity];  // its unit normal
  alignas(64) double vx[kCapacity], vy[kCapacity], vz[kCapacity];  // the unit view, from the eye
  alignas(64) double cavity[kCapacity];                           // cavityOfDepth(), 0..1
  alignas(64) double r[kCapacity], g[kCapacity], b[kCapacity];     // out: linear RGB
  bool full() const { return n == kCapacity; }
};

// An octahedral map of directions (shading.cpp's SphereMap): size x size texels of three floats.
struct SphereTexels {
  int size = 0;
  const float* rgb = nullptr;
};

// What shadeMetal() reads besides the hit, as plain numbers.
struct MetalLaneParams {
  double hammer = 0.0;  // the dimples' largest slope (0: none)
  // The lobe's response by view cosine: bins + 1 entries of single scattering (3 doubles each) and
  // of the albedo with Fresnel 1, and the multiple scattering's tint.
  int bins = 0;
  const double* single = nullptr;
  const double* albedo = nullptr;
  double fms[3] = {0, 0, 0};
  SphereTexels specular, irradiance;
  double frontZ = 0.0, tingeDepth = 1.0;
  double tingeStrength = 0.0;  // the scene's tinge (0: none)
  double tingeColor[3] = {1, 1, 1};
};

// Shades the batch's n hits into r, g, b (the lanes past n are filled with a harmless hit first).
void shadeMetalLanes(const MetalLaneParams& params, ShadeBatch& batch);

}  // namespace emboss

// Shading: how polished metal under a museum's lights looks, from a surface point and its normal.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include "tools/metal.h"

namespace emboss {

// Everything the shading needs that does not change from pixel to pixel.
struct ShadingParams {
  Metal metal;
  Tinge tinge;
  double frontZ = 0.5;      // z of the untouched front face (the tinge gathers below it)
  double tingeDepth = 0.6;  // mm below the front face where the tinge is at full strength
};
// The shading of a sheet whose untouched front face is at frontZ, its metal and tinge by name
// (names metalByName() and tingeByName() know).
ShadingParams sheetShading(std::string_view metal, std::string_view tinge, double frontZ);

// Linear RGB of a surface point seen along `view` (unit, from the eye) with unit normal `n`;
// `cavity` (0 open metal .. 1 a deep groove, from cavityAt()) hides the lights and gathers the tinge.
// Deterministic: depends on nothing but its arguments. The first call for a metal builds its tables
// (a prefiltered environment and the lobe's albedo, tens of milliseconds); later calls share them.
// How much of each tinge the patina brush left at a point (index as tinges(); 0 unused), 0..1.
struct Patina {
  std::array<double, 5> amount{};
  // Whether any tinge is there (none: shadeMetal() gives the same bits as without a patina).
  bool any() const {
    for (size_t i = 1; i < amount.size(); ++i)
      if (amount[i] > 0) return true;
    return false;
  }
};
// `patina` (optional) tints the metal like the scene's tinge, settling into the hollows: the colour
// without it times patinaTint().
glm::dvec3 shadeMetal(const ShadingParams& s, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& view,
                      double cavity = 0.0, const Patina* patina = nullptr);

// The factor a patina tints a colour by at a hit at height z with that cavity term.
glm::dvec3 patinaTint(const ShadingParams& s, double z, double cavity, const Patina& patina);
// A tinge's factor for `amount` of it, `floor` of which stays on the high points (`settle` 0).
glm::dvec3 tingeMix(const Tinge& t, double amount, double floor, double settle);
struct ShadeBatch;
// shadeMetal() for a batch of hits (render/shade_lanes.h) without a patina, in SIMD lanes: the
// same bits, hit by hit, as one call each.
void shadeMetal(const ShadingParams& s, ShadeBatch& batch);

class ThreadPool;
// Builds the metal's tables now, shared out over `pool` (else the first shadeMetal() call builds
// them alone); Renderer::setShading() calls it. Not to be called from inside a pool job.
void prepareShading(const Metal& metal, ThreadPool* pool);

// The fraction of a white surrounding's light the metal's lobe returns toward a viewer at cosine
// `cosView` from the normal: single scattering with the exact Fresnel term plus the multiple
// scattering compensation. For a perfect mirror material (Fresnel 1) it is 1 at every angle.
glm::dvec3 metalAlbedo(const Metal& metal, double cosView);

// How far (x, y) lies in a cavity of the displacement D: 0 on open or convex metal, towards 1 at
// the bottom of a groove or at the foot of a raised rim. Reads D within kCavityReach of (x, y).
inline constexpr double kCavityReach = 1.1;  // mm
// The ring's six directions (unit vectors, every 60 degrees), and the depth below the ring's mean
// that is half occluded; the POV-Ray export writes the same term as a function of its own.
inline constexpr double kCavityRing[6][2] = {{1, 0}, {0.5, 0.8660254037844386}, {-0.5, 0.8660254037844386},
                                             {-1, 0}, {-0.5, -0.8660254037844386}, {0.5, -0.8660254037844386}};
inline constexpr double kCavityHalfDepth = 0.1;  // mm
template <class D>
double cavityAt(double x, double y, const D& displacement);
// The mean of D on that ring around (x, y) (the cavity's depth is it less D at the point).
template <class D>
double cavityRingMean(double x, double y, const D& displacement) {
  double ring = 0.0;
  for (const auto& u : kCavityRing) ring += displacement(x + kCavityReach * u[0], y + kCavityReach * u[1]);
  return ring / 6.0;
}
// The cavity term of a depth below the ring's mean (the renderer keeps the depth per sample of its
// field: HeightField::cavityDepth()).
inline double cavityOfDepth(double depth) { return depth <= 0 ? 0.0 : depth / (depth + kCavityHalfDepth); }
// Radiance of the studio the metal reflects, by direction (x right, y up the bench, z toward the
// viewer's side of the sheet), in linear RGB: what every metal is lit by (and what the studio
// export gives a path tracer).
glm::dvec3 studioEnvironment(const glm::dvec3& d);
// The backdrop (dark velvet) behind the piece, for pixel (x, y) of a w x h image.
glm::dvec3 backdrop(int x, int y, int w, int h);
// Linear to 8-bit sRGB through a camera-like curve: a toe (c^2 / (c + 0.03)) that deepens the
// shadows and keeps the metal's colour in them, and a gentle shoulder (c / (1 + c / 4)) so
// highlights do not clip harshly.
std::array<std::uint8_t, 3> toSrgb8(const glm::dvec3& linear);

template <class D>
double cavityAt(double x, double y, const D& displacement) {
  // D at the point against its mean on a ring of six at kCavityReach: a groove, a dent, the foot
  // of a raised rim. The renderer keeps this depth at the samples of its field and interpolates it
  // (HeightField::cavityDepth: one lookup a hit instead of seven scattered ones).
  const double d = displacement(x, y);
  return cavityOfDepth(cavityRingMean(x, y, displacement) - d);
}

}  // namespace emboss

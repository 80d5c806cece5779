// Metals: how each one looks (optical constants, roughness) and feels under the tool (ductility, hardness).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace emboss {

// Wavelengths (nm) at which the red, green and blue channels take a metal's optical constants.
inline constexpr std::array<double, 3> kChannelWavelengths = {630.0, 532.0, 465.0};

struct Metal {
  std::string_view name;
  // Measured complex refractive index n + ik at kChannelWavelengths (red, green, blue), interpolated
  // from the tables behind pbrt-v4's named spectra metal-Cu, metal-CuZn, metal-Ag and metal-Al
  // (src/pbrt/util/spectrum.cpp); docs/rendering.md gives the table.
  std::array<double, 3> eta;
  std::array<double, 3> k;
  double roughness;   // microfacet roughness of a lightly polished sheet (GGX alpha)
  double hammer;      // largest slope of the planishing hammer's dimples in the sheet's face
  double ductility;   // 0..1: how far the sheet yields to a given pressure (copper 1)
  double hardness;    // 0..1: how much material a blending punch gathers (the paper's a1)
  // Linear-light reflectance at normal incidence, ((n-1)^2 + k^2) / ((n+1)^2 + k^2) per channel.
  std::array<double, 3> f0;
};

// copper, brass, silver, aluminium.
const std::array<Metal, 4>& metals();
std::optional<Metal> metalByName(std::string_view name);

// Unpolarised Fresnel reflectance of a conductor n + ik in air at incidence cosine `cosTheta`.
double fresnelConductor(double cosTheta, double eta, double k);

// The chemical tinges of the paper (patinas): none, black, brown, green, golden.
struct Tinge {
  std::string_view name;
  std::array<double, 3> color{1.0, 1.0, 1.0};  // linear-light tint multiplied into the reflectance
  double strength = 0.0;                        // 0..1, how much of the tint shows in the hollows
};
const std::array<Tinge, 5>& tinges();
std::optional<Tinge> tingeByName(std::string_view name);

}  // namespace emboss

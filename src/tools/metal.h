// Metals: how each one looks (reflectance, roughness) and feels under the tool (ductility, hardness).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace emboss {

struct Metal {
  std::string_view name;
  // Linear-light normal-incidence reflectance (F0), from measured optical constants.
  std::array<double, 3> f0;
  double roughness;   // microfacet roughness of a lightly polished sheet (GGX alpha)
  double ductility;   // 0..1: how far the sheet yields to a given pressure (copper 1)
  double hardness;    // 0..1: how much material a blending punch gathers (the paper's a1)
};

// copper, brass, silver, aluminium.
const std::array<Metal, 4>& metals();
std::optional<Metal> metalByName(std::string_view name);

// The chemical tinges of the paper (patinas): none, black, brown, green, golden.
struct Tinge {
  std::string_view name;
  std::array<double, 3> color;  // linear-light tint multiplied into the reflectance
  double strength;              // 0..1, how much of the tint shows in the hollows
};
const std::array<Tinge, 5>& tinges();
std::optional<Tinge> tingeByName(std::string_view name);

}  // namespace emboss

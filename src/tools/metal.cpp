// The metal and tinge tables.
#include "tools/metal.h"

namespace emboss {

const std::array<Metal, 4>& metals() {
  // F0 values are the usual linear-sRGB reflectances of the pure metals (brass: Cu-Zn alloy).
  static const std::array<Metal, 4> kMetals = {{
      {"copper", {0.955, 0.638, 0.538}, 0.28, 1.00, 0.45},
      {"brass", {0.910, 0.778, 0.423}, 0.25, 0.70, 0.75},
      {"silver", {0.972, 0.960, 0.915}, 0.20, 0.90, 0.55},
      {"aluminium", {0.913, 0.922, 0.924}, 0.32, 0.85, 0.35},
  }};
  return kMetals;
}

std::optional<Metal> metalByName(std::string_view name) {
  for (const Metal& m : metals())
    if (m.name == name) return m;
  if (name == "aluminum") return metals()[3];
  return std::nullopt;
}

const std::array<Tinge, 5>& tinges() {
  static const std::array<Tinge, 5> kTinges = {{
      {"none", {1.0, 1.0, 1.0}, 0.0},
      {"black", {0.06, 0.055, 0.05}, 0.85},
      {"brown", {0.35, 0.16, 0.07}, 0.75},
      {"green", {0.20, 0.45, 0.30}, 0.70},
      {"golden", {1.00, 0.76, 0.30}, 0.60},
  }};
  return kTinges;
}

std::optional<Tinge> tingeByName(std::string_view name) {
  for (const Tinge& t : tinges())
    if (t.name == name) return t;
  return std::nullopt;
}

}  // namespace emboss

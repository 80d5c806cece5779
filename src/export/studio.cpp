// Radiance RGBE writer and the studio's description.
#include "export/studio.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "render/shading.h"
#include "tools/metal.h"

namespace emboss {

namespace {

std::array<unsigned char, 4> rgbe(const glm::dvec3& c) {
  const double m = std::max({c.r, c.g, c.b});
  if (m < 1e-32) return {0, 0, 0, 0};
  int e;
  const double f = std::frexp(m, &e) * 256.0 / m;
  return {static_cast<unsigned char>(std::max(0.0, c.r) * f), static_cast<unsigned char>(std::max(0.0, c.g) * f),
          static_cast<unsigned char>(std::max(0.0, c.b) * f), static_cast<unsigned char>(e + 128)};
}

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

Status writeStudio(const Scene& scene, const std::string& hdrPath, const std::string& jsonPath, int width) {
  const auto metal = metalByName(scene.metal);
  const auto tinge = tingeByName(scene.tinge);
  if (!metal) return fail("unknown metal '" + scene.metal + "'");
  const int w = std::max(16, width), h = w / 2;
  // Flat (not run-length encoded) scanlines: every Radiance reader takes them.
  std::string out = "#?RADIANCE\n# emboss studio environment, equirectangular\nFORMAT=32-bit_rle_rgbe\n\n-Y " +
                    std::to_string(h) + " +X " + std::to_string(w) + "\n";
  out.reserve(out.size() + static_cast<size_t>(w) * h * 4);
  constexpr double kPi = 3.14159265358979323846;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      // Average a 2 x 2 block of directions: the softboxes' edges are sharp.
      glm::dvec3 c(0.0);
      for (double du : {-0.25, 0.25})
        for (double dv : {-0.25, 0.25}) {
          const double tt = (0.5 - (v + 0.5 + dv) / h) * kPi, pp = (0.5 - (u + 0.5 + du) / w) * 2.0 * kPi;
          c += studioEnvironment({std::cos(tt) * std::cos(pp), std::cos(tt) * std::sin(pp), std::sin(tt)});
        }
      const auto px = rgbe(c * 0.25);
      out.append(reinterpret_cast<const char*>(px.data()), 4);
    }
  }
  if (Status s = writeFileAtomically(hdrPath, out); !s) return s;

  nlohmann::json j;
  j["format"] = "emboss-studio";
  j["environment"] = std::filesystem::path(hdrPath).filename().string();
  j["environment_mapping"] = "equirectangular as Blender's world texture, in the scene's axes (z toward the viewer)";
  const CameraSpec& c = scene.camera;
  j["camera"] = {{"type", c.type == CameraSpec::Type::Perspective ? "perspective" : "ortho"},
                 {"eye", vec(c.eye)}, {"target", vec(c.target)}, {"up", vec(c.up)},
                 {"fov_deg", c.fovDeg}, {"fov_axis", "vertical"}, {"height", c.height}};
  j["metal"] = {{"name", std::string(metal->name)},
                {"wavelengths_nm", kChannelWavelengths},
                {"eta", metal->eta},
                {"k", metal->k},
                {"f0", metal->f0},
                {"roughness_alpha", metal->roughness},
                {"hammer_slope", metal->hammer}};
  if (tinge) j["tinge"] = {{"name", std::string(tinge->name)}, {"color", tinge->color}, {"strength", tinge->strength}};
  j["tone"] = "linear c -> c / (1 + 0.25 c), then the sRGB curve";
  return writeFileAtomically(jsonPath, j.dump(1) + "\n");
}

}  // namespace emboss

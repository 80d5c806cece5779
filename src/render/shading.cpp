// Metal shading: a studio environment (softboxes, a dim room) reflected by a GGX microfacet lobe with
// the conductor Fresnel term of the metal's measured n and k (split-sum prefiltering, multiple
// scattering compensated), the planishing hammer's dimples, and occlusion in the cavities.
#include "render/shading.h"

#include "render/shade_lanes.h"
#include "render/table_cache.h"
#include "render/thread_pool.h"
#include "util/portable_math.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace emboss {

namespace {

// Radiance of the studio around the bench, by direction (z is toward the viewer's side of the
// sheet, y up the bench), in warm museum light (about 3000 K). A dark room; overhead, a ceiling of
// strip softboxes (bright bands running up the bench with dark gaps between), graduated from dim
// at the visitor's side to bright at the far side; a key softbox high to the left, a cooler fill to
// the right, a strip light above; a warm floor bounce. Dark surroundings and bright, bounded lights
// are what make a photograph of polished metal read as metal: a flat sheet mirrors the strips as
// bands, and the hammer's dimples break them into the glints of a planished sheet. (One uniform
// overhead panel, as before, gave a flat face of one colour: pale salmon copper.)
struct Light {
  glm::dvec3 dir;     // unit, toward the light's centre
  double cosEdge;     // cosine of its angular radius
  double soft;        // width of its soft edge, in cosine
  glm::dvec3 colour;  // radiance at full power
  double power;
  bool graduated;     // the overhead strips: power ramps up with the direction's height
};

const std::array<Light, 4>& lights() {
  static const std::array<Light, 4> kLights = [] {
    const glm::dvec3 warm(1.0, 0.85, 0.65), cool(0.88, 0.92, 1.0);
    auto light = [](glm::dvec3 centre, double size, double soft, glm::dvec3 colour, double power, bool graduated) {
      return Light{glm::normalize(centre), std::cos(size), soft, colour, power, graduated};
    };
    return std::array<Light, 4>{light({-0.05, 0.42, 0.90}, 0.42, 0.15, warm, 3.6, true),
                                light({-0.55, 0.65, 0.55}, 0.30, 0.03, warm, 3.6, false),
                                light({0.65, 0.45, 0.60}, 0.22, 0.03, cool, 1.5, false),
                                light({0.0, 0.9, 0.45}, 0.10, 0.03, warm, 4.8, false)};
  }();
  return kLights;
}

glm::dvec3 environment(const glm::dvec3& d) { return studioEnvironment(d); }

}  // namespace

glm::dvec3 studioEnvironment(const glm::dvec3& d) {
  const double up = std::clamp(0.5 + 0.5 * d.y, 0.0, 1.0);
  glm::dvec3 c = glm::mix(glm::dvec3(0.0156, 0.0132, 0.0096), glm::dvec3(0.084, 0.0672, 0.048), up);
  for (const Light& l : lights()) {
    const double k = glm::dot(d, l.dir);
    if (k <= l.cosEdge - l.soft) continue;
    double power = l.power;
    if (l.graduated) {
      // Bright at the far side; straight up, over the sheet itself, still a third of that (the
      // ramp's 0.4, squared), so a sheet seen straight down mirrors strips, not a dark ceiling.
      const double ramp = std::max(std::clamp((d.y - 0.05) / 0.6, 0.0, 1.0), 0.6 * std::clamp((d.y + 0.4) / 0.6, 0.0, 1.0));
      power = 0.072 + l.power * ramp * ramp;
      // The strips: kStripDuty of every kStripPeriod (radians across), soft-edged.
      constexpr double kStripPeriod = 0.2, kStripDuty = 0.35, kStripSoft = 0.15, kGap = 0.024;
      const double u = d.x / kStripPeriod + 10.25, f = u - std::floor(u);
      const double on = std::clamp((kStripDuty - std::abs(f - 0.5) * 2.0) / kStripSoft + 0.5, 0.0, 1.0);
      power = kGap + (power - kGap) * on;
    }
    c += l.colour * (power * std::clamp((k - (l.cosEdge - l.soft)) / l.soft, 0.0, 1.0));
  }
  // Floor bounce from below the bench.
  c += glm::dvec3(0.096, 0.066, 0.042) * std::clamp(-d.y, 0.0, 1.0);
  return c;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// Point i of n of the Hammersley set (radical inverse in base 2): fixed, so the tables below are
// the same bits in every run.
glm::dvec2 hammersley(unsigned i, unsigned n) {
  unsigned b = i;
  b = (b << 16u) | (b >> 16u);
  b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
  b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
  b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
  b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
  return {(i + 0.5) / n, b * 2.3283064365386963e-10};
}

// A GGX half vector around +z for roughness alpha (the visible normals are not needed: the tables
// weight each sample by what it contributes).
glm::dvec3 ggxHalfVector(const glm::dvec2& u, double alpha) {
  const double phi = 2.0 * kPi * u.y;
  const double cosT = std::sqrt((1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x));
  const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
  return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
}

// Smith's height-correlated masking-shadowing for GGX, divided by 4 NoL NoV (the "visibility").
double ggxVisibility(double nov, double nol, double alpha) {
  const double a2 = alpha * alpha;
  const double gv = nol * std::sqrt(nov * nov * (1.0 - a2) + a2);
  const double gl = nov * std::sqrt(nol * nol * (1.0 - a2) + a2);
  return 0.5 / std::max(gv + gl, 1e-12);
}

// An orthonormal frame around unit vector d.
void frame(const glm::dvec3& d, glm::dvec3& t, glm::dvec3& b) {
  t = glm::normalize(std::abs(d.z) < 0.9 ? glm::cross(d, glm::dvec3(0, 0, 1)) : glm::cross(d, glm::dvec3(1, 0, 0)));
  b = glm::cross(d, t);
}

// Octahedral maps of functions over the sphere of directions, bilinearly interpolated.
class SphereMap {
 public:
  // Rows are shared out over `pool` when one is given (each texel's arithmetic is the same).
  template <class F>
  SphereMap(int size, F f, ThreadPool* pool = nullptr) : size_(size), texels_(static_cast<size_t>(size) * size) {
    auto rows = [&](const Rect& r) {
      for (int j = r.y; j < r.y + r.h; ++j)
        for (int i = r.x; i < r.x + r.w; ++i)
          texels_[static_cast<size_t>(j) * size_ + i] = glm::vec3(f(decode((i + 0.5) / size_ * 2.0 - 1.0, (j + 0.5) / size_ * 2.0 - 1.0)));
    };
    if (pool && pool->size() > 1)
      pool->parallelFor2D(Rect{0, 0, size_, size_}, 16, rows);
    else
      rows(Rect{0, 0, size_, size_});
  }
  // A map from its texels (as texels() gave them: size * size of them).
  SphereMap(int size, std::vector<glm::vec3> texels) : size_(size), texels_(std::move(texels)) {}
  const std::vector<glm::vec3>& texels() const { return texels_; }
  int size() const { return size_; }
  glm::dvec3 lookup(const glm::dvec3& d) const {
    const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    double u = d.x / l1, v = d.y / l1;
    if (d.z < 0) {
      const double ou = u;
      u = (1.0 - std::abs(v)) * (ou >= 0 ? 1.0 : -1.0);
      v = (1.0 - std::abs(ou)) * (v >= 0 ? 1.0 : -1.0);
    }
    const double fx = std::clamp((u + 1.0) * 0.5 * size_ - 0.5, 0.0, size_ - 1.0);
    const double fy = std::clamp((v + 1.0) * 0.5 * size_ - 0.5, 0.0, size_ - 1.0);
    const int x0 = std::min(static_cast<int>(fx), size_ - 2), y0 = std::min(static_cast<int>(fy), size_ - 2);
    const double ax = fx - x0, ay = fy - y0;
    const glm::vec3* row0 = &texels_[static_cast<size_t>(y0) * size_ + x0];
    const glm::vec3* row1 = row0 + size_;
    const glm::dvec3 top = glm::mix(glm::dvec3(row0[0]), glm::dvec3(row0[1]), ax);
    const glm::dvec3 bottom = glm::mix(glm::dvec3(row1[0]), glm::dvec3(row1[1]), ax);
    return glm::mix(top, bottom, ay);
  }

 private:
  static glm::dvec3 decode(double u, double v) {
    glm::dvec3 d(u, v, 1.0 - std::abs(u) - std::abs(v));
    if (d.z < 0) {
      const double ou = d.x;
      d.x = (1.0 - std::abs(d.y)) * (ou >= 0 ? 1.0 : -1.0);
      d.y = (1.0 - std::abs(ou)) * (d.y >= 0 ? 1.0 : -1.0);
    }
    return glm::normalize(d);
  }
  int size_;
  std::vector<glm::vec3> texels_;
};

// GGX half vectors around +z for roughness alpha, at fixed Hammersley points.
std::vector<glm::dvec3> ggxHalfVectors(double alpha, unsigned count) {
  std::vector<glm::dvec3> h(count);
  for (unsigned i = 0; i < count; ++i) h[i] = ggxHalfVector(hammersley(i, count), alpha);
  return h;
}

// The environment seen through a GGX lobe around the mirror direction r (split-sum prefiltering:
// n = v = r, each light direction weighted by n.l), from the lobe's half vectors around +z.
glm::dvec3 prefilteredEnvironment(const glm::dvec3& r, const std::vector<glm::dvec3>& halfVectors) {
  glm::dvec3 t, b;
  frame(r, t, b);
  glm::dvec3 sum(0.0);
  double wsum = 0.0;
  for (const glm::dvec3& hl : halfVectors) {
    const glm::dvec3 h = hl.x * t + hl.y * b + hl.z * r;
    const glm::dvec3 l = 2.0 * glm::dot(r, h) * h - r;
    const double nol = glm::dot(r, l);
    if (nol <= 0) continue;
    sum += nol * environment(l);
    wsum += nol;
  }
  return wsum > 0 ? sum / wsum : environment(r);
}

// The cosine-weighted environment around n (irradiance / pi): what the light that bounces more
// than once between the microfacets brings, spread like a diffuse lobe.
glm::dvec3 irradiance(const glm::dvec3& n) {
  glm::dvec3 t, b;
  frame(n, t, b);
  constexpr unsigned kSamples = 512;
  glm::dvec3 sum(0.0);
  for (unsigned i = 0; i < kSamples; ++i) {
    const glm::dvec2 u = hammersley(i, kSamples);
    const double r = std::sqrt(u.x), phi = 2.0 * kPi * u.y;
    sum += environment(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u.x)) * n);
  }
  return sum / double(kSamples);
}

// Per metal: the directional albedo of its GGX lobe with the exact conductor Fresnel, by the
// cosine of the view angle (the split sum's second factor), and the numbers the multiple
// scattering compensation needs (Kulla and Conty 2017; Fdez-Aguera 2019).
struct MetalResponse {
  static constexpr int kBins = 64;
  std::array<glm::dvec3, kBins + 1> single{};   // E_F(mu): single scattering with Fresnel, mu = i / kBins
  std::array<double, kBins + 1> albedo{};       // E_1(mu): the same with Fresnel 1
  glm::dvec3 favg{0.0};                          // hemispherical average of the Fresnel term
  double eavg = 0.0;                             // cosine-weighted average of E_1
  // Kulla-Conty: the lobe that returns the energy single scattering loses, 1 - E_1(mu), tinted by
  // the Fresnel term averaged over the bounces (the same for every mu: worked out once).
  glm::dvec3 fms{0.0};

  MetalResponse() = default;
  explicit MetalResponse(const Metal& m) {
    const double alpha = m.roughness;
    constexpr unsigned kSamples = 1024;
    for (int bin = 0; bin <= kBins; ++bin) {
      const double mu = std::max(1e-3, bin / double(kBins));
      const glm::dvec3 v(std::sqrt(1.0 - mu * mu), 0.0, mu);
      glm::dvec3 e(0.0);
      double e1 = 0.0;
      for (unsigned i = 0; i < kSamples; ++i) {
        const glm::dvec3 h = ggxHalfVector(hammersley(i, kSamples), alpha);
        const double voh = glm::dot(v, h);
        const glm::dvec3 l = 2.0 * voh * h - v;
        if (l.z <= 0 || voh <= 0) continue;
        // pdf(l) = D noh / (4 voh); f cos = D vis F nol  =>  weight = vis F nol 4 voh / noh
        const double w = ggxVisibility(mu, l.z, alpha) * l.z * 4.0 * voh / h.z;
        e1 += w;
        for (int c = 0; c < 3; ++c) e[c] += w * fresnelConductor(voh, m.eta[c], m.k[c]);
      }
      single[bin] = e / double(kSamples);
      albedo[bin] = e1 / kSamples;
    }
    constexpr int kAvg = 256;
    for (int i = 0; i < kAvg; ++i) {
      const double mu = (i + 0.5) / kAvg;
      for (int c = 0; c < 3; ++c) favg[c] += 2.0 * mu * fresnelConductor(mu, m.eta[c], m.k[c]) / kAvg;
    }
    for (int bin = 0; bin < kBins; ++bin) {
      const double mu = (bin + 0.5) / kBins;
      eavg += 2.0 * mu * 0.5 * (albedo[bin] + albedo[bin + 1]) / kBins;
    }
    fms = favg * favg * eavg / (glm::dvec3(1.0) - favg * (1.0 - eavg));
  }

  // Single and multiple scattering reflectance for view cosine mu, to multiply the prefiltered
  // environment and the irradiance respectively.
  void at(double mu, glm::dvec3& ss, glm::dvec3& ms) const {
    const double f = std::clamp(mu, 0.0, 1.0) * kBins;
    const int i = std::min(static_cast<int>(f), kBins - 1);
    const double a = f - i;
    ss = glm::mix(single[i], single[i + 1], a);
    const double e1 = albedo[i] + (albedo[i + 1] - albedo[i]) * a;
    ms = fms * (1.0 - e1);
  }
};

// The planishing hammer's dimples: a field of shallow round dents of random centres, one per cell
// of a 1.6 mm lattice, in the sheet's plane. Returns the gradient of their depth at (x, y) for
// dimples whose largest slope is `slope`.
glm::dvec2 hammerGradient(double x, double y, double slope) {
  using H = Hammer;
  constexpr double kCell = H::kCell, kInvR2 = H::kInvR2, kJitter = H::kJitter, kOffset = H::kOffset;
  const double k0 = H::k0(slope);
  const int cx = floorToInt(x / kCell), cy = floorToInt(y / kCell);
  // The centres of the nine cells around, hashed from the cells' indices: the same for every hit in
  // the cell (about five pixels in a row of a frame), so each thread keeps the last cell's.
  struct Centres {
    int cx = std::numeric_limits<int>::min(), cy = 0;
    double fx[9], fy[9];
  };
  thread_local Centres c;
  if (cx != c.cx || cy != c.cy) {
    c.cx = cx, c.cy = cy;
    for (int n = 0; n < 9; ++n) {
      const int i = cx - 1 + n % 3, j = cy - 1 + n / 3;
      std::uint32_t hsh = static_cast<std::uint32_t>(i) * H::kHash[0] ^ static_cast<std::uint32_t>(j) * H::kHash[1];
      hsh ^= hsh >> 15, hsh *= H::kHash[2], hsh ^= hsh >> 12, hsh *= H::kHash[3], hsh ^= hsh >> 15;
      c.fx[n] = (i + kOffset + kJitter * (hsh & 0xFFFF)) * kCell;
      c.fy[n] = (j + kOffset + kJitter * (hsh >> 16)) * kCell;
    }
  }
  // No division and no branch per cell (a dimple out of reach weighs 0).
  double gx = 0.0, gy = 0.0;
  for (int n = 0; n < 9; ++n) {
    const double dx = x - c.fx[n], dy = y - c.fy[n];
    const double k = k0 * std::max(0.0, 1.0 - (dx * dx + dy * dy) * kInvR2);
    gx += k * dx, gy += k * dy;
  }
  return {gx, gy};
}

// Everything computed once per metal (and shared by every thread for the program's life).
struct MetalTables {
  static constexpr int kSpecularSize = 192;
  static constexpr unsigned kSpecularSamples = 128;
  MetalResponse response;
  SphereMap specular;
};

// The tables as bytes, for the table cache (plain copies of the numbers: the cache is read back only
// by the build that wrote it, on the same machine).
template <class T>
void putBytes(std::vector<std::uint8_t>& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  const auto* b = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), b, b + sizeof v);
}
template <class T>
void getBytes(const std::uint8_t*& in, T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::memcpy(&v, in, sizeof v);
  in += sizeof v;
}

std::vector<std::uint8_t> sphereMapBytes(const SphereMap& map) {
  std::vector<std::uint8_t> out;
  const auto& t = map.texels();
  out.resize(t.size() * sizeof(glm::vec3));
  std::memcpy(out.data(), t.data(), out.size());
  return out;
}
SphereMap sphereMapOf(int size, const std::uint8_t* in) {
  std::vector<glm::vec3> t(static_cast<size_t>(size) * size);
  std::memcpy(t.data(), in, t.size() * sizeof(glm::vec3));
  return SphereMap(size, std::move(t));
}

// A metal's tables: from the table cache when this build kept them there, else computed (and kept).
std::unique_ptr<MetalTables> makeTables(const Metal& m, ThreadPool* pool) {
  // What the tables depend on: the metal's constants and the tables' sizes. The cache's file is per
  // metal; its key adds the build (whose code computes them).
  std::uint64_t what = fnv1a64(m.name.data(), m.name.size());
  what = fnv1a64(&m.roughness, sizeof m.roughness, what);
  what = fnv1a64(m.eta.data(), sizeof m.eta, what);
  what = fnv1a64(m.k.data(), sizeof m.k, what);
  const int sizes[] = {MetalResponse::kBins, MetalTables::kSpecularSize, static_cast<int>(MetalTables::kSpecularSamples)};
  what = fnv1a64(sizes, sizeof sizes, what);
  const std::uint64_t build = buildFingerprint();
  const std::uint64_t key = fnv1a64(&build, sizeof build, what);
  char name[96];
  std::snprintf(name, sizeof name, "metal-%.*s-%016llx", static_cast<int>(m.name.size()), m.name.data(),
                static_cast<unsigned long long>(what));
  constexpr size_t kResponseBytes = sizeof(MetalResponse::single) + sizeof(MetalResponse::albedo) + 2 * sizeof(glm::dvec3) + sizeof(double);
  constexpr size_t kSpecularBytes = sizeof(glm::vec3) * MetalTables::kSpecularSize * MetalTables::kSpecularSize;
  if (auto bytes = loadTable(name, key, kResponseBytes + kSpecularBytes)) {
    const std::uint8_t* in = bytes->data();
    MetalResponse r;
    getBytes(in, r.single), getBytes(in, r.albedo), getBytes(in, r.favg), getBytes(in, r.eavg), getBytes(in, r.fms);
    return std::make_unique<MetalTables>(MetalTables{r, sphereMapOf(MetalTables::kSpecularSize, in)});
  }
  auto t = std::make_unique<MetalTables>(MetalTables{
      MetalResponse(m),
      SphereMap(MetalTables::kSpecularSize,
                [h = ggxHalfVectors(m.roughness, MetalTables::kSpecularSamples)](const glm::dvec3& d) {
                  return prefilteredEnvironment(d, h);
                },
                pool)});
  if (!tableCacheDir().empty()) {
    std::vector<std::uint8_t> out;
    const MetalResponse& r = t->response;
    putBytes(out, r.single), putBytes(out, r.albedo), putBytes(out, r.favg), putBytes(out, r.eavg), putBytes(out, r.fms);
    const auto spec = sphereMapBytes(t->specular);
    out.insert(out.end(), spec.begin(), spec.end());
    storeTable(name, key, out);
  }
  return t;
}

const SphereMap& irradianceMap(ThreadPool* pool = nullptr) {
  static constexpr int kSize = 48;
  static const SphereMap map = [pool] {
    const std::uint64_t build = buildFingerprint();
    const std::uint64_t key = fnv1a64(&build, sizeof build, fnv1a64(&kSize, sizeof kSize));
    if (auto bytes = loadTable("irradiance", key, sizeof(glm::vec3) * kSize * kSize)) return sphereMapOf(kSize, bytes->data());
    SphereMap m(kSize, irradiance, pool);
    if (!tableCacheDir().empty()) storeTable("irradiance", key, sphereMapBytes(m));
    return m;
  }();
  return map;
}

const MetalTables& tablesFor(const Metal& m, ThreadPool* pool = nullptr) {
  thread_local Metal lastMetal{};
  thread_local const MetalTables* last = nullptr;
  if (last && lastMetal.name == m.name && lastMetal.roughness == m.roughness && lastMetal.eta == m.eta &&
      lastMetal.k == m.k)
    return *last;
  static std::mutex mutex;
  static std::map<std::tuple<std::string, double, std::array<double, 3>, std::array<double, 3>>, std::unique_ptr<MetalTables>> tables;
  std::lock_guard lock(mutex);
  auto& slot = tables[{std::string(m.name), m.roughness, m.eta, m.k}];
  if (!slot) slot = makeTables(m, pool);
  lastMetal = m;
  last = slot.get();
  return *last;
}

}  // namespace

ShadingParams sheetShading(std::string_view metal, std::string_view tinge, double frontZ) {
  ShadingParams s;
  s.metal = *metalByName(metal);
  s.tinge = *tingeByName(tinge);
  s.frontZ = frontZ;
  return s;
}

glm::dvec3 shadeMetal(const ShadingParams& s, const glm::dvec3& p, const glm::dvec3& nIn, const glm::dvec3& view,
                      double cavity, const Patina* patina) {
  glm::dvec3 n = nIn;
  if (glm::dot(n, view) > 0) n = -n;  // seen from behind: light the face we see
  // The hammer's dimples tilt the normal of the faces (not the rim's wall).
  if (s.metal.hammer > 0) {
    const glm::dvec2 g = hammerGradient(p.x, p.y, s.metal.hammer);
    n = glm::normalize(n - glm::dvec3(g.x, g.y, 0.0) * n.z);
  }
  const double cosV = std::clamp(-glm::dot(view, n), 1e-4, 1.0);
  const glm::dvec3 r = glm::reflect(view, n);
  const MetalTables& t = tablesFor(s.metal);
  glm::dvec3 ss, ms;
  t.response.at(cosV, ss, ms);
  // The tinge (patina) gathers in the hollows: below the front face, fading in over tingeDepth,
  // and more in the grooves the cavity term finds; the scene's tinge over the whole sheet, the
  // brush's where it went. Liquor of sulphur settles in the hollows and wears off the high points.
  const double settle = std::max(std::clamp((s.frontZ - p.z) / s.tingeDepth, 0.0, 1.0), cavity);
  glm::dvec3 tint(1.0);
  if (s.tinge.strength > 0) tint *= tingeMix(s.tinge, s.tinge.strength, 0.25, settle);
  // Cavities see less of the room: the grooves' walls and the hollows under raised rims hide the
  // lights (specular occlusion from the height field; 0 on open metal).
  const double open = 1.0 - 0.75 * std::clamp(cavity, 0.0, 1.0);
  const glm::dvec3 spec = t.specular.lookup(r) * ss + irradianceMap().lookup(n) * ms;
  const glm::dvec3 bare = tint * spec * open;
  // The brush's tinges last, as a factor of the colour without them (the lanes' colour times
  // patinaTint() is this, bit for bit).
  return patina ? bare * patinaTint(s, p.z, cavity, *patina) : bare;
}

glm::dvec3 tingeMix(const Tinge& t, double amount, double floor, double settle) {
  const double k = std::clamp(amount * (floor + (1.0 - floor) * settle), 0.0, 1.0);
  return glm::mix(glm::dvec3(1.0), glm::dvec3(t.color[0], t.color[1], t.color[2]), k);
}

glm::dvec3 patinaTint(const ShadingParams& s, double z, double cavity, const Patina& patina) {
  const double settle = std::max(std::clamp((s.frontZ - z) / s.tingeDepth, 0.0, 1.0), cavity);
  glm::dvec3 tint(1.0);
  for (size_t i = 1; i < patina.amount.size(); ++i)
    if (patina.amount[i] > 0) tint *= tingeMix(tinges()[i], patina.amount[i], 0.75, settle);
  return tint;
}

void shadeMetal(const ShadingParams& s, ShadeBatch& batch) {
  const MetalTables& t = tablesFor(s.metal);
  MetalLaneParams p;
  p.hammer = s.metal.hammer;
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double) && sizeof(glm::vec3) == 3 * sizeof(float));
  p.bins = MetalResponse::kBins;
  p.single = &t.response.single[0].x;
  p.albedo = t.response.albedo.data();
  for (int c = 0; c < 3; ++c) p.fms[c] = t.response.fms[c];
  p.specular = SphereTexels{t.specular.size(), &t.specular.texels()[0].x};
  const SphereMap& irr = irradianceMap();
  p.irradiance = SphereTexels{irr.size(), &irr.texels()[0].x};
  p.frontZ = s.frontZ, p.tingeDepth = s.tingeDepth;
  p.tingeStrength = s.tinge.strength;
  for (int c = 0; c < 3; ++c) p.tingeColor[c] = s.tinge.color[static_cast<size_t>(c)];
  shadeMetalLanes(p, batch);
}

void prepareShading(const Metal& metal, ThreadPool* pool) {
  tablesFor(metal, pool);
  irradianceMap(pool);
}

glm::dvec3 metalAlbedo(const Metal& metal, double cosView) {
  glm::dvec3 ss, ms;
  tablesFor(metal).response.at(cosView, ss, ms);
  return ss + ms;
}

glm::dvec3 backdrop(int x, int y, int w, int h) {
  const double u = (x + 0.5) / w - 0.5, v = (y + 0.5) / h - 0.5;
  const double vignette = std::clamp(1.0 - 1.3 * (u * u + v * v), 0.0, 1.0);
  return glm::dvec3(0.018, 0.020, 0.026) * (0.4 + 0.6 * vignette);
}

std::array<std::uint8_t, 3> toSrgb8(const glm::dvec3& linear) {
  std::array<std::uint8_t, 3> out{};
  for (int i = 0; i < 3; ++i) {
    double c = std::max(0.0, linear[i]);
    c = c * c / (c + 0.03);    // a toe: the deep shadows of a camera's curve, which keep the metal's colour
    c = c / (1.0 + 0.25 * c);  // soft shoulder
    c = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    out[i] = static_cast<std::uint8_t>(std::clamp(std::lround(c * 255.0), 0L, 255L));
  }
  return out;
}

}  // namespace emboss

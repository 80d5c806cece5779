// Curves and the chaser's strokes for the attract pieces.
#include "pieces/piece_art.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "util/portable_math.h"

namespace emboss::art {

namespace {
constexpr double kDeg = M_PI / 180.0;

Vec2 catmull(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3, double t) {
  const double t2 = t * t, t3 = t2 * t;
  auto f = [&](double a, double b, double c, double d) {
    return 0.5 * ((2 * b) + (-a + c) * t + (2 * a - 5 * b + 4 * c - d) * t2 + (-a + 3 * b - 3 * c + d) * t3);
  };
  return {f(p0.x, p1.x, p2.x, p3.x), f(p0.y, p1.y, p2.y, p3.y)};
}
}  // namespace

double noise(std::uint64_t seed, std::uint64_t i) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + i * 0xBF58476D1CE4E5B9ull + 0x94D049BB133111EBull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

Path resampleEvery(const Path& p, double step) {
  Path out;
  if (p.empty()) return out;
  out.push_back(p[0]);
  double carry = 0;
  for (size_t i = 1; i < p.size(); ++i) {
    const Vec2 a = p[i - 1], b = p[i];
    const double seg = portableHypot(b.x - a.x, b.y - a.y);
    double s = step - carry;
    while (s <= seg) {
      out.push_back({a.x + (b.x - a.x) * s / seg, a.y + (b.y - a.y) * s / seg});
      s += step;
    }
    carry = seg - (s - step);
  }
  if (portableHypot(out.back().x - p.back().x, out.back().y - p.back().y) > 1e-9) out.push_back(p.back());
  return out;
}

Path spline(const Path& c, bool closed, double step) {
  Path dense;
  const size_t n = c.size();
  if (n < 2) return c;
  const size_t segs = closed ? n : n - 1;
  auto at = [&](long i) -> const Vec2& {
    if (closed) return c[static_cast<size_t>((i % static_cast<long>(n) + static_cast<long>(n)) % static_cast<long>(n))];
    return c[static_cast<size_t>(std::clamp(i, 0L, static_cast<long>(n) - 1))];
  };
  for (size_t s = 0; s < segs; ++s)
    for (int k = 0; k < 16; ++k)
      dense.push_back(catmull(at(long(s) - 1), at(long(s)), at(long(s) + 1), at(long(s) + 2), k / 16.0));
  dense.push_back(closed ? c[0] : c[n - 1]);
  return resampleEvery(dense, step);
}

Path arc(Vec2 c, double r, double fromDeg, double toDeg, double step) {
  Path p;
  const double len = std::abs(toDeg - fromDeg) * kDeg * r;
  const int n = std::max(2, static_cast<int>(std::ceil(len / step)));
  for (int i = 0; i <= n; ++i) {
    const double a = (fromDeg + (toDeg - fromDeg) * i / n) * kDeg;
    p.push_back({c.x + r * portableCos(a), c.y + r * portableSin(a)});
  }
  return p;
}

Path circle(Vec2 c, double r, double step) { return arc(c, r, 0, 360, step); }

Path transform(const Path& p, double scale, double rotateDeg, Vec2 move) {
  const double cs = portableCos(rotateDeg * kDeg), sn = portableSin(rotateDeg * kDeg);
  Path out;
  out.reserve(p.size());
  for (const auto& q : p) out.push_back({move.x + scale * (q.x * cs - q.y * sn), move.y + scale * (q.x * sn + q.y * cs)});
  return out;
}

Path mirrorX(const Path& p) {
  Path out;
  for (const auto& q : p) out.push_back({-q.x, q.y});
  return out;
}

double length(const Path& p) {
  double l = 0;
  for (size_t i = 1; i < p.size(); ++i) l += portableHypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  return l;
}

bool inside(const Path& c, Vec2 q) {
  bool in = false;
  for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++)
    if ((c[i].y > q.y) != (c[j].y > q.y) && q.x < (c[j].x - c[i].x) * (q.y - c[i].y) / (c[j].y - c[i].y) + c[i].x) in = !in;
  return in;
}

Path offsetContour(const Path& c, double d) {
  // Signed area tells the winding, so "outward" is the same for either direction.
  double area = 0;
  for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++) area += c[j].x * c[i].y - c[i].x * c[j].y;
  const double sgn = area > 0 ? 1.0 : -1.0;
  Path out;
  const size_t n = c.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = c[(i + n - 1) % n], b = c[(i + 1) % n];
    double tx = b.x - a.x, ty = b.y - a.y;
    const double l = portableHypot(tx, ty);
    if (l < 1e-12) {
      out.push_back(c[i]);
      continue;
    }
    tx /= l, ty /= l;
    out.push_back({c[i].x + sgn * ty * d, c[i].y - sgn * tx * d});
  }
  return out;
}

Chaser::Chaser(std::string metal, double surfaceZ) : z_(surfaceZ) {
  const auto m = metalByName(metal);
  if (!m) throw std::invalid_argument("unknown metal " + metal);
  metal_ = *m;
}

ToolSpec Chaser::tool(const std::string& name, double size) {
  for (const auto& t : toolCatalogue())
    if (t.name == name) {
      ToolSpec s = t;
      if (size > 0) s.size = size;
      return s;
    }
  throw std::invalid_argument("no tool named " + name);
}

void Chaser::stroke(const ToolSpec& tool, const Path& path, double pressure) {
  stroke(tool, path, std::vector<double>(path.size(), pressure));
}

void Chaser::stroke(const ToolSpec& tool, const Path& path, const std::vector<double>& pressures) {
  std::vector<StrokePoint> s;
  for (size_t i = 0; i < path.size(); ++i) s.push_back({path[i].x, path[i].y, z_, pressures[std::min(i, pressures.size() - 1)]});
  for (auto& op : strokeToOperations(tool, metal_, s)) ops_.push_back(std::move(op));
}

void Chaser::strike(const ToolSpec& tool, Vec2 at, double pressure) { stroke(tool, Path{at}, pressure); }

void Chaser::raise(const Path& contour, double pressure, double falloff) {
  ToolSpec t = tool("Region raiser", falloff);
  stroke(t, contour, pressure);
}

void Chaser::matte(const Path& area, const std::vector<Path>& holes, double spacing, double keepOff, double pressure,
                   std::uint64_t seed, double size) {
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const auto& q : area) x0 = std::min(x0, q.x), y0 = std::min(y0, q.y), x1 = std::max(x1, q.x), y1 = std::max(y1, q.y);
  std::vector<Path> grown;
  for (const auto& h : holes) grown.push_back(offsetContour(h, keepOff));
  const ToolSpec t = tool("Hammer", size);
  std::uint64_t i = 0;
  // Row by row, as a chaser works across the ground; odd rows shifted half a step.
  int row = 0;
  for (double y = y0; y <= y1; y += spacing * 0.87, ++row) {
    for (double x = x0 + (row % 2) * spacing * 0.5; x <= x1; x += spacing) {
      const Vec2 q{x + (noise(seed, i) - 0.5) * spacing * 0.5, y + (noise(seed, i + 1) - 0.5) * spacing * 0.5};
      const double pr = pressure * (0.8 + 0.4 * noise(seed, i + 2));
      i += 3;
      if (!inside(area, q)) continue;
      bool hit = false;
      for (const auto& h : grown)
        if (inside(h, q)) hit = true;
      if (!hit) strike(t, q, pr);
    }
  }
}

}  // namespace emboss::art

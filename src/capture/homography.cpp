// Homographies from four point pairs (a direct 8x8 solve, coordinates normalised for conditioning).
#include "capture/homography.h"

#include <cmath>
#include <utility>

namespace emboss {

namespace {

// Solves a x = b (n <= 8) by Gaussian elimination with partial pivoting; false when singular.
bool solve(double a[8][8], double b[8], double x[8]) {
  constexpr int n = 8;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    if (std::fabs(a[pivot][c]) < 1e-12) return false;
    if (pivot != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c][k], a[pivot][k]);
      std::swap(b[c], b[pivot]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < n; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return true;
}

// A similarity taking the points to centre 0 and mean distance sqrt(2) (Hartley's normalisation).
Homography normaliser(const std::array<Vec2, 4>& p) {
  double cx = 0, cy = 0;
  for (const auto& q : p) cx += q.x / 4, cy += q.y / 4;
  double d = 0;
  for (const auto& q : p) d += std::hypot(q.x - cx, q.y - cy) / 4;
  const double s = d > 0 ? std::sqrt(2.0) / d : 1.0;
  return Homography{{s, 0, -s * cx, 0, s, -s * cy, 0, 0, 1}};
}

}  // namespace

Vec2 Homography::apply(const Vec2& p) const {
  const double w = m[6] * p.x + m[7] * p.y + m[8];
  return {(m[0] * p.x + m[1] * p.y + m[2]) / w, (m[3] * p.x + m[4] * p.y + m[5]) / w};
}

std::optional<Homography> Homography::inverse() const {
  const auto& a = m;
  const double c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8], c02 = a[3] * a[7] - a[4] * a[6];
  const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
  if (std::fabs(det) < 1e-300) return std::nullopt;
  Homography h;
  h.m = {c00,
         a[2] * a[7] - a[1] * a[8],
         a[1] * a[5] - a[2] * a[4],
         c01,
         a[0] * a[8] - a[2] * a[6],
         a[2] * a[3] - a[0] * a[5],
         c02,
         a[1] * a[6] - a[0] * a[7],
         a[0] * a[4] - a[1] * a[3]};
  for (double& v : h.m) v /= det;
  return h;
}

Homography operator*(const Homography& a, const Homography& b) {
  Homography h;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) h.m[r * 3 + c] = a.m[r * 3] * b.m[c] + a.m[r * 3 + 1] * b.m[3 + c] + a.m[r * 3 + 2] * b.m[6 + c];
  return h;
}

std::optional<Homography> Homography::fromQuad(const std::array<Vec2, 4>& src, const std::array<Vec2, 4>& dst) {
  const Homography ns = normaliser(src), nd = normaliser(dst);
  double a[8][8] = {}, b[8] = {}, x[8] = {};
  for (int i = 0; i < 4; ++i) {
    const Vec2 s = ns.apply(src[i]), d = nd.apply(dst[i]);
    // u = (h0 x + h1 y + h2) / (h6 x + h7 y + 1), v likewise with h3..h5.
    double* r0 = a[2 * i];
    double* r1 = a[2 * i + 1];
    r0[0] = s.x, r0[1] = s.y, r0[2] = 1, r0[6] = -d.x * s.x, r0[7] = -d.x * s.y;
    r1[3] = s.x, r1[4] = s.y, r1[5] = 1, r1[6] = -d.y * s.x, r1[7] = -d.y * s.y;
    b[2 * i] = d.x, b[2 * i + 1] = d.y;
  }
  if (!solve(a, b, x)) return std::nullopt;
  Homography h{{x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], 1.0}};
  // Three points on a line give a solvable system with a singular map: refuse it.
  double frob = 0;
  for (double v : h.m) frob += v * v;
  const auto& m = h.m;
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
  if (std::fabs(det) < 1e-9 * std::pow(frob, 1.5)) return std::nullopt;
  const auto ndInv = nd.inverse();
  if (!ndInv) return std::nullopt;
  Homography out = *ndInv * h * ns;
  // Scale so that m[8] is 1 where possible (it does not change the map).
  if (std::fabs(out.m[8]) > 1e-12) {
    const double k = out.m[8];
    for (double& v : out.m) v /= k;
  }
  return out;
}

}  // namespace emboss

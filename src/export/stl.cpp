// Binary STL writer.
#include "export/stl.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace emboss {

static_assert(std::endian::native == std::endian::little, "STL is little-endian; add byte swapping for this machine");

namespace {

void put(std::string& out, const void* p, size_t n) { out.append(static_cast<const char*>(p), n); }

}  // namespace

std::string stlBytes(const TriangleMesh& mesh, const std::string& header) {
  std::string out;
  out.reserve(84 + mesh.triangles.size() * 50);
  char head[80] = {};
  // "solid" at the start makes some readers take a binary file for ASCII.
  std::string h = header.rfind("solid", 0) == 0 ? "emboss " + header : header;
  std::memcpy(head, h.data(), std::min<size_t>(h.size(), sizeof head));
  put(out, head, sizeof head);
  const std::uint32_t count = static_cast<std::uint32_t>(mesh.triangles.size());
  put(out, &count, 4);
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.vertices[t[0]];
    const auto& b = mesh.vertices[t[1]];
    const auto& c = mesh.vertices[t[2]];
    // The edges' differences in float, as a reader has them; the products in double (a sliver's
    // normal would lose its digits in float).
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    double nd[3] = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
    const double len = std::sqrt(nd[0] * nd[0] + nd[1] * nd[1] + nd[2] * nd[2]);
    float n[3] = {0.0f, 0.0f, 0.0f};
    if (len > 0.0)
      for (int i = 0; i < 3; ++i) n[i] = static_cast<float>(nd[i] / len);
    put(out, n, 12);
    put(out, a.data(), 12);
    put(out, b.data(), 12);
    put(out, c.data(), 12);
    const std::uint16_t attr = 0;
    put(out, &attr, 2);
  }
  return out;
}

}  // namespace emboss

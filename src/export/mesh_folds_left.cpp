// The fine mesh's own folds left after the removals (mesh_unfold.cpp): edges flipped along a
// sharp ridge, then vertices moved along the surface (mesh_internal.h, docs/exports.md "Folds
// moved out" and "Fins on a ridge flipped").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "export/mesh_internal.h"
#include "frep/grad.h"
#include "frep/model.h"
#include "frep/op_grid.h"

namespace emboss {
namespace mesh_detail {

namespace {

// Every directed edge (u << 32 | v) with its triangle, sorted: the triangle across u -> v is the
// one that holds v -> u.
struct EdgeIndex {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  explicit EdgeIndex(const std::vector<std::array<std::uint32_t, 3>>& T) {
    edges.reserve(3 * T.size());
    for (std::uint32_t t = 0; t < T.size(); ++t)
      for (int k = 0; k < 3; ++k) edges.push_back({key(T[t][k], T[t][(k + 1) % 3]), t});
    std::sort(edges.begin(), edges.end());
  }
  static std::uint64_t key(std::uint32_t u, std::uint32_t v) { return (std::uint64_t{u} << 32) | v; }
  // The triangle holding the directed edge u -> v, or UINT32_MAX.
  std::uint32_t holding(std::uint32_t u, std::uint32_t v) const {
    const std::uint64_t k = key(u, v);
    auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(k, std::uint32_t{0}));
    return it != edges.end() && it->first == k ? it->second : UINT32_MAX;
  }
};

// Under kThin: its normal is float noise.
bool thinTriangle(const std::vector<std::array<float, 3>>& V, const std::array<std::uint32_t, 3>& t) {
  return shape(V[t[0]].data(), V[t[1]].data(), V[t[2]].data()) < static_cast<float>(kThin);
}

}  // namespace

size_t flipFoldEdges(TriangleMesh& mesh, const Model& model, const OpGrid& grid) {
  const auto& V = mesh.vertices;
  auto& T = mesh.triangles;
  std::vector<std::uint32_t> scratch;
  auto offSurface = [&](const std::array<std::uint32_t, 3>& t) {
    return farthestOfSeven(model, grid, V[t[0]], V[t[1]], V[t[2]], std::numeric_limits<double>::infinity(), scratch);
  };
  size_t flipped = 0;
  for (int sweep = 0; sweep < 8; ++sweep) {
    const EdgeIndex index(T);
    // The index as the sweep began: a flip's triangles and the triangles beyond them hold only
    // vertices marked here, whose edges wait for the next sweep's index.
    std::vector<std::uint8_t> touched(V.size(), 0);
    size_t flips = 0;
    for (const auto& [key, t1] : index.edges) {
      const std::uint32_t u = static_cast<std::uint32_t>(key >> 32), v = static_cast<std::uint32_t>(key);
      if (u > v) continue;  // each edge once
      const std::uint32_t t2 = index.holding(v, u);
      if (t2 == UINT32_MAX || !foldsAcross(V, T[t1], T[t2])) continue;
      // t1 = (u, v, c), t2 = (v, u, d), in their cyclic orders.
      auto third = [&](const std::array<std::uint32_t, 3>& t, std::uint32_t a, std::uint32_t b) {
        for (std::uint32_t w : t)
          if (w != a && w != b) return w;
        return UINT32_MAX;
      };
      const std::uint32_t c = third(T[t1], u, v), d = third(T[t2], u, v);
      if (c == UINT32_MAX || d == UINT32_MAX || c == d) continue;
      if (touched[u] || touched[v] || touched[c] || touched[d]) continue;
      if (index.holding(c, d) != UINT32_MAX || index.holding(d, c) != UINT32_MAX) continue;  // would not be manifold
      const std::array<std::uint32_t, 3> n1{c, u, d}, n2{d, v, c};
      if (thinTriangle(V, n1) || thinTriangle(V, n2)) continue;
      // The quad's four outer edges with the triangles beyond them: (v, c) and (c, u) of t1,
      // (u, d) and (d, v) of t2.
      const std::uint32_t beyondVC = index.holding(c, v), beyondCU = index.holding(u, c);
      const std::uint32_t beyondUD = index.holding(d, u), beyondDV = index.holding(v, d);
      auto folds = [&](const std::array<std::uint32_t, 3>& a, std::uint32_t b) {
        return b != UINT32_MAX && foldsAcross(V, a, T[b]) ? 1 : 0;
      };
      const int before = 1 + folds(T[t1], beyondVC) + folds(T[t1], beyondCU) + folds(T[t2], beyondUD) +
                         folds(T[t2], beyondDV);
      const int after = (foldsAcross(V, n1, n2) ? 1 : 0) + folds(n1, beyondCU) + folds(n1, beyondUD) +
                        folds(n2, beyondDV) + folds(n2, beyondVC);
      if (after >= before) continue;
      if (std::max(offSurface(n1), offSurface(n2)) > std::max(offSurface(T[t1]), offSurface(T[t2]))) continue;
      T[t1] = n1, T[t2] = n2;
      touched[u] = touched[v] = touched[c] = touched[d] = 1;
      ++flips;
    }
    flipped += flips;
    if (flips == 0) break;
  }
  return flipped;
}

size_t moveOutOfFolds(TriangleMesh& mesh, const Model& model, const OpGrid& grid) {
  auto& V = mesh.vertices;
  const auto& T = mesh.triangles;
  const EdgeIndex index(T);
  auto across = [&](std::uint32_t u, std::uint32_t v) { return index.holding(v, u); };  // the triangle with edge v -> u
  auto folded = [&](std::uint32_t a, std::uint32_t b) {
    return a != UINT32_MAX && b != UINT32_MAX && foldsAcross(V, T[a], T[b]);
  };
  std::vector<std::uint32_t> at;  // the folds' vertices
  for (const auto& [key, t] : index.edges) {
    const std::uint32_t u = static_cast<std::uint32_t>(key >> 32), v = static_cast<std::uint32_t>(key);
    if (u < v && folded(t, across(u, v))) at.insert(at.end(), {T[t][0], T[t][1], T[t][2]});
  }
  if (at.empty()) return 0;
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  std::vector<std::vector<std::uint32_t>> fan(at.size());
  for (std::uint32_t t = 0; t < T.size(); ++t)
    for (std::uint32_t v : T[t])
      if (auto it = std::lower_bound(at.begin(), at.end(), v); it != at.end() && *it == v) fan[it - at.begin()].push_back(t);
  // Folds on the edges of a vertex's fan (each once), and whether a fan triangle is thin.
  auto around = [&](const std::vector<std::uint32_t>& f, bool& thin) {
    size_t folds = 0;
    thin = false;
    std::vector<std::uint64_t> seen;
    for (std::uint32_t t : f) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t o = across(T[t][k], T[t][(k + 1) % 3]);
        const std::uint64_t pair = (std::uint64_t{std::min(t, o)} << 32) | std::max(t, o);
        if (std::find(seen.begin(), seen.end(), pair) != seen.end()) continue;
        seen.push_back(pair);
        folds += folded(t, o);
      }
      thin = thin || thinTriangle(V, T[t]);
    }
    return folds;
  };
  std::vector<std::uint32_t> scratch;
  size_t moved = 0;
  for (int sweep = 0; sweep < 3; ++sweep)
    for (size_t i = 0; i < at.size(); ++i) {
      const std::uint32_t v = at[i];
      bool thinBefore;
      const size_t before = around(fan[i], thinBefore);
      if (before == 0) continue;
      // The neighbours' centre, then onto the surface.
      double c[3] = {0, 0, 0};
      int count = 0;
      for (std::uint32_t t : fan[i])
        for (std::uint32_t w : T[t])
          if (w != v) {
            for (int k = 0; k < 3; ++k) c[k] += V[w][k];
            ++count;
          }
      for (int k = 0; k < 3; ++k) c[k] /= count;
      double dist = 1e30;
      for (int step = 0; step <= 4; ++step) {  // four steps, then the distance where they end
        const Grad g = model.evaluate(P3<Grad>{{c[0], 1, 0, 0}, {c[1], 0, 1, 0}, {c[2], 0, 0, 1}}, grid.at(c[0], c[1], scratch));
        const double len2 = g.dx * g.dx + g.dy * g.dy + g.dz * g.dz;
        dist = len2 > 0.0 ? std::abs(g.v) / std::sqrt(len2) : 1e30;
        if (step == 4 || !(len2 > 0.0)) break;
        c[0] -= g.v * g.dx / len2, c[1] -= g.v * g.dy / len2, c[2] -= g.v * g.dz / len2;
      }
      if (!(dist < 1e-4)) continue;
      const auto old = V[v];
      V[v] = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
      bool thinAfter;
      const size_t after = around(fan[i], thinAfter);
      if (after < before && (!thinAfter || thinBefore)) ++moved;
      else V[v] = old;
    }
  return moved;
}

}  // namespace mesh_detail
}  // namespace emboss

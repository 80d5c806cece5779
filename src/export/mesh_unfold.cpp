// Folds and thin triangles left by simplification, taken out by removing a vertex and
// triangulating the hole again (mesh_internal.h, docs/exports.md "Folds").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>

#include <glm/glm.hpp>

#include "export/mesh_internal.h"

namespace emboss::mesh_detail {

namespace {

using D3 = glm::dvec3;

// The point of triangle abc closest to p (Ericson, "Real-Time Collision Detection", 5.1.5).
D3 closestOnTriangle(const D3& p, const D3& a, const D3& b, const D3& c) {
  const D3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const D3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return a + v * ab;
  }
  const D3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return a + w * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return b + w * (c - b);
  }
  const double s = 1.0 / (va + vb + vc), v = vb * s, w = vc * s;
  return a + ab * v + ac * w;
}

// |cross| / (longest edge)^2, as shape() in mesh_decimate.cpp but in doubles.
double shapeOf(const D3& a, const D3& b, const D3& c) {
  const double l = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  return l > 0.0 ? glm::length(glm::cross(b - a, c - a)) / l : 0.0;
}

constexpr unsigned int kDead = 0xffffffffu;
// A vertex is removed only where each new triangle lies within 60 degrees of the hole's plane and
// is not thin (under about 0.6 degrees).
constexpr double kPlaneCos = 0.5;
constexpr double kWorstShape = 0.01;
// Holes of more triangles than this are not triangulated again (the polygon's tests grow with the
// square of its rim).
constexpr size_t kMaxFan = 24;

class Unfolder {
 public:
  Unfolder(std::vector<unsigned int>& ix, size_t n, const std::vector<float>& pos, double maxError)
      : ix_(ix), n_(n), pos_(pos), maxError_(maxError), first_(pos.size() / 3 + 1, 0) {
    // Each vertex's triangles, packed (a vector per vertex would cost tens of megabytes on a big
    // mesh); the few stars a removal changes are kept apart (edited_).
    for (size_t i = 0; i < n_; ++i) ++first_[ix_[i] + 1];
    for (size_t v = 1; v < first_.size(); ++v) first_[v] += first_[v - 1];
    tris_.resize(n_);
    std::vector<std::uint32_t> fill(first_.begin(), first_.end() - 1);
    for (size_t i = 0; i < n_; ++i) tris_[fill[ix_[i]]++] = static_cast<std::uint32_t>(i / 3);
  }

  // Every vertex of a folded triangle, then the pairs; again while any goes (three passes at most).
  // Returns how many vertices went.
  size_t foldPasses() {
    size_t removed = 0;
    for (int pass = 0; pass < 3; ++pass) {
      std::vector<std::uint32_t> folded;
      for (std::uint32_t t = 0; t < n_ / 3; ++t)
        if (!dead(t) && isFolded(t)) folded.push_back(t);
      std::vector<unsigned int> cand;
      for (std::uint32_t t : folded) cand.insert(cand.end(), {ix_[3 * t], ix_[3 * t + 1], ix_[3 * t + 2]});
      std::sort(cand.begin(), cand.end());
      cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
      size_t now = 0;
      for (unsigned int v : cand) now += removeVertices({v});
      // Where no one vertex would do: the two ends of an edge of a triangle still folded.
      // (A removal that fails leaves the mesh as it was: t is checked again only after one that
      // went.)
      for (std::uint32_t t : folded) {
        bool stillFolded = !dead(t) && isFolded(t);
        for (int e = 0; e < 3 && stillFolded; ++e)
          if (removeVertices({ix_[3 * t + e], ix_[3 * t + (e + 1) % 3]})) {
            now += 2;
            stillFolded = !dead(t) && isFolded(t);
          }
      }
      removed += now;
      if (now == 0) break;
    }
    return removed;
  }

  // Each triangle still thin: one of its vertices, the one off its longest edge first.
  size_t thinPass() {
    size_t removed = 0;
    for (std::uint32_t t = 0; t < n_ / 3; ++t) {
      if (dead(t)) continue;
      const D3 a = p(ix_[3 * t]), b = p(ix_[3 * t + 1]), c = p(ix_[3 * t + 2]);
      if (shapeOf(a, b, c) >= kThin) continue;
      const double ab = glm::dot(b - a, b - a), bc = glm::dot(c - b, c - b), ca = glm::dot(a - c, a - c);
      const int off = ab >= bc && ab >= ca ? 2 : bc >= ca ? 0 : 1;
      for (int k = 0; k < 3; ++k)
        if (removeVertices({ix_[3 * t + (off + k) % 3]}, true)) {
          ++removed;
          break;
        }
    }
    return removed;
  }

  // Drops the dead triangles; the new count of indices.
  size_t compacted() {
    size_t m = 0;
    for (size_t t = 0; t < n_ / 3; ++t)
      if (!dead(static_cast<std::uint32_t>(t))) {
        for (int k = 0; k < 3; ++k) ix_[3 * m + k] = ix_[3 * t + k];
        ++m;
      }
    return 3 * m;
  }

 private:
  // A directed edge of a region's rim, and the region's triangle it belongs to.
  struct Step {
    unsigned int a, b;
    std::uint32_t t;
  };
  // A region to take out: the vertices that go, its triangles (their indices and corners as they
  // are), its rim, and per rim edge the triangle across it (-1: none) and those triangles.
  struct Region {
    const std::vector<unsigned int>& gone;
    const std::vector<std::uint32_t>& fan;
    const std::vector<unsigned int>& rim;
    std::vector<std::array<unsigned int, 3>> old;
    std::vector<long> across;
    std::vector<std::array<unsigned int, 3>> outside;
  };
  D3 p(unsigned int v) const { return {pos_[3 * v], pos_[3 * v + 1], pos_[3 * v + 2]}; }
  // The triangles using v (dead ones among them too).
  std::span<const std::uint32_t> star(unsigned int v) const {
    if (const auto it = edited_.find(v); it != edited_.end()) return it->second;
    return {tris_.data() + first_[v], tris_.data() + first_[v + 1]};
  }
  std::vector<std::uint32_t>& editable(unsigned int v) {
    auto [it, fresh] = edited_.try_emplace(v);
    if (fresh) it->second.assign(tris_.begin() + first_[v], tris_.begin() + first_[v + 1]);
    return it->second;
  }
  bool dead(std::uint32_t t) const { return ix_[3 * t] == kDead; }
  D3 normal(std::uint32_t t) const {
    const D3 a = p(ix_[3 * t]), m = glm::cross(p(ix_[3 * t + 1]) - a, p(ix_[3 * t + 2]) - a);
    const double l = glm::length(m);
    return l > 0.0 ? m * (1.0 / l) : D3(0.0);
  }
  // The live triangle other than t with the directed edge (b, a), or -1.
  long across(std::uint32_t t, unsigned int a, unsigned int b) const {
    for (std::uint32_t u : star(a)) {
      if (u == t || dead(u)) continue;
      for (int k = 0; k < 3; ++k)
        if (ix_[3 * u + k] == b && ix_[3 * u + (k + 1) % 3] == a) return u;
    }
    return -1;
  }
  bool foldAt(std::uint32_t t, int k) const {
    const long u = across(t, ix_[3 * t + k], ix_[3 * t + (k + 1) % 3]);
    return u >= 0 && glm::dot(normal(t), normal(static_cast<std::uint32_t>(u))) < kFoldCos;
  }
  bool isFolded(std::uint32_t t) const { return foldAt(t, 0) || foldAt(t, 1) || foldAt(t, 2); }
  // Replaces the triangles `slots` (the region around the removed vertices `gone`, its rim `rim`)
  // by `tris` (fewer), keeping the stars right: the first slots take the new triangles, the rest die.
  void put(const std::vector<unsigned int>& gone, const std::vector<unsigned int>& rim,
           const std::vector<std::uint32_t>& slots, const std::vector<std::array<unsigned int, 3>>& tris) {
    auto inSlots = [&](std::uint32_t u) { return std::find(slots.begin(), slots.end(), u) != slots.end(); };
    for (unsigned int a : rim) std::erase_if(editable(a), inSlots);
    for (unsigned int v : gone) std::erase_if(editable(v), inSlots);
    for (size_t i = 0; i < slots.size(); ++i) {
      const std::uint32_t t = slots[i];
      if (i < tris.size()) {
        for (int k = 0; k < 3; ++k) {
          ix_[3 * t + k] = tris[i][static_cast<size_t>(k)];
          editable(tris[i][static_cast<size_t>(k)]).push_back(t);
        }
      } else {
        ix_[3 * t] = ix_[3 * t + 1] = ix_[3 * t + 2] = kDead;
      }
    }
  }

  // Removes the vertices `gone` (one, or the two ends of an edge) when the triangles around them
  // make a disc whose hole can be filled again: by ear clipping, where the rim seen along its own
  // normal is a simple polygon and the new triangles are good and face that way; else, for one
  // vertex, by collapsing its edge onto a rim vertex. Either is kept only where each vertex lies
  // within maxError of the surface after, no new edge exists elsewhere, and the region has fewer
  // folds after (`thin`: no more folds, and its worst triangle better) (tryFill).
  bool removeVertices(const std::vector<unsigned int>& gone, bool thin = false) {
    std::vector<std::uint32_t> fan;  // the region
    for (unsigned int v : gone)
      for (std::uint32_t t : star(v))
        if (!dead(t) && std::find(fan.begin(), fan.end(), t) == fan.end()) fan.push_back(t);
    const size_t region = fan.size();
    if (region < 3 || region > kMaxFan) return false;
    auto isGone = [&](unsigned int a) { return std::find(gone.begin(), gone.end(), a) != gone.end(); };
    // The rim: the region's directed edges whose reverse is not in it (each with its triangle);
    // they must make one cycle through vertices that stay, and the region a disc (Euler: a disc
    // of r rim vertices and g inside has r + 2 g - 2 triangles).
    std::vector<Step> steps;
    auto inFan = [&](unsigned int a, unsigned int b) {
      for (std::uint32_t t : fan)
        for (int e = 0; e < 3; ++e)
          if (ix_[3 * t + e] == a && ix_[3 * t + (e + 1) % 3] == b) return true;
      return false;
    };
    for (std::uint32_t t : fan)
      for (int e = 0; e < 3; ++e) {
        const unsigned int a = ix_[3 * t + e], b = ix_[3 * t + (e + 1) % 3];
        if (!inFan(b, a)) {
          if (isGone(a) || isGone(b)) return false;
          steps.push_back({a, b, t});
        }
      }
    const size_t k = steps.size();
    if (k < 3 || region != k + 2 * gone.size() - 2) return false;
    std::vector<unsigned int> rim{steps[0].a};
    std::vector<Step> ordered;
    for (size_t s = 0; s < k; ++s) {
      const Step* next = nullptr;
      int found = 0;
      for (const Step& st : steps)
        if (st.a == rim.back()) next = &st, ++found;
      if (found != 1) return false;
      ordered.push_back(*next);
      if (s + 1 == k) {
        if (next->b != rim[0]) return false;
      } else {
        if (std::find(rim.begin(), rim.end(), next->b) != rim.end()) return false;
        rim.push_back(next->b);
      }
    }
    // The region's triangles as they are, and the triangle across each rim edge (-1: none), for
    // every fill tried.
    Region r{gone, fan, rim, {}, {}, {}};
    for (std::uint32_t t : fan) r.old.push_back({ix_[3 * t], ix_[3 * t + 1], ix_[3 * t + 2]});
    for (const Step& st : ordered) {
      r.across.push_back(across(st.t, st.a, st.b));
      if (const long u = r.across.back(); u >= 0) {
        const size_t q = 3 * static_cast<size_t>(u);
        r.outside.push_back({ix_[q], ix_[q + 1], ix_[q + 2]});
      }
    }
    std::vector<std::array<unsigned int, 3>> tris;
    if (earFill(rim, tris) && tryFill(r, thin, tris, false)) return true;
    if (gone.size() != 1) return false;
    // A vertex where the surface turns (the sheet's face and its side wall): no one plane holds
    // its hole. Its edge to a rim vertex is collapsed instead (the hole filled by a fan from that
    // vertex), the rim vertex whose fan is best shaped tried first: each new triangle must face
    // within 60 degrees of the one it replaces, or of the one across its rim edge.
    std::vector<std::pair<double, size_t>> apexes;
    for (size_t j = 0; j < k; ++j) {
      double worst = 1.0;
      bool ok = true;
      for (size_t i = 0; i < k && ok; ++i) {
        const size_t i1 = (i + 1) % k;
        if (i == j || i1 == j) continue;
        const D3 a = p(rim[j]), b = p(rim[i]), d = p(rim[i1]);
        const D3 m = glm::cross(b - a, d - a);
        const double l = glm::length(m), s = shapeOf(a, b, d);
        const long u = r.across[i];
        const bool faces = glm::dot(m, normal(ordered[i].t)) >= kPlaneCos * l ||
                           (u >= 0 && glm::dot(m, normal(static_cast<std::uint32_t>(u))) >= kPlaneCos * l);
        ok = l > 0.0 && s >= kWorstShape && faces;
        worst = std::min(worst, s);
      }
      if (ok) apexes.push_back({worst, j});
    }
    std::sort(apexes.begin(), apexes.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    for (const auto& [worst, j] : apexes) {
      tris.clear();
      for (size_t i = 0; i < k; ++i)
        if (i != j && (i + 1) % k != j) tris.push_back({rim[j], rim[i], rim[(i + 1) % k]});
      if (tryFill(r, thin, tris, true)) return true;
    }
    return false;
  }

  // Fills the hole of rim `rim` by ear clipping in the rim's own plane; false where the rim, seen
  // along that plane's normal, is no simple polygon, or a triangle would be thin or face away.
  bool earFill(const std::vector<unsigned int>& rim, std::vector<std::array<unsigned int, 3>>& tris) const {
    const size_t k = rim.size();
    // The rim's plane: its normal by Newell's method (the fan's summed area vector, whichever way
    // its triangles face), the rim in coordinates of that plane.
    D3 c(0.0);
    for (unsigned int a : rim) c += p(a);
    c *= 1.0 / static_cast<double>(k);
    D3 nn(0.0);
    for (size_t i = 0; i < k; ++i) {
      const D3 m = glm::cross(p(rim[i]) - c, p(rim[(i + 1) % k]) - c);
      nn += m;
    }
    const double nl = glm::length(nn);
    if (!(nl > 0.0)) return false;
    const D3 N = nn * (1.0 / nl);
    const D3 axis = std::abs(N.x) < 0.6 ? D3(1, 0, 0) : D3(0, 1, 0);
    const D3 e1 = glm::cross(N, axis) * (1.0 / glm::length(glm::cross(N, axis))), e2 = glm::cross(N, e1);
    std::vector<double> qx(k), qy(k);
    double extent = 0.0;
    for (size_t i = 0; i < k; ++i) {
      const D3 d = p(rim[i]) - c;
      qx[i] = glm::dot(d, e1), qy[i] = glm::dot(d, e2);
      extent = std::max(extent, std::abs(qx[i]) + std::abs(qy[i]));
    }
    auto orient = [&](size_t a, size_t b, size_t d) {
      return (qx[b] - qx[a]) * (qy[d] - qy[a]) - (qy[b] - qy[a]) * (qx[d] - qx[a]);
    };
    const double eps = 1e-12 * extent * extent;
    // A simple polygon: no two edges that are not neighbours meet or touch.
    for (size_t i = 0; i < k; ++i)
      for (size_t j = i + 2; j < k; ++j) {
        if (i == 0 && j == k - 1) continue;
        const size_t i1 = (i + 1) % k, j1 = (j + 1) % k;
        const double o1 = orient(i, i1, j), o2 = orient(i, i1, j1), o3 = orient(j, j1, i), o4 = orient(j, j1, i1);
        if (std::min({std::abs(o1), std::abs(o2), std::abs(o3), std::abs(o4)}) <= eps) return false;
        if ((o1 > 0) != (o2 > 0) && (o3 > 0) != (o4 > 0)) return false;
      }
    // Ear clipping, the best-shaped ear first.
    std::vector<size_t> poly(k);
    for (size_t i = 0; i < k; ++i) poly[i] = i;
    while (poly.size() > 3) {
      const size_t m = poly.size();
      double best = -1.0;
      size_t bi = m;
      for (size_t i = 0; i < m; ++i) {
        const size_t a = poly[(i + m - 1) % m], b = poly[i], d = poly[(i + 1) % m];
        if (orient(a, b, d) <= eps) continue;
        bool empty = true;
        for (size_t j = 0; j < m && empty; ++j) {
          const size_t q = poly[j];
          if (q != a && q != b && q != d && orient(a, b, q) >= -eps && orient(b, d, q) >= -eps && orient(d, a, q) >= -eps)
            empty = false;
        }
        if (!empty) continue;
        const double s = shapeOf(p(rim[a]), p(rim[b]), p(rim[d]));
        if (s > best) best = s, bi = i;
      }
      if (bi == m) return false;
      tris.push_back({rim[poly[(bi + m - 1) % m]], rim[poly[bi]], rim[poly[(bi + 1) % m]]});
      poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(bi));
    }
    if (orient(poly[0], poly[1], poly[2]) <= eps) return false;
    tris.push_back({rim[poly[0]], rim[poly[1]], rim[poly[2]]});
    for (const auto& t : tris) {
      const D3 a = p(t[0]), b = p(t[1]), d = p(t[2]);
      const D3 m = glm::cross(b - a, d - a);
      const double l = glm::length(m);
      if (!(l > 0.0) || glm::dot(m, N) < kPlaneCos * l || shapeOf(a, b, d) < kWorstShape) return false;
    }
    return true;
  }

  // Puts `tris` in the place of the region's triangles when no new edge
  // exists elsewhere already, each removed vertex lies within maxError of the surface after (and
  // a collapse's triangles within it of the surface before), and the region has fewer folds after
  // (`thin`: no more, and its worst triangle better); else leaves the mesh as it was.
  bool tryFill(const Region& r, bool thin, const std::vector<std::array<unsigned int, 3>>& tris, bool collapse) {
    const std::vector<unsigned int>& rim = r.rim;
    const std::vector<std::uint32_t>& fan = r.fan;
    const size_t k = rim.size();
    double worstNew = 1.0;
    for (const auto& t : tris) worstNew = std::min(worstNew, shapeOf(p(t[0]), p(t[1]), p(t[2])));
    // A new edge inside the hole must not be an edge of a triangle outside the fan already.
    auto rimIndex = [&](unsigned int a) { return static_cast<size_t>(std::find(rim.begin(), rim.end(), a) - rim.begin()); };
    for (const auto& t : tris)
      for (int e = 0; e < 3; ++e) {
        const unsigned int a = t[static_cast<size_t>(e)], b = t[static_cast<size_t>((e + 1) % 3)];
        const size_t ia = rimIndex(a), ib = rimIndex(b);
        if ((ia + 1) % k == ib || (ib + 1) % k == ia) continue;  // the rim's own edge
        for (std::uint32_t u : star(a))
          if (!dead(u) && std::find(fan.begin(), fan.end(), u) == fan.end() &&
              (ix_[3 * u] == b || ix_[3 * u + 1] == b || ix_[3 * u + 2] == b))
            return false;
      }
    // q's distance to the nearest triangle of `inside` and of the triangles around the hole.
    using Tris = std::vector<std::array<unsigned int, 3>>;
    auto distance = [&](const D3& q, const Tris& inside) {
      double dmin = std::numeric_limits<double>::infinity();
      for (const Tris* surface : {&inside, &r.outside})
        for (const auto& t : *surface) dmin = std::min(dmin, glm::length(closestOnTriangle(q, p(t[0]), p(t[1]), p(t[2])) - q));
      return dmin;
    };
    // Each vertex within maxError of the surface after: the new triangles or the ones around the
    // hole (a folding vertex often lies beyond its own rim, over a neighbour).
    for (unsigned int v : r.gone)
      if (distance(p(v), tris) > maxError_) return false;
    // A collapse's triangles, too, within maxError of the surface before (the region and the
    // triangles around it), at their centres and their edges' midpoints: across a turn of the
    // surface they could cut its corner while the vertex lies near a neighbour.
    if (collapse)
      for (const auto& t : tris) {
        const D3 a = p(t[0]), b = p(t[1]), d = p(t[2]);
        for (const D3& q : {(a + b + d) * (1.0 / 3.0), 0.5 * (a + b), 0.5 * (b + d), 0.5 * (d + a)})
          if (distance(q, r.old) > maxError_) return false;
      }
    // Fewer folds along the hole's edges after than along the fan's before (each counted from
    // both sides inside, once on the rim).
    auto folds = [&](size_t count) {
      long f = 0;
      for (size_t i = 0; i < count; ++i)
        for (int e = 0; e < 3; ++e) f += foldAt(fan[i], e);
      return f;
    };
    const long before = folds(fan.size());
    double worstOld = 1.0;
    for (const auto& t : r.old) worstOld = std::min(worstOld, shapeOf(p(t[0]), p(t[1]), p(t[2])));
    put(r.gone, rim, fan, tris);
    const long after = folds(tris.size());
    if (thin ? after <= before && worstNew > worstOld : after < before) return true;
    put(r.gone, rim, fan, r.old);
    return false;
  }

  std::vector<unsigned int>& ix_;
  size_t n_;
  const std::vector<float>& pos_;
  double maxError_;
  std::vector<std::uint32_t> first_, tris_;  // vertex v's triangles: tris_[first_[v] .. first_[v + 1])
  std::unordered_map<unsigned int, std::vector<std::uint32_t>> edited_;  // stars changed since
};

}  // namespace

VertexRemovals removeFoldsAndThinTriangles(std::vector<unsigned int>& ix, size_t& n, const std::vector<float>& pos,
                                           double maxError) {
  Unfolder u(ix, n, pos, maxError);
  VertexRemovals r;
  r.folds = u.foldPasses();
  r.thin = u.thinPass();
  if (r.folds + r.thin > 0) n = u.compacted();
  return r;
}

}  // namespace emboss::mesh_detail

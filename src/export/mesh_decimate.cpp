// The mesh export's clean-up: welding equal vertices, mending slivers, and decimation by
// meshoptimizer in tiles that cannot disagree (mesh.cpp makes the mesh, this makes it small).
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <unordered_map>
#include <unordered_set>

#include "export/mesh_internal.h"
#include "render/thread_pool.h"

namespace emboss::mesh_detail {

namespace {
struct FloatKey {
  std::uint32_t x, y, z;
  bool operator==(const FloatKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
FloatKey floatKey(const std::array<float, 3>& p) {
  FloatKey k;
  float v[3] = {p[0] == 0.0f ? 0.0f : p[0], p[1] == 0.0f ? 0.0f : p[1], p[2] == 0.0f ? 0.0f : p[2]};  // -0 is +0
  std::memcpy(&k.x, &v[0], 4);
  std::memcpy(&k.y, &v[1], 4);
  std::memcpy(&k.z, &v[2], 4);
  return k;
}

}  // namespace

// Merges vertices whose float positions are equal and drops the triangles that degenerate. The
// vertices are sorted by position (an index array, not a hash map of every vertex: on a busy piece
// that map held hundreds of megabytes); each keeps its first occurrence's place, in the order of
// first occurrence, as a map filled in vertex order would.
void weldFloats(TriangleMesh& mesh) {
  const size_t n = mesh.vertices.size();
  std::vector<FloatKey> keys(n);
  for (size_t v = 0; v < n; ++v) keys[v] = floatKey(mesh.vertices[v]);
  std::vector<std::uint32_t> order(n);
  for (size_t v = 0; v < n; ++v) order[v] = static_cast<std::uint32_t>(v);
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const FloatKey &p = keys[a], &q = keys[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;  // equal positions: the first occurrence first
  };
  std::sort(order.begin(), order.end(), less);
  // first[v]: the first occurrence of v's position (v itself when it is the first).
  std::vector<std::uint32_t> first(n);
  for (size_t r = 0; r < n; ++r)
    first[order[r]] = r > 0 && keys[order[r]] == keys[order[r - 1]] ? first[order[r - 1]] : order[r];
  keys = {};
  order = {};
  std::vector<std::uint32_t>& remap = first;  // filled in vertex order: a first occurrence precedes its copies
  std::vector<std::array<float, 3>> kept;
  kept.reserve(n);
  for (size_t v = 0; v < n; ++v) {
    if (first[v] == v) {
      remap[v] = static_cast<std::uint32_t>(kept.size());
      kept.push_back(mesh.vertices[v]);
    } else {
      remap[v] = remap[first[v]];
    }
  }
  size_t m = 0;
  for (auto t : mesh.triangles) {
    t = {remap[t[0]], remap[t[1]], remap[t[2]]};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    mesh.triangles[m++] = t;
  }
  mesh.triangles.resize(m);
  mesh.vertices = std::move(kept);
}

// Keeps only the vertices some triangle uses, in first-use order.
void compact(TriangleMesh& mesh) {
  std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
  std::vector<std::array<float, 3>> kept;
  for (auto& t : mesh.triangles)
    for (auto& v : t) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<std::uint32_t>(kept.size());
        kept.push_back(mesh.vertices[v]);
      }
      v = remap[v];
    }
  mesh.vertices = std::move(kept);
}

float crossLength2(const float* a, const float* b, const float* c, float n[3]) {
  const float ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const float vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  n[0] = uy * vz - uz * vy;
  n[1] = uz * vx - ux * vz;
  n[2] = ux * vy - uy * vx;
  return n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
}

// cos^2 of 10 degrees.
constexpr float kFlipCos2 = 0.9698463f;

// |cross|^2 and the longest edge's length^2: what sliver() and shape() compare.
static void crossAndLongest2(const float* a, const float* b, const float* c, float& c2, float& l2) {
  float n[3];
  c2 = crossLength2(a, b, c, n);
  auto d2 = [](const float* u, const float* v) {
    return (v[0] - u[0]) * (v[0] - u[0]) + (v[1] - u[1]) * (v[1] - u[1]) + (v[2] - u[2]) * (v[2] - u[2]);
  };
  l2 = std::max({d2(a, b), d2(b, c), d2(c, a)});
}

float shape(const float* a, const float* b, const float* c) {
  float c2, l2;
  crossAndLongest2(a, b, c, c2, l2);
  return l2 > 0.0f ? std::sqrt(c2) / l2 : 0.0f;
}

bool sliver(const float* a, const float* b, const float* c, float k) {
  float c2, l2;
  crossAndLongest2(a, b, c, c2, l2);
  return c2 <= k * k * l2 * l2;
}

bool foldsAcross(const std::vector<std::array<float, 3>>& v, const std::array<std::uint32_t, 3>& a,
                 const std::array<std::uint32_t, 3>& b) {
  float na[3], nb[3];
  const float la = crossLength2(v[a[0]].data(), v[a[1]].data(), v[a[2]].data(), na);
  const float lb = crossLength2(v[b[0]].data(), v[b[1]].data(), v[b[2]].data(), nb);
  const float d = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
  return la > 0.0f && lb > 0.0f && d < static_cast<float>(kFoldCos) * std::sqrt(la) * std::sqrt(lb);
}

// Simplifying a flat face leaves triangles whose corners are (nearly) collinear: zero area or a
// sliver, the collapse checks see no flip in them. Each is mended by flipping its longest edge with
// the neighbour across it, when that makes two proper triangles facing the neighbour's way and the
// new edge is new.
void mendFlatTriangles(std::vector<unsigned int>& ix, size_t n, const std::vector<float>& pos) {
  auto p = [&](unsigned int v) { return &pos[3 * v]; };
  auto key = [](unsigned int u, unsigned int v) { return (static_cast<std::uint64_t>(u) << 32) | v; };
  // Slivers are few: each pass finds them, then looks up only the edges it needs in one scan of the
  // mesh (a map of every edge would cost more than the rest of the decimation).
  for (int pass = 0; pass < 4; ++pass) {
    struct Candidate {
      size_t t;
      unsigned int a, b, c;
      size_t u = SIZE_MAX;
      unsigned int d = 0;
    };
    std::vector<Candidate> cands;
    for (size_t t = 0; t < n; t += 3) {
      if (!sliver(p(ix[t]), p(ix[t + 1]), p(ix[t + 2]), kMendSliver)) continue;
      int best = 0;  // the longest edge (a, b); c lies (nearly) on it
      float bestLen = -1.0f;
      for (int e = 0; e < 3; ++e) {
        const float* a = p(ix[t + e]);
        const float* b = p(ix[t + (e + 1) % 3]);
        const float l = (b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]);
        if (l > bestLen) {
          bestLen = l;
          best = e;
        }
      }
      cands.push_back({t, ix[t + best], ix[t + (best + 1) % 3], ix[t + (best + 2) % 3]});
    }
    if (cands.empty()) return;
    // The neighbour across each longest edge.
    std::unordered_map<std::uint64_t, size_t> wanted;
    for (size_t i = 0; i < cands.size(); ++i) wanted[key(cands[i].b, cands[i].a)] = i;
    for (size_t t = 0; t < n; t += 3)
      for (int e = 0; e < 3; ++e) {
        auto it = wanted.find(key(ix[t + e], ix[t + (e + 1) % 3]));
        if (it == wanted.end()) continue;
        Candidate& c = cands[it->second];
        c.u = t;
        c.d = ix[t + (e + 2) % 3];
      }
    // The new edges c-d must not exist already.
    std::unordered_map<std::uint64_t, bool> fresh;
    for (const Candidate& c : cands)
      if (c.u != SIZE_MAX) fresh[key(std::min(c.c, c.d), std::max(c.c, c.d))] = true;
    for (size_t t = 0; t < n; t += 3)
      for (int e = 0; e < 3; ++e) {
        const unsigned int u = ix[t + e], v = ix[t + (e + 1) % 3];
        auto it = fresh.find(key(std::min(u, v), std::max(u, v)));
        if (it != fresh.end()) it->second = false;
      }
    std::unordered_map<size_t, bool> touched;
    bool changed = false;
    for (const Candidate& c : cands) {
      if (c.u == SIZE_MAX || c.d == c.c || !fresh[key(std::min(c.c, c.d), std::max(c.c, c.d))]) continue;
      if (touched.count(c.t) || touched.count(c.u)) continue;
      const size_t t = c.t, u = c.u;
      const unsigned int a = c.a, b = c.b, cc = c.c, d = c.d;
      float nu[3], n1[3], n2[3];
      crossLength2(p(ix[u]), p(ix[u + 1]), p(ix[u + 2]), nu);
      if (sliver(p(a), p(d), p(cc)) || sliver(p(d), p(b), p(cc))) continue;
      // Only a flip that makes the worse triangle better (a sliver of 1 degree is not traded for
      // another).
      if (std::min(shape(p(a), p(d), p(cc)), shape(p(d), p(b), p(cc))) <= std::min(shape(p(a), p(b), p(cc)), shape(p(ix[u]), p(ix[u + 1]), p(ix[u + 2]))))
        continue;
      crossLength2(p(a), p(d), p(cc), n1);
      crossLength2(p(d), p(b), p(cc), n2);
      if (n1[0] * nu[0] + n1[1] * nu[1] + n1[2] * nu[2] <= 0.0f || n2[0] * nu[0] + n2[1] * nu[1] + n2[2] * nu[2] <= 0.0f) continue;
      // A thin triangle that is not a sliver by kSliver: only within about 10 degrees of the
      // neighbour's plane, a flip in a face, never one that cuts across an edge of the sheet (a
      // thin triangle along the rim, its neighbour on the side wall). (A sliver by kSliver has no
      // area worth keeping: any flip that faces the neighbour's way.)
      auto cos2 = [](const float* p, const float* q) {
        const float d = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        return d * d / ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]));
      };
      if (!sliver(p(a), p(b), p(cc)) && (cos2(n1, nu) < kFlipCos2 || cos2(n2, nu) < kFlipCos2)) continue;
      ix[t] = a, ix[t + 1] = d, ix[t + 2] = cc;
      ix[u] = d, ix[u + 1] = b, ix[u + 2] = cc;
      touched[t] = touched[u] = true;
      fresh[key(std::min(cc, d), std::max(cc, d))] = false;  // now it exists
      changed = true;
    }
    if (!changed) return;
  }
}

namespace {

// A piece of the mesh simplified alone, its border locked; kept only when it is still a manifold
// patch with the same border (each inner edge used once each way, no degenerate triangle). With
// `keepFlat`, triangles of zero area and slivers are kept too, for the caller to count as flaws
// (thin triangles: simplifyPatch() keeps fine triangles around them and tries again).
bool simplifyOnce(const std::vector<std::array<float, 3>>& allVertices, std::vector<std::array<std::uint32_t, 3>>& tris,
                   double maxError, bool keepFlat = false) {
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  std::vector<std::uint32_t> global;
  std::vector<float> pos;
  std::vector<unsigned int> idx;
  idx.reserve(tris.size() * 3);
  for (const auto& t : tris)
    for (std::uint32_t v : t) {
      auto [it, fresh] = local.try_emplace(v, static_cast<std::uint32_t>(global.size()));
      if (fresh) {
        global.push_back(v);
        pos.insert(pos.end(), allVertices[v].begin(), allVertices[v].end());
      }
      idx.push_back(it->second);
    }
  float lo[3] = {pos[0], pos[1], pos[2]}, hi[3] = {pos[0], pos[1], pos[2]};
  for (size_t v = 0; v < global.size(); ++v)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], pos[3 * v + a]);
      hi[a] = std::max(hi[a], pos[3 * v + a]);
    }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (extent <= 0.0) return false;
  // Directed edges, sorted (a sort beats a hash map here): a repeat is a neighbour equal to it, a
  // border edge one whose reverse is missing.
  auto edgesOf = [](const unsigned int* ix, size_t n) {
    std::vector<std::uint64_t> e(n);
    for (size_t t = 0; t < n; t += 3)
      for (int k = 0; k < 3; ++k) e[t + k] = (static_cast<std::uint64_t>(ix[t + k]) << 32) | ix[t + (k + 1) % 3];
    std::sort(e.begin(), e.end());
    return e;
  };
  // (Each vertex's edges out are a run of the sorted keys: an edge's reverse is looked for in the
  // run of its end, a few edges, not by a binary search of them all, a tenth of an export's time.)
  const size_t vertexCount = global.size();
  auto border = [vertexCount](const std::vector<std::uint64_t>& sorted) {
    std::vector<std::uint32_t> first(vertexCount + 1, 0);
    for (std::uint64_t key : sorted) ++first[(key >> 32) + 1];
    for (size_t v = 0; v < vertexCount; ++v) first[v + 1] += first[v];
    std::vector<std::uint64_t> b;
    for (std::uint64_t key : sorted) {
      const std::uint64_t rev = (key << 32) | (key >> 32);
      const auto end = static_cast<std::uint32_t>(key);  // the reverse's start
      bool found = false;
      for (std::uint32_t k = first[end]; k < first[end + 1] && !found; ++k) found = sorted[k] == rev;
      if (!found) b.push_back(key);
    }
    return b;
  };
  const auto originalBorder = border(edgesOf(idx.data(), idx.size()));
  std::vector<unsigned int> out(idx.size());
  for (double error : {maxError, 0.25 * maxError}) {
    const size_t n = meshopt_simplify(out.data(), idx.data(), idx.size(), pos.data(), global.size(), sizeof(float) * 3, 0,
                                      static_cast<float>(error / extent), meshopt_SimplifyLockBorder, nullptr);
    if (n == idx.size()) return false;  // nothing to gain
    mendFlatTriangles(out, n, pos);
    bool ok = true;
    for (size_t t = 0; t < n && ok; t += 3) {
      const float* a = &pos[3 * out[t]];
      const float* b = &pos[3 * out[t + 1]];
      const float* c = &pos[3 * out[t + 2]];
      float n[3];
      ok = out[t] != out[t + 1] && out[t + 1] != out[t + 2] && out[t] != out[t + 2] &&
           (keepFlat || (crossLength2(a, b, c, n) != 0.0f &&
                         !sliver(a, b, c, 0.1f * kSliver)));  // a tile is not refused for what the last pass mends
    }
    if (!ok) continue;
    const auto after = edgesOf(out.data(), n);
    ok = std::adjacent_find(after.begin(), after.end()) == after.end();
    if (!ok || border(after) != originalBorder) continue;
    tris.resize(n / 3);
    for (size_t t = 0; t < n / 3; ++t) tris[t] = {global[out[3 * t]], global[out[3 * t + 1]], global[out[3 * t + 2]]};
    return true;
  }
  return false;
}

using Tri = std::array<std::uint32_t, 3>;

// How many times a patch's simplification is tried again with more kept fine around its flaws
// (ten give the rosette the same mesh as six, a pile of 400 strokes 0.2 % fewer triangles).
constexpr int kFlawRounds = 6;

// Directed edges of the triangles, (u << 32 | v), sorted.
std::vector<std::uint64_t> sortedEdges(const std::vector<Tri>& a, const std::vector<Tri>& b) {
  std::vector<std::uint64_t> e;
  e.reserve(3 * (a.size() + b.size()));
  for (const auto* set : {&a, &b})
    for (const Tri& t : *set)
      for (int k = 0; k < 3; ++k) e.push_back((static_cast<std::uint64_t>(t[k]) << 32) | t[(k + 1) % 3]);
  std::sort(e.begin(), e.end());
  return e;
}

// A triangle's key whatever corner it starts at (the smallest first, the turn kept).
struct TriKey {
  Tri t;
  explicit TriKey(const Tri& x) {
    const int k = x[0] <= x[1] && x[0] <= x[2] ? 0 : x[1] <= x[2] ? 1 : 2;
    t = {x[static_cast<size_t>(k)], x[static_cast<size_t>((k + 1) % 3)], x[static_cast<size_t>((k + 2) % 3)]};
  }
  bool operator==(const TriKey& o) const { return t == o.t; }
};
struct TriKeyHash {
  size_t operator()(const TriKey& k) const {
    return std::hash<std::uint64_t>()((static_cast<std::uint64_t>(k.t[0]) << 32 | k.t[1]) * 0x9e3779b97f4a7c15ull ^ k.t[2]);
  }
};
using FineSet = std::unordered_set<TriKey, TriKeyHash>;

// The flaws of `own` that `fine` does not hold both triangles of: its folds (kFoldCos), among its
// triangles and against `context`, each as the four vertices of its two triangles; and its thin
// triangles (kThin), each as its three vertices and the third again. The same measures as the
// passes after the decimation (mesh_unfold.cpp).
std::vector<std::array<std::uint32_t, 4>> flawsIn(const std::vector<std::array<float, 3>>& v, const std::vector<Tri>& own,
                                                 const std::vector<Tri>& context, const FineSet& fine) {
  // Triangle i of own, then of context.
  auto tri = [&](size_t i) -> const Tri& { return i < own.size() ? own[i] : context[i - own.size()]; };
  const size_t count = own.size() + context.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> e;
  e.reserve(3 * count);
  for (size_t t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k)
      e.push_back({(static_cast<std::uint64_t>(tri(t)[k]) << 32) | tri(t)[(k + 1) % 3], static_cast<std::uint32_t>(t)});
  std::sort(e.begin(), e.end());
  std::vector<std::array<std::uint32_t, 4>> flaws;
  for (const auto& [key, t] : e) {
    const std::uint64_t rev = (key << 32) | (key >> 32);
    if (rev < key) continue;  // each pair once
    auto it = std::lower_bound(e.begin(), e.end(), std::make_pair(rev, std::uint32_t{0}));
    if (it == e.end() || it->first != rev) continue;
    if (t >= own.size() && it->second >= own.size()) continue;  // both in the context
    const Tri &a = tri(t), &b = tri(it->second);
    if (fine.count(TriKey(a)) && fine.count(TriKey(b))) continue;  // the fine mesh's own
    if (foldsAcross(v, a, b)) {
      std::uint32_t apexB = b[0];
      for (std::uint32_t x : b)
        if (x != a[0] && x != a[1] && x != a[2]) apexB = x;
      flaws.push_back({a[0], a[1], a[2], apexB});
    }
  }
  for (const Tri& t : own)
    if (shape(v[t[0]].data(), v[t[1]].data(), v[t[2]].data()) < static_cast<float>(kThin) && !fine.count(TriKey(t)))
      flaws.push_back({t[0], t[1], t[2], t[2]});
  return flaws;
}

// simplifyOnce() (beside the fine mesh's own flaws, kept fine), then, where the simplified patch
// folds (against itself or against the ring around it, which stays as it is) or has a thin
// triangle that the fine mesh had not, the fine triangles around each flaw's
// vertices are kept as they are and the rest is simplified again, their rim locked as the border
// is; the kept set grows around the flaws left, up to kFlawRounds times, and the attempt with the
// fewest is kept. (meshoptimizer 0.18 cannot lock single vertices; a patch is cut instead.) A
// patch that still has one fails, and goes round again in a smaller tile: a flaw the simplifier
// made is cheaper to keep out than to take out after, where the passes after often cannot (a fold
// on the sheet's rim).
bool simplifyPatch(const std::vector<std::array<float, 3>>& allVertices, std::vector<Tri>& tris, const std::vector<Tri>& ring,
                   double maxError, const SurfaceCheck* onSurface = nullptr) {
  // The fine triangles (the patch's and its ring's): a flaw among them alone is the fine mesh's
  // (marching tetrahedra's, at a sharp crease), no simplification's, and is not counted; but the
  // triangles around it are kept fine from the start, so that the passes after the decimation
  // find it among fine triangles, as in a tile left fine.
  FineSet fine;
  for (const Tri& t : tris) fine.insert(TriKey(t));
  for (const Tri& t : ring) fine.insert(TriKey(t));
  std::vector<Tri> pinned, rest = tris;
  // Moves the triangles of `rest` with a vertex of a flaw to `pinned`.
  auto pinAround = [&](const std::vector<std::array<std::uint32_t, 4>>& flaws) {
    std::unordered_set<std::uint32_t> at;
    for (const auto& f : flaws) at.insert(f.begin(), f.end());
    size_t m = 0;
    for (const Tri& t : rest) {
      if (at.count(t[0]) || at.count(t[1]) || at.count(t[2])) pinned.push_back(t);
      else rest[m++] = t;
    }
    rest.resize(m);
  };
  // The rest simplified beside the pinned triangles, or false (the simplification fails its
  // check, or makes an edge a pinned triangle has).
  auto attempt = [&](std::vector<Tri>& out) {
    out = rest;
    if (!rest.empty() && !simplifyOnce(allVertices, out, maxError, onSurface != nullptr)) return false;
    const auto edges = sortedEdges(out, pinned);
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
    out.insert(out.end(), pinned.begin(), pinned.end());
    return true;
  };
  // The flaws of an attempt: folds and thin triangles, and with `onSurface` each new triangle
  // off the surface (as a thin one: its three vertices). A triangle is checked once: the attempts
  // after the first make many of the same again.
  std::unordered_map<TriKey, bool, TriKeyHash> checked;
  auto flawsOf = [&](const std::vector<Tri>& out) {
    auto found = flawsIn(allVertices, out, ring, fine);
    if (onSurface)
      for (const Tri& t : out) {
        const TriKey key(t);
        if (fine.count(key)) continue;
        auto [it, fresh] = checked.try_emplace(key, true);
        if (fresh) it->second = (*onSurface)(allVertices[t[0]], allVertices[t[1]], allVertices[t[2]]);
        if (!it->second) found.push_back({t[0], t[1], t[2], t[2]});
      }
    return found;
  };
  pinAround(flawsIn(allVertices, tris, ring, FineSet{}));
  std::vector<Tri> result;
  if (!attempt(result)) return false;
  auto flaws = flawsOf(result);
  size_t fewest = flaws.size();
  for (int round = 0; round < kFlawRounds && fewest > 0; ++round) {
    pinAround(flaws);
    std::vector<Tri> next;
    if (!attempt(next)) break;
    flaws = flawsOf(next);
    if (flaws.size() < fewest) result = std::move(next), fewest = flaws.size();
  }
  if (fewest > 0) return false;
  tris = std::move(result);
  return true;
}

// The bands' passes (decimate()): how many, and meshoptimizer's error in each as a share of the
// export's. The simplified patches it is given lie up to maxError from the fine mesh already; at
// half of it, fewer new triangles leave the surface and fewer tiles fail. The medallion at 0.15 mm
// (367 054 triangles with the seams' pass alone): 123 012 after two passes, 116 418 after three.
// (Before zero-area triangles were flaws rather than failures, one pass at the whole error gave
// 252 282, at half 223 206; three at half 177 858, four 175 400.)
constexpr int kBandPasses = 3;
constexpr double kBandError = 0.5;

// The seams: what the rounds left fine (the rings along the tiles' edges, and the tiles that
// failed), simplified once more in tiles of the first round's size moved by half a tile, so that
// the first round's seams cross their middles. A tile's patch is its fine triangles; everything
// else stays as it is while it is simplified, so its border (the vertices it shares with the
// simplified patches around it, or with another tile) is locked, and it is checked against the
// triangles around it as simplifyPatch() checks a patch against its ring. Tiles of one of four
// colours at a time (by the parity of their column and row), so no two tiles being simplified touch.
// The bands' passes call it with every triangle in `todo` and none in `done`, and `onSurface`.
void simplifySeams(const std::vector<std::array<float, 3>>& vertices, std::vector<Tri>& done, std::vector<Tri>& todo,
                   double maxError, double tile, double planeX, double planeY, ThreadPool& pool,
                   const SurfaceCheck* onSurface = nullptr) {
  if (todo.empty()) return;
  const double ox = planeX + 0.5 * tile, oy = planeY + 0.5 * tile;
  auto tileOf = [&](const Tri& t, int& i, int& j) {
    const double cx = (double(vertices[t[0]][0]) + vertices[t[1]][0] + vertices[t[2]][0]) / 3.0;
    const double cy = (double(vertices[t[0]][1]) + vertices[t[1]][1] + vertices[t[2]][1]) / 3.0;
    i = static_cast<int>(std::floor((cx - ox) / tile));
    j = static_cast<int>(std::floor((cy - oy) / tile));
  };
  for (int colour = 0; colour < 4; ++colour) {
    // This colour's tiles, keyed by (column, row); the other fine triangles wait.
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    std::vector<std::vector<Tri>> tiles;
    std::vector<Tri> waiting;
    for (const Tri& t : todo) {
      int i, j;
      tileOf(t, i, j);
      if ((i & 1) + 2 * (j & 1) != colour) {
        waiting.push_back(t);
        continue;
      }
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 32) | static_cast<std::uint32_t>(i);
      auto [it, fresh] = index.try_emplace(key, static_cast<std::uint32_t>(tiles.size()));
      if (fresh) tiles.emplace_back();
      tiles[it->second].push_back(t);
    }
    if (tiles.empty()) continue;
    // Each vertex's tile of this colour (or none), and each tile's ring: the triangles outside it
    // that use one of its vertices. A tile that touches another of this colour (tiles smaller
    // than the triangles) is left as it is.
    constexpr std::uint32_t kNone = UINT32_MAX, kTwo = UINT32_MAX - 1;
    std::vector<std::uint32_t> tileAt(vertices.size(), kNone);
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
      for (const Tri& t : tiles[k])
        for (std::uint32_t v : t) tileAt[v] = tileAt[v] == kNone || tileAt[v] == k ? k : kTwo;
    std::vector<std::vector<Tri>> rings(tiles.size());
    std::vector<std::uint8_t> clash(tiles.size(), 0);
    auto ringOf = [&](const Tri& t) {
      std::uint32_t k = kNone;
      for (std::uint32_t v : t) {
        if (tileAt[v] == kNone) continue;
        if (tileAt[v] == kTwo || (k != kNone && k != tileAt[v])) return kTwo;
        k = tileAt[v];
      }
      return k;
    };
    for (const auto* list : {&done, &waiting})
      for (const Tri& t : *list)
        if (const std::uint32_t k = ringOf(t); k == kTwo) {
          for (std::uint32_t v : t)
            if (tileAt[v] < kTwo) clash[tileAt[v]] = 1;
        } else if (k != kNone) {
          rings[k].push_back(t);
        }
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
      for (const Tri& t : tiles[k])
        for (std::uint32_t v : t)
          if (tileAt[v] == kTwo) clash[k] = 1;
    pool.parallelFor2D(Rect{0, 0, static_cast<int>(tiles.size()), 1}, 1, [&](const Rect& r) {
      // (simplifyPatch() leaves a patch it cannot simplify as it was.)
      for (int k = r.x; k < r.x + r.w; ++k) {
        const size_t t = static_cast<size_t>(k);
        if (!clash[t]) simplifyPatch(vertices, tiles[t], rings[t], maxError, onSurface);
      }
    });
    todo = std::move(waiting);
    for (const auto& t : tiles) todo.insert(todo.end(), t.begin(), t.end());
  }
}

}  // namespace

// Decimates tile by tile (squares in the plate's plane, each triangle in the tile of its
// centroid), in parallel. In each tile the triangles touching a vertex that another tile uses, or
// that an earlier round settled, stay as they are (a ring along the tile's edge); the rest is
// simplified with its border locked, so no new edge ends at a shared vertex and tiles cannot
// disagree. A tile whose result fails the patch check or still folds or has a thin triangle
// (simplifyPatch()), and the rings, go round again in tiles half the size. A ring triangle along a
// simplified patch touches a settled vertex in every later round, so it stays fine to the end: the
// folds a patch is checked for against its ring are the only ones a simplified triangle can make.
// Then, with `onSurface`, the bands' passes: everything simplified again in the seams' tiles and the
// first round's, a new triangle kept only on the surface. Then what is still fine, the rings and
// the tiles that failed, goes through simplifySeams() (unless `seams` is false). Returns the number
// of tiles that failed in the last round.
size_t decimate(TriangleMesh& mesh, double maxError, double tile, double planeX, double planeY, ThreadPool& pool,
                bool seams, const SurfaceCheck* onSurface) {
  std::vector<std::array<std::uint32_t, 3>> todo = std::move(mesh.triangles), done;
  std::vector<std::uint8_t> settled(mesh.vertices.size(), 0);
  size_t failed = 0;
  const double firstTile = tile;
  for (int round = 0; round < 4 && !todo.empty(); ++round, tile *= 0.5) {
    float lo[2] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
    float hi[2] = {-lo[0], -lo[1]};
    for (const auto& t : todo)
      for (std::uint32_t v : t)
        for (int a = 0; a < 2; ++a) {
          lo[a] = std::min(lo[a], mesh.vertices[v][a]);
          hi[a] = std::max(hi[a], mesh.vertices[v][a]);
        }
    // The tiles' edges on the grid's planes (tile is a whole number of cells): a cell's triangles
    // then fall in one tile, and only the vertices on a tile's edge are shared. With edges
    // through the cells, their triangles fell either side by their centroids, and the ring left
    // fine along every edge was about twice as wide (docs/exports.md).
    const double plane[2] = {planeX, planeY};
    for (int a = 0; a < 2; ++a) lo[a] = static_cast<float>(plane[a] + std::floor((lo[a] - plane[a]) / tile) * tile);
    const int tx = std::max(1, static_cast<int>(std::ceil((hi[0] - lo[0]) / tile)));
    const int ty = std::max(1, static_cast<int>(std::ceil((hi[1] - lo[1]) / tile)));
    std::vector<std::vector<std::array<std::uint32_t, 3>>> tiles(static_cast<size_t>(tx) * ty);
    for (const auto& t : todo) {
      const float cx = (mesh.vertices[t[0]][0] + mesh.vertices[t[1]][0] + mesh.vertices[t[2]][0]) / 3.0f;
      const float cy = (mesh.vertices[t[0]][1] + mesh.vertices[t[1]][1] + mesh.vertices[t[2]][1]) / 3.0f;
      const int i = std::clamp(static_cast<int>((cx - lo[0]) / tile), 0, tx - 1);
      const int j = std::clamp(static_cast<int>((cy - lo[1]) / tile), 0, ty - 1);
      tiles[static_cast<size_t>(j) * tx + i].push_back(t);
    }
    todo.clear();
    std::vector<std::uint32_t> owner(mesh.vertices.size(), UINT32_MAX);
    std::vector<std::uint8_t> shared = settled;
    for (size_t k = 0; k < tiles.size(); ++k)
      for (const auto& t : tiles[k])
        for (std::uint32_t v : t) {
          if (owner[v] == UINT32_MAX) owner[v] = static_cast<std::uint32_t>(k);
          else if (owner[v] != k) shared[v] = 1;
        }
    std::vector<std::vector<std::array<std::uint32_t, 3>>> rings(tiles.size());
    for (size_t k = 0; k < tiles.size(); ++k) {
      auto& tris = tiles[k];
      size_t n = 0;
      for (const auto& t : tris) {
        if (shared[t[0]] || shared[t[1]] || shared[t[2]]) rings[k].push_back(t);  // the ring: next round
        else tris[n++] = t;
      }
      tris.resize(n);
      todo.insert(todo.end(), rings[k].begin(), rings[k].end());
    }
    std::vector<std::uint8_t> ok(tiles.size(), 0);
    pool.parallelFor2D(Rect{0, 0, tx, ty}, 1, [&](const Rect& r) {
      for (int j = r.y; j < r.y + r.h; ++j)
        for (int i = r.x; i < r.x + r.w; ++i) {
          const size_t k = static_cast<size_t>(j) * tx + i;
          if (!tiles[k].empty()) ok[k] = simplifyPatch(mesh.vertices, tiles[k], rings[k], maxError);
        }
    });
    failed = 0;
    for (size_t k = 0; k < tiles.size(); ++k) {
      if (tiles[k].empty()) continue;
      if (ok[k]) {
        for (const auto& t : tiles[k]) {
          done.push_back(t);
          for (std::uint32_t v : t) settled[v] = 1;
        }
      } else {
        ++failed;
        todo.insert(todo.end(), tiles[k].begin(), tiles[k].end());
      }
    }
  }
  if (seams && onSurface) {
    // The bands the rounds leave along their tiles' edges (docs/exports.md, "The seams' bands"):
    // the seams' tiles take everything in them, the simplified patches beside a seam too, and
    // simplify it again, kBandPasses times, the seams' tiles and the first round's by turns. A new
    // triangle off the surface counts as a flaw (simplifyPatch()). What is still fine after goes on
    // to the seams' pass as before.
    FineSet fine;
    for (const Tri& t : todo) fine.insert(TriKey(t));
    std::vector<Tri> all = std::move(done), none;
    all.insert(all.end(), todo.begin(), todo.end());
    done.clear();
    for (int pass = 0; pass < kBandPasses; ++pass) {
      const double shift = pass % 2 == 0 ? 0.0 : 0.5 * firstTile;  // (simplifySeams() adds half a tile)
      simplifySeams(mesh.vertices, none, all, kBandError * maxError, firstTile, planeX + shift, planeY + shift, pool,
                    onSurface);
    }
    // The fine triangles left go on in their order before (a tile's triangles in another order
    // would be simplified a little differently).
    FineSet left;
    for (const Tri& t : all)
      if (fine.count(TriKey(t))) left.insert(TriKey(t));
      else done.push_back(t);
    todo.erase(std::remove_if(todo.begin(), todo.end(), [&](const Tri& t) { return !left.count(TriKey(t)); }), todo.end());
  }
  if (seams) simplifySeams(mesh.vertices, done, todo, maxError, firstTile, planeX, planeY, pool);
  mesh.triangles = std::move(done);
  mesh.triangles.insert(mesh.triangles.end(), todo.begin(), todo.end());
  compact(mesh);
  return failed;
}


}  // namespace emboss::mesh_detail

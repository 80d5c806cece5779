// From ink to strokes: thinning, a graph of the skeleton's chains, pruning and joining, and simplification.
#include "capture/skeleton.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

namespace emboss {

namespace {

// The 8 neighbours in ring order: N, NE, E, SE, S, SW, W, NW.
constexpr int kDx[8] = {0, 1, 1, 1, 0, -1, -1, -1};
constexpr int kDy[8] = {-1, -1, 0, 1, 1, 1, 0, -1};

int degree(const Mask& m, int x, int y) {
  int n = 0;
  for (int k = 0; k < 8; ++k) n += m.get(x + kDx[k], y + kDy[k]);
  return n;
}

// True when the set neighbours of (x, y) are at least two and all 8-connected to each other without
// (x, y): removing it then changes neither connectivity nor the ends of lines.
bool redundant(const Mask& m, int x, int y) {
  int idx[8], n = 0;
  for (int k = 0; k < 8; ++k)
    if (m.get(x + kDx[k], y + kDy[k])) idx[n++] = k;
  if (n < 2) return false;
  int group[8];
  for (int i = 0; i < n; ++i) group[i] = i;
  auto find = [&](int i) {
    while (group[i] != i) i = group[i];
    return i;
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const int ax = kDx[idx[i]], ay = kDy[idx[i]], bx = kDx[idx[j]], by = kDy[idx[j]];
      if (std::abs(ax - bx) <= 1 && std::abs(ay - by) <= 1) group[find(i)] = find(j);
    }
  for (int i = 1; i < n; ++i)
    if (find(i) != find(0)) return false;
  return true;
}

Vec2 centre(int p, int w) { return {p % w + 0.5, p / w + 0.5}; }

struct Edge {
  int a = -1, b = -1;  // node ids at the first and last point
  std::vector<Vec2> pts;
  bool alive = true;
  bool closed = false;
};

double segDist(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

// The direction leaving a node along an edge end (first end when atStart), over a few pixels.
Vec2 leaving(const Edge& e, bool atStart) {
  const auto& p = e.pts;
  const size_t n = p.size();
  const size_t k = std::min<size_t>(n - 1, std::max<size_t>(1, std::min<size_t>(8, n / 2)));
  const Vec2 from = atStart ? p[0] : p[n - 1], to = atStart ? p[k] : p[n - 1 - k];
  const double len = std::hypot(to.x - from.x, to.y - from.y);
  return len > 0 ? Vec2{(to.x - from.x) / len, (to.y - from.y) / len} : Vec2{0, 0};
}


// The edge's points starting at the node end (atStart: the edge already starts there).
std::vector<Vec2> fromNode(const Edge& e, bool atStart) {
  std::vector<Vec2> p = e.pts;
  if (!atStart) std::reverse(p.begin(), p.end());
  return p;
}

// The points from arc length `from` on.
std::vector<Vec2> afterArc(const std::vector<Vec2>& p, double from) {
  double s = 0;
  for (size_t i = 1; i < p.size(); ++i) {
    s += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
    if (s >= from) return std::vector<Vec2>(p.begin() + static_cast<long>(i), p.end());
  }
  return {};
}

// A line (point, unit direction) fitted by total least squares to the points at arc length a..b.
std::optional<std::pair<Vec2, Vec2>> fitArc(const std::vector<Vec2>& p, double a, double b) {
  std::vector<Vec2> pts;
  double s = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (i) s += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
    if (s >= a && s <= b) pts.push_back(p[i]);
  }
  if (pts.size() < 3) return std::nullopt;
  double cx = 0, cy = 0;
  for (const auto& q : pts) cx += q.x / pts.size(), cy += q.y / pts.size();
  double sxx = 0, sxy = 0, syy = 0;
  for (const auto& q : pts) sxx += (q.x - cx) * (q.x - cx), sxy += (q.x - cx) * (q.y - cy), syy += (q.y - cy) * (q.y - cy);
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  return std::make_pair(Vec2{cx, cy}, Vec2{std::cos(angle), std::sin(angle)});
}

std::optional<Vec2> intersectLines(const std::pair<Vec2, Vec2>& l1, const std::pair<Vec2, Vec2>& l2) {
  const auto& [p1, d1] = l1;
  const auto& [p2, d2] = l2;
  const double den = d1.x * d2.y - d1.y * d2.x;
  if (std::fabs(den) < 1e-9) return std::nullopt;
  const double t = ((p2.x - p1.x) * d2.y - (p2.y - p1.y) * d2.x) / den;
  return Vec2{p1.x + t * d1.x, p1.y + t * d1.y};
}

double dist(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

class Graph {
 public:
  std::vector<Edge> edges;

  int degree(int node) const {
    int d = 0;
    for (const auto& e : edges)
      if (e.alive && !e.closed) d += (e.a == node) + (e.b == node);
    return d;
  }

  // Joins edges i and j at `node` into i (i's other end first).
  void join(size_t i, size_t j, int node) {
    Edge& e1 = edges[i];
    Edge& e2 = edges[j];
    if (e1.a == node && e1.b != node) std::reverse(e1.pts.begin(), e1.pts.end()), std::swap(e1.a, e1.b);
    if (e2.b == node && e2.a != node) std::reverse(e2.pts.begin(), e2.pts.end()), std::swap(e2.a, e2.b);
    const bool same = e1.pts.back().x == e2.pts.front().x && e1.pts.back().y == e2.pts.front().y;
    e1.pts.insert(e1.pts.end(), e2.pts.begin() + (same ? 1 : 0), e2.pts.end());
    e1.b = e2.b;
    e2.alive = false;
  }

  // A sharp corner thins into a fork at `node`: two arms and a short free branch toward the tip.
  // When the arms' lines meet nearer the tip than the fork, the arms are joined at that point.
  bool rebuildCorner(int node, double w) {
    const auto e = ends(node);
    if (e.size() != 3) return false;
    for (int t = 0; t < 3; ++t) {
      const Edge& tip = edges[e[t].first];
      const size_t i1 = e[(t + 1) % 3].first, i2 = e[(t + 2) % 3].first;
      if (tip.a == tip.b || i1 == i2 || i1 == e[t].first || i2 == e[t].first) continue;
      if (degree(e[t].second ? tip.b : tip.a) != 1) continue;
      const auto tipPts = fromNode(tip, e[t].second);
      if (polylineLength(tipPts) > 6 * w) continue;
      const auto arm1 = fromNode(edges[i1], e[(t + 1) % 3].second), arm2 = fromNode(edges[i2], e[(t + 2) % 3].second);
      const auto l1 = fitArc(arm1, w, 5 * w), l2 = fitArc(arm2, w, 5 * w);
      if (!l1 || !l2) continue;
      const auto x = intersectLines(*l1, *l2);
      const Vec2 apex = tipPts.back(), fork = tipPts.front();
      if (!x || dist(*x, apex) >= dist(*x, fork) || dist(*x, apex) > polylineLength(tipPts)) continue;
      std::vector<Vec2> pts = afterArc(arm1, w);
      std::reverse(pts.begin(), pts.end());
      pts.push_back(*x);
      const auto rest = afterArc(arm2, w);
      pts.insert(pts.end(), rest.begin(), rest.end());
      const int far1 = e[(t + 1) % 3].second ? edges[i1].b : edges[i1].a;
      const int far2 = e[(t + 2) % 3].second ? edges[i2].b : edges[i2].a;
      edges[e[t].first].alive = false;
      edges[i2].alive = false;
      edges[i1].pts = std::move(pts);
      edges[i1].a = far1;
      edges[i1].b = far2;
      return true;
    }
    return false;
  }

  // Both ends of edges at this node: (edge index, at its start?).
  std::vector<std::pair<size_t, bool>> ends(int node) const {
    std::vector<std::pair<size_t, bool>> out;
    for (size_t i = 0; i < edges.size(); ++i) {
      const Edge& e = edges[i];
      if (!e.alive || e.closed) continue;
      if (e.a == node) out.emplace_back(i, true);
      if (e.b == node) out.emplace_back(i, false);
    }
    return out;
  }
};

}  // namespace

void thinZhangSuen(Mask& m) {
  const int w = m.width, h = m.height;
  std::vector<int> del;
  for (bool changed = true; changed;) {
    changed = false;
    for (int pass = 0; pass < 2; ++pass) {
      del.clear();
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          if (!m.at(x, y)) continue;
          int p[8];
          for (int k = 0; k < 8; ++k) p[k] = m.get(x + kDx[k], y + kDy[k]);
          int b = 0, a = 0;
          for (int k = 0; k < 8; ++k) b += p[k], a += (!p[k] && p[(k + 1) % 8]);
          if (b < 2 || b > 6 || a != 1) continue;
          // p[0] N, p[2] E, p[4] S, p[6] W.
          if (pass == 0 && (p[0] * p[2] * p[4] != 0 || p[2] * p[4] * p[6] != 0)) continue;
          if (pass == 1 && (p[0] * p[2] * p[6] != 0 || p[0] * p[4] * p[6] != 0)) continue;
          del.push_back(y * w + x);
        }
      for (int i : del) m.v[i] = 0;
      changed = changed || !del.empty();
    }
  }
}

std::vector<SkeletonPath> traceSkeleton(const Mask& skeleton, const TraceOptions& options) {
  Mask m = skeleton;
  const int w = m.width, h = m.height;
  for (bool changed = true; changed;) {
    changed = false;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (m.at(x, y) && redundant(m, x, y)) m.at(x, y) = 0, changed = true;
  }

  // Nodes: endpoints (one neighbour) alone, junction pixels (three or more) by 8-connected cluster.
  std::vector<int> node(m.v.size(), -1);
  int nodes = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int p = y * w + x;
      if (!m.v[p] || node[p] >= 0) continue;
      const int d = degree(m, x, y);
      if (d == 1) node[p] = nodes++;
      if (d < 3) continue;
      std::vector<int> stack{p};
      node[p] = nodes;
      while (!stack.empty()) {
        const int q = stack.back();
        stack.pop_back();
        for (int k = 0; k < 8; ++k) {
          const int nx = q % w + kDx[k], ny = q / w + kDy[k];
          if (!m.get(nx, ny)) continue;
          const int r = ny * w + nx;
          if (node[r] < 0 && degree(m, nx, ny) >= 3) node[r] = nodes, stack.push_back(r);
        }
      }
      ++nodes;
    }

  Graph g;
  std::vector<std::uint8_t> visited(m.v.size(), 0);
  auto neighbours = [&](int p, int* out) {
    int n = 0;
    for (int k = 0; k < 8; ++k) {
      const int nx = p % w + kDx[k], ny = p / w + kDy[k];
      if (m.get(nx, ny)) out[n++] = ny * w + nx;
    }
    return n;
  };
  for (int p = 0; p < w * h; ++p) {
    if (node[p] < 0) continue;
    int nb[8];
    const int n = neighbours(p, nb);
    for (int k = 0; k < n; ++k) {
      const int q = nb[k];
      if (node[q] == node[p]) continue;
      if (node[q] >= 0) {  // two nodes side by side: a chain of two pixels
        if (p < q) g.edges.push_back({node[p], node[q], {centre(p, w), centre(q, w)}});
        continue;
      }
      if (visited[q]) continue;
      Edge e;
      e.a = node[p];
      e.pts = {centre(p, w), centre(q, w)};
      visited[q] = 1;
      int prev = p, cur = q;
      for (;;) {
        int cn[8];
        const int c = neighbours(cur, cn);
        int next = -1;
        for (int i = 0; i < c; ++i)
          if (cn[i] != prev && (node[cn[i]] >= 0 || !visited[cn[i]])) next = cn[i];
        if (next < 0) break;  // cannot happen on a cleaned skeleton; stop rather than loop
        e.pts.push_back(centre(next, w));
        if (node[next] >= 0) {
          e.b = node[next];
          break;
        }
        visited[next] = 1;
        prev = cur, cur = next;
      }
      if (e.b < 0) e.b = nodes++;  // a dead end: give it its own node
      g.edges.push_back(std::move(e));
    }
  }
  // Loops without any node: a circle, an O.
  for (int s = 0; s < w * h; ++s) {
    if (!m.v[s] || node[s] >= 0 || visited[s]) continue;
    Edge e;
    e.closed = true;
    e.pts = {centre(s, w)};
    visited[s] = 1;
    int prev = -1, cur = s;
    for (;;) {
      int cn[8];
      const int c = neighbours(cur, cn);
      int next = -1;
      for (int i = 0; i < c && next < 0; ++i)
        if (cn[i] != prev && (cn[i] == s ? prev >= 0 && e.pts.size() > 2 : !visited[cn[i]])) next = cn[i];
      if (next < 0) break;
      e.pts.push_back(centre(next, w));
      if (next == s) break;
      visited[next] = 1;
      prev = cur, cur = next;
    }
    e.a = e.b = nodes++;
    g.edges.push_back(std::move(e));
  }

  // Prune spurs, join through two-way nodes and straight crossings, until nothing changes.
  const double cosJoin = std::cos(options.joinAngleDeg * std::numbers::pi / 180.0);
  for (bool changed = true; changed;) {
    changed = false;
    for (int n = 0; n < nodes && !changed; ++n) changed = g.rebuildCorner(n, options.strokeWidth);
    if (changed) continue;
    // The shortest spur first: a free end whose other end is at a junction.
    size_t spur = g.edges.size();
    double spurLen = options.spurLength;
    for (size_t i = 0; i < g.edges.size(); ++i) {
      const Edge& e = g.edges[i];
      if (!e.alive || e.closed || e.a == e.b) continue;
      const int da = g.degree(e.a), db = g.degree(e.b);
      if (!((da == 1 && db >= 3) || (db == 1 && da >= 3))) continue;
      const double len = polylineLength(e.pts);
      if (len < spurLen) spurLen = len, spur = i;
    }
    if (spur < g.edges.size()) {
      g.edges[spur].alive = false;
      changed = true;
      continue;
    }
    for (int n = 0; n < nodes && !changed; ++n) {
      const auto ends = g.ends(n);
      if (ends.size() == 2) {
        if (ends[0].first == ends[1].first) {
          g.edges[ends[0].first].closed = true;  // a loop through its only node
        } else {
          g.join(ends[0].first, ends[1].first, n);
        }
        changed = true;
      } else if (ends.size() >= 3) {
        double best = cosJoin;
        int bi = -1, bj = -1;
        for (size_t i = 0; i < ends.size(); ++i)
          for (size_t j = i + 1; j < ends.size(); ++j) {
            if (ends[i].first == ends[j].first) continue;
            const Vec2 u = leaving(g.edges[ends[i].first], ends[i].second), v = leaving(g.edges[ends[j].first], ends[j].second);
            const double c = u.x * v.x + u.y * v.y;
            if (c < best) best = c, bi = static_cast<int>(i), bj = static_cast<int>(j);
          }
        if (bi >= 0) {
          // The joined stroke passes through: it no longer ends at this node.
          const size_t ei = ends[bi].first, ej = ends[bj].first;
          g.join(ei, ej, n);
          changed = true;
        }
      }
    }
  }

  std::vector<SkeletonPath> out;
  for (const auto& e : g.edges) {
    if (!e.alive || e.pts.size() < 2 || polylineLength(e.pts) < options.minLength) continue;
    SkeletonPath path{e.pts, e.closed};
    if (path.closed && (path.points.front().x != path.points.back().x || path.points.front().y != path.points.back().y))
      path.points.push_back(path.points.front());
    out.push_back(std::move(path));
  }
  return out;
}

double polylineLength(const std::vector<Vec2>& p) {
  double len = 0;
  for (size_t i = 1; i < p.size(); ++i) len += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  return len;
}

std::vector<Vec2> simplifyRdp(const std::vector<Vec2>& pts, double tolerance) {
  const size_t n = pts.size();
  if (n < 3) return pts;
  const bool closed = pts.front().x == pts.back().x && pts.front().y == pts.back().y;
  std::vector<std::uint8_t> keep(n, 0);
  keep[0] = keep[n - 1] = 1;
  std::vector<std::pair<size_t, size_t>> stack;
  if (closed) {
    // Split at the point farthest from the start, so that each half has distinct ends.
    size_t far = 1;
    double best = -1;
    for (size_t i = 1; i + 1 < n; ++i) {
      const double d = std::hypot(pts[i].x - pts[0].x, pts[i].y - pts[0].y);
      if (d > best) best = d, far = i;
    }
    keep[far] = 1;
    stack = {{0, far}, {far, n - 1}};
  } else {
    stack = {{0, n - 1}};
  }
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double best = -1;
    size_t idx = a;
    for (size_t i = a + 1; i < b; ++i) {
      const double d = segDist(pts[i], pts[a], pts[b]);
      if (d > best) best = d, idx = i;
    }
    if (best > tolerance) {
      keep[idx] = 1;
      stack.push_back({a, idx});
      stack.push_back({idx, b});
    }
  }
  std::vector<Vec2> out;
  for (size_t i = 0; i < n; ++i)
    if (keep[i]) out.push_back(pts[i]);
  return out;
}

}  // namespace emboss

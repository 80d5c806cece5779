// A row of offsets at once (SIMD lanes through Highway, a region's inside test from the row's
// crossings) gives what one point at a time gives, bit for bit: the height field is built by rows,
// and dirty updates must equal full frames on every machine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "frep/operation.h"
#include "frep/path_rows.h"

namespace emboss {
namespace {

// The scalar search of PreparedOp::pathDistance2, written out.
void referenceNearest(const std::vector<PathSegment>& segs, double y, double x, std::uint32_t* best, double* bestV) {
  for (std::uint32_t i = 0; i < segs.size(); ++i) {
    const PathSegment& g = segs[i];
    const double px = x - g.ax, py = y - g.ay;
    double v;
    if (g.inv == 0.0) {
      v = px * px + py * py;
    } else {
      double t = (px * g.ex + py * g.ey) * g.inv;
      t = std::min(std::max(t, 0.0), 1.0);
      v = (px - t * g.ex) * (px - t * g.ex) + (py - t * g.ey) * (py - t * g.ey);
    }
    if (i == 0 || !(*bestV <= v)) *bestV = v, *best = i;
  }
}

TEST(PathRows, NearestSegmentsOfARowAreThoseOfEachPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<PathSegment> segs;
    const int count = 1 + trial % 13;
    for (int s = 0; s < count; ++s) {
      const double ax = u(rng), ay = u(rng);
      // Every fifth segment has zero length (a repeated point), and some repeat an earlier one
      // exactly, so that equal distances are met (the first must be kept).
      double ex = s % 5 == 4 ? 0.0 : u(rng), ey = s % 5 == 4 ? 0.0 : u(rng);
      if (s % 7 == 6) segs.push_back(segs.front());
      const double len2 = ex * ex + ey * ey;
      segs.push_back({ax, ay, ex, ey, len2 <= 0.0 ? 0.0 : 1.0 / len2});
    }
    // Rows of every length up to a few vectors (the last points fewer than a vector).
    const int n = trial;
    std::vector<double> xs(static_cast<size_t>(n));
    for (double& x : xs) x = u(rng);
    const double y = u(rng);
    std::vector<std::uint32_t> best(static_cast<size_t>(n), 99);
    std::vector<double> bestV(static_cast<size_t>(n), -1.0);
    nearestSegments(segs, y, xs.data(), n, best.data(), bestV.data());
    for (int k = 0; k < n; ++k) {
      std::uint32_t rb = 0;
      double rv = 0.0;
      referenceNearest(segs, y, xs[static_cast<size_t>(k)], &rb, &rv);
      ASSERT_EQ(best[static_cast<size_t>(k)], rb) << "trial " << trial << " point " << k << " on " << simdTargetName();
      ASSERT_EQ(bestV[static_cast<size_t>(k)], rv) << "trial " << trial << " point " << k;
    }
  }
  EXPECT_STRNE(simdTargetName(), "");
}

TEST(PathRows, OnePointsNearestDistanceIsEachSegmentsMin) {
  // A point's squared distance to a path, a vector of segments at a time (PreparedOp's without
  // gradients: the exporter's and the exact tracer's), is the least of the segments' one at a
  // time, bit for bit, for paths of every length up to a few vectors (the last segments fewer).
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  for (int count = 1; count <= 41; ++count) {
    std::vector<PathSegment> segs;
    for (int s = 0; s < count; ++s) {
      const double ax = u(rng), ay = u(rng);
      const double ex = s % 6 == 5 ? 0.0 : u(rng), ey = s % 6 == 5 ? 0.0 : u(rng);  // a repeated point
      const double len2 = ex * ex + ey * ey;
      // Some segments again, exactly: equal distances, of which the first is the nearest.
      segs.push_back(s % 9 == 8 ? segs[static_cast<size_t>(s / 3)] : PathSegment{ax, ay, ex, ey, len2 <= 0.0 ? 0.0 : 1.0 / len2});
    }
    const PathFields fields(segs);
    ASSERT_EQ(fields.size(), (segs.size() + 7) / 8 * 8);  // (whole chunks of 8: the last repeated)
    for (int k = 0; k < 50; ++k) {
      // Points anywhere, on a segment's end, and on a segment's line.
      double x = u(rng), y = u(rng);
      const PathSegment& g = segs[static_cast<size_t>(k) % segs.size()];
      if (k % 5 == 1) x = g.ax, y = g.ay;
      if (k % 5 == 2) x = g.ax + 0.37 * g.ex, y = g.ay + 0.37 * g.ey;
      std::uint32_t rb = 0;
      double rv = 0.0;
      referenceNearest(segs, y, x, &rb, &rv);
      ASSERT_EQ(nearestDistance2(fields, x, y), rv) << count << " segments, point " << k << " on " << simdTargetName();
      std::uint32_t at = 99;
      ASSERT_EQ(nearestSegment(fields, x, y, &at), rv);
      ASSERT_EQ(at, rb) << count << " segments, point " << k;
    }
  }
}

TEST(PathRows, AChunkPassedOverHoldsNoNearerSegment) {
  // A long path, its segments in chunks whose boxes let a far chunk be passed over: a spiral of 300
  // segments (with repeated points), and points near it, on it, between its turns and far off.
  std::vector<PathSegment> segs;
  double px = 0.0, py = 0.0;
  for (int k = 1; k <= 300; ++k) {
    const double a = 0.21 * k, r = 0.5 + 0.08 * k;
    const double qx = k % 37 == 0 ? px : r * std::cos(a), qy = k % 37 == 0 ? py : r * std::sin(a);
    const double ex = qx - px, ey = qy - py, len2 = ex * ex + ey * ey;
    segs.push_back({px, py, ex, ey, len2 <= 0.0 ? 0.0 : 1.0 / len2});
    px = qx, py = qy;
  }
  // The path going back over some of its segments, exactly, chunks later: the first is nearest.
  for (size_t k = 0; k < 24; ++k) segs.push_back(segs[40 + 3 * k]);
  const PathFields fields(segs);
  ASSERT_GT(fields.boxX0.size(), 30u);
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-40.0, 40.0), t(0.0, 1.0);
  for (int k = 0; k < 3000; ++k) {
    double x = u(rng), y = u(rng);
    const PathSegment& g = segs[static_cast<size_t>(k) % segs.size()];
    if (k % 3 == 1) x = g.ax + t(rng) * g.ex, y = g.ay + t(rng) * g.ey;  // on (or next to) a segment
    if (k % 6 == 2) x *= 100.0, y *= 100.0;                              // far off
    std::uint32_t rb = 0;
    double rv = 0.0;
    referenceNearest(segs, y, x, &rb, &rv);
    ASSERT_EQ(nearestDistance2(fields, x, y), rv) << "point " << k << " at " << x << ", " << y;
    std::uint32_t at = 9999;
    ASSERT_EQ(nearestSegment(fields, x, y, &at), rv);
    ASSERT_EQ(at, rb) << "point " << k << " at " << x << ", " << y;
  }
}

// The scalar odd-parity test the lanes' must equal (operation.cpp's, before it went into lanes).
bool referenceInside(double x, double y, const std::vector<Vec2>& c) {
  bool inside = false;
  for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++) {
    if ((c[i].y > y) != (c[j].y > y)) {
      const double xc = c[j].x + (y - c[j].y) * (c[i].x - c[j].x) / (c[i].y - c[j].y);
      if (x < xc) inside = !inside;
    }
  }
  return inside;
}

TEST(PathRows, TheInsideTestInLanesIsTheScalarOne) {
  // Random contours of every size up to a few vectors, their points on a coarse grid so that rows
  // meet vertices and horizontal edges exactly; and a star, concave, with many crossings a row.
  std::mt19937 rng(23);
  std::uniform_int_distribution<int> grid(-12, 12);
  std::uniform_real_distribution<double> u(-14.0, 14.0);
  int inside = 0, tested = 0;
  for (int n = 0; n <= 40; ++n) {
    std::vector<Vec2> c;
    if (n == 40) {
      for (int k = 0; k < 45; ++k) {
        const double a = 6.283185307179586 * k / 45, r = k % 2 == 0 ? 9.0 : 4.0;
        c.push_back({r * std::cos(a), r * std::sin(a)});
      }
    } else {
      for (int k = 0; k < n; ++k) c.push_back({grid(rng) * 0.5, grid(rng) * 0.5});
    }
    std::vector<double> xy;
    for (const Vec2& p : c) xy.push_back(p.x), xy.push_back(p.y);
    const ContourEdges edges(xy);
    ASSERT_GE(edges.size(), c.size());  // (an edge is listed in every band of heights it meets)
    for (int k = 0; k < 200; ++k) {
      double x = u(rng), y = u(rng);
      if (k % 3 == 1) y = grid(rng) * 0.5;                    // a vertex's row
      if (k % 3 == 2 && !c.empty()) x = c[static_cast<size_t>(k) % c.size()].x, y = grid(rng) * 0.5;
      const bool want = referenceInside(x, y, c);
      ASSERT_EQ(insideContour(edges, x, y), want) << n << " points, at " << x << ", " << y << " on " << simdTargetName();
      inside += want, ++tested;
    }
  }
  // The contours held points, and left others out.
  EXPECT_GT(inside, tested / 20);
  EXPECT_LT(inside, tested - tested / 20);
}

void expectRowEqualsPoints(const Operation& op, double x0, double x1, double y0, double y1) {
  const PreparedOp prepared(op);
  std::mt19937 rng(11);
  for (int row = 0; row < 60; ++row) {
    const double y = y0 + (y1 - y0) * row / 59.0;
    const int n = 1 + row * 3 % 101;
    std::vector<double> xs(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) xs[static_cast<size_t>(k)] = x0 + (x1 - x0) * k / std::max(1, n - 1);
    std::vector<Grad> out(static_cast<size_t>(n));
    prepared.offsetRow(y, xs.data(), n, out.data());
    for (int k = 0; k < n; ++k) {
      const Grad g = prepared.offset(P3<Grad>{Grad(xs[static_cast<size_t>(k)], 1.0, 0.0, 0.0), Grad(y, 0.0, 1.0, 0.0), Grad(0.0)},
                                     Deformation::Sheet);
      const Grad& r = out[static_cast<size_t>(k)];
      ASSERT_EQ(r.v, g.v) << opKindName(op.kind) << " at " << xs[static_cast<size_t>(k)] << ", " << y;
      ASSERT_EQ(r.dx, g.dx) << opKindName(op.kind) << " at " << xs[static_cast<size_t>(k)] << ", " << y;
      ASSERT_EQ(r.dy, g.dy) << opKindName(op.kind) << " at " << xs[static_cast<size_t>(k)] << ", " << y;
    }
  }
}

TEST(PathRows, ARowOfOffsetsIsEachPointsOffset) {
  // A traced line with joints at both ends and a repeated point.
  Operation trace;
  trace.kind = OpKind::Trace;
  trace.side = Side::Front;
  trace.a = 0.6;
  trace.points = {{-8, -2}, {-3, 4}, {-3, 4}, {2, -1}, {7, 3}};
  trace.joinStart = {{-1, -1.2}, 0.6};
  trace.joinEnd = {{1, 0.8}, 0.6};
  expectRowEqualsPoints(trace, -12, 12, -7, 8);
  trace.joinStart = {}, trace.joinEnd = {};
  expectRowEqualsPoints(trace, -12, 12, -7, 8);

  // A concave raised region (a star of 45 points): rows through its spikes cross it many times,
  // and rows through its points meet crossings exactly at vertices.
  Operation region;
  region.kind = OpKind::Region;
  region.side = Side::Back;
  region.height = 0.8;
  region.falloff = 1.5;
  for (int k = 0; k < 45; ++k) {
    const double a = 6.283185307179586 * k / 45, r = k % 2 == 0 ? 9.0 : 4.0;
    region.points.push_back({r * std::cos(a), std::round(r * std::sin(a) * 4.0) / 4.0});
  }
  expectRowEqualsPoints(region, -16, 16, -15, 15);
  region.side = Side::Front;
  expectRowEqualsPoints(region, -16, 16, -15, 15);
  // Two points only: a region that is a line (never inside).
  region.points = {{-3, -1}, {4, 2}};
  expectRowEqualsPoints(region, -9, 9, -7, 7);

  // The kinds without a path go point by point.
  Operation punch;
  punch.kind = OpKind::Punch;
  punch.side = Side::Back;
  punch.at = {1, 2, 0};
  punch.a = 0.5, punch.p = 2.0, punch.q = 3.0;
  expectRowEqualsPoints(punch, -5, 5, -4, 6);
}

}  // namespace
}  // namespace emboss

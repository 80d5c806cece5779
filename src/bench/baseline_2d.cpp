// The plain interval-pruning 2D renderer (baseline_2d.h).
#include "bench/baseline_2d.h"

#include <atomic>
#include <chrono>
#include <cstring>

namespace emboss {

namespace {

constexpr int kTile = 64;  // the threads' unit of work
constexpr int kLeaf = 8;   // cells this small are evaluated pixel by pixel

struct Job {
  const VmProgram* program;
  int size;
  double halfWidth, pixel;  // model units per pixel
  std::uint8_t* mask;
  std::atomic<long>* intervals;
  std::atomic<long>* points;
};

// x of a pixel column's centre and y of a row's (row 0 at the top: +y).
double colX(const Job& j, int px) { return -j.halfWidth + (px + 0.5) * j.pixel; }
double rowY(const Job& j, int py) { return j.halfWidth - (py + 0.5) * j.pixel; }

void fill(const Job& j, int x0, int y0, int n, std::uint8_t v) {
  for (int y = y0; y < y0 + n && y < j.size; ++y) std::memset(j.mask + static_cast<size_t>(y) * j.size + x0, v, std::min(n, j.size - x0));
}

void cell(const Job& j, int x0, int y0, int n, long& intervals, long& points) {
  if (x0 >= j.size || y0 >= j.size) return;
  const Interval ix(-j.halfWidth + x0 * j.pixel, -j.halfWidth + (x0 + n) * j.pixel);
  const Interval iy(j.halfWidth - (y0 + n) * j.pixel, j.halfWidth - y0 * j.pixel);
  const Interval v = j.program->eval(ix, iy, Interval(0.0, 0.0));
  ++intervals;
  if (v.lo > 0.0) return fill(j, x0, y0, n, 0);     // outside (the mask starts at 0, kept for clarity)
  if (v.hi < 0.0) return fill(j, x0, y0, n, 255);   // inside
  if (n > kLeaf) {
    const int h = n / 2;
    cell(j, x0, y0, h, intervals, points);
    cell(j, x0 + h, y0, h, intervals, points);
    cell(j, x0, y0 + h, h, intervals, points);
    cell(j, x0 + h, y0 + h, h, intervals, points);
    return;
  }
  for (int y = y0; y < y0 + n && y < j.size; ++y)
    for (int x = x0; x < x0 + n && x < j.size; ++x) {
      j.mask[static_cast<size_t>(y) * j.size + x] = j.program->eval(colX(j, x), rowY(j, y), 0.0) < 0.0 ? 255 : 0;
      ++points;
    }
}

}  // namespace

Baseline2dResult renderBaseline2d(const VmProgram& program, int size, double halfWidth, ThreadPool& pool) {
  Baseline2dResult r;
  r.mask.assign(static_cast<size_t>(size) * size, 0);
  std::atomic<long> intervals{0}, points{0};
  Job j{&program, size, halfWidth, 2.0 * halfWidth / size, r.mask.data(), &intervals, &points};
  const auto t0 = std::chrono::steady_clock::now();
  pool.parallelFor2D(Rect{0, 0, size, size}, kTile, [&](const Rect& t) {
    long iv = 0, pt = 0;
    cell(j, t.x, t.y, kTile, iv, pt);
    intervals += iv;
    points += pt;
  });
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  r.intervalEvals = intervals;
  r.pointEvals = points;
  for (std::uint8_t m : r.mask) r.insidePixels += m != 0;
  return r;
}

}  // namespace emboss

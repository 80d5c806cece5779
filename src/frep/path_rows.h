// The nearest segment of a path for a whole row of points at once, in SIMD lanes (Highway, the
// widest instruction set of the machine chosen at run time: AVX-512, AVX2 or SSE on a PC, NEON on
// a Raspberry Pi). The height field's update of a traced line or a raised region spends most of its
// time here: every sample under the stroke looks at every segment of the path. One point's
// distance to a path and a region's inside test take a vector of segments or edges at a time (the
// exporter's evaluations of the model spent a sixth of its time on them one at a time).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace emboss {

// A segment a-b of a path, with what its distance works out from its ends alone.
struct PathSegment {
  double ax, ay, ex, ey, inv;  // e = b - a; inv = 1 / |e|^2, 0 for a zero-length segment
};

// For the n points (xs[k], y): the first of the nearest segments (best[k]) and its squared
// distance (bestV[k]), with the arithmetic of kernels::segmentDistance2 and min's choice among equal
// values (the first kept): the same results, bit for bit, as one point at a time.
void nearestSegments(std::span<const PathSegment> segments, double y, const double* xs, int n,
                     std::uint32_t* best, double* bestV);

// A path's segments again, field by field, for one point's distance a vector of segments at a time,
// and the boxes of consecutive chunks of them (a chunk whose box is too far is passed over).
struct PathFields {
  static constexpr size_t kChunk = 8;
  std::vector<double> ax, ay, ex, ey, inv;
  // Chunk c's box: segments c kChunk .. (c + 1) kChunk - 1 (then empty boxes, to whole vectors).
  std::vector<double> boxX0, boxY0, boxX1, boxY1;
  size_t segments = 0;  // the path's own (the fields hold whole chunks: the last one repeated)
  explicit PathFields(std::span<const PathSegment> segments = {});
  size_t size() const { return ax.size(); }
};

// The squared distance from (x, y) to the nearest segment (at least one): kernels::segmentDistance2's
// value for each segment, in its operations, and their min: the same value, bit for bit, as the
// segments one at a time.
double nearestDistance2(const PathFields& path, double x, double y);
// The same, and the first segment with that value (*index), as nearestSegments() has it for one
// point: the same segment.
double nearestSegment(const PathFields& path, double x, double y, std::uint32_t* index);

// A closed contour's edges, each from point i - 1 (j) to point i (the last point to the first
// for i = 0), field by field, listed by bands of height: a row's inside test reads its band's.
struct ContourEdges {
  std::vector<double> ix, iy, jx, jy;  // band b's edges: bandStart[b] .. bandStart[b + 1] - 1
  std::vector<size_t> bandStart;
  double y0 = 0.0, y1 = -1.0, invHeight = 0.0;  // the contour's heights; bands per unit of height
  size_t bands = 0;
  explicit ContourEdges(std::span<const double> xy = {});  // x0, y0, x1, y1, ...
  size_t size() const { return ix.size(); }  // edges listed (an edge once in each band it meets)
  size_t bandOf(double y) const {
    const double b = (y - y0) * invHeight;
    return b <= 0.0 ? 0 : std::min(bands - 1, static_cast<size_t>(b));
  }
};

// The odd-parity (even-odd) inside test of (x, y): the edges that cross its row (one end above y,
// the other not) at an x above it, each crossing at jx + (y - jy) (ix - jx) / (iy - jy) in that
// order of operations, as the scalar test had it (PreparedOp::offsetRow's crossings too).
bool insideContour(const ContourEdges& edges, double x, double y);

// The instruction set nearestSegments runs on here ("AVX3", "AVX2", "NEON", "EMU128", ...).
const char* simdTargetName();

}  // namespace emboss

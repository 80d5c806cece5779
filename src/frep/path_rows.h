// The nearest segment of a path for a whole row of points at once, in SIMD lanes (Highway, the
// widest instruction set of the machine chosen at run time: AVX-512, AVX2 or SSE on a PC, NEON on
// a Raspberry Pi). The height field's update of a traced line or a raised region spends most of its
// time here: every sample under the stroke looks at every segment of the path.
#pragma once

#include <cstdint>
#include <span>

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

// The instruction set nearestSegments runs on here ("AVX3", "AVX2", "NEON", "EMU128", ...).
const char* simdTargetName();

}  // namespace emboss

// From ink to strokes: Zhang-Suen thinning, following the skeleton into polylines, Ramer-Douglas-Peucker.
#pragma once

#include <vector>

#include "capture/gray.h"
#include "frep/operation.h"

namespace emboss {

// Zhang-Suen thinning, in place: a one-pixel-wide, 8-connected skeleton with the mask's topology.
void thinZhangSuen(Mask& mask);

struct SkeletonPath {
  std::vector<Vec2> points;  // pixel centres (gray.h); a closed path repeats its first point last
  bool closed = false;
};

struct TraceOptions {
  double strokeWidth = 3.0;    // pixels: the ink's width (sharp corners leave branches a few widths long)
  double spurLength = 6.0;     // pixels: branches this short that end freely are thinning artefacts
  double minLength = 6.0;      // pixels: shorter paths (specks) are dropped
  double joinAngleDeg = 140.0; // at a crossing, two branches at least this straight are one stroke
};

// Follows a skeleton into paths: endpoints and junctions are nodes, the chains between them edges;
// staircase pixels that would fake junctions are removed first. A sharp corner thins into a fork
// with a short free branch toward the tip: when the two arms' lines meet nearer the tip than the
// fork, the corner is rebuilt at their intersection. Spurs are pruned, chains through two-way nodes
// joined, and at crossings the branches that continue each other straightest become one path.
// Closed loops without nodes (a circle) come out closed.
std::vector<SkeletonPath> traceSkeleton(const Mask& skeleton, const TraceOptions& options = {});

// Ramer-Douglas-Peucker: the fewest points within `tolerance` of the polyline (its ends kept; a
// closed polyline, first point == last, stays closed).
std::vector<Vec2> simplifyRdp(const std::vector<Vec2>& points, double tolerance);

// The length of a polyline.
double polylineLength(const std::vector<Vec2>& points);

}  // namespace emboss

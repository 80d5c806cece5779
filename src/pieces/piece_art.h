// The chaser's bench for authoring pieces in code: curves, and strokes of catalogue tools turned
// into operations exactly as a visitor's strokes are (strokeToOperations).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tools/tool_catalogue.h"

namespace emboss::art {

using Path = std::vector<Vec2>;

// A closed (or open) Catmull-Rom spline through the control points, sampled every `step` mm.
Path spline(const Path& control, bool closed, double step = 0.5);
// A circle (or arc, degrees counter-clockwise from +x) sampled every `step` mm.
Path arc(Vec2 c, double r, double fromDeg, double toDeg, double step = 0.5);
Path circle(Vec2 c, double r, double step = 0.5);
// The path moved, turned (degrees about the origin, then moved) and scaled.
Path transform(const Path& p, double scale, double rotateDeg, Vec2 move);
Path mirrorX(const Path& p);
// The path's length and a point at arc length s.
double length(const Path& p);
Path resampleEvery(const Path& p, double step);
// Inside test for a closed contour (odd parity).
bool inside(const Path& contour, Vec2 q);
// The closed contour moved outward (positive) or inward by d along its normals (small d only).
Path offsetContour(const Path& contour, double d);

// A deterministic hash noise in [0, 1) (the same numbers on every machine and compiler).
double noise(std::uint64_t seed, std::uint64_t i);

// Accumulates a piece's operations in the order a chaser works.
class Chaser {
 public:
  explicit Chaser(std::string metal, double surfaceZ = 0.5);
  // A catalogue tool by name with its size changed (mm; <= 0 keeps the catalogue's).
  static ToolSpec tool(const std::string& name, double size = 0);

  // A stroke of `tool` along `path` with a pressure (0..1), which may vary along the path.
  void stroke(const ToolSpec& tool, const Path& path, double pressure);
  void stroke(const ToolSpec& tool, const Path& path, const std::vector<double>& pressures);
  // One strike of a punch at `at`.
  void strike(const ToolSpec& tool, Vec2 at, double pressure);
  // The region raiser around a closed contour.
  void raise(const Path& contour, double pressure, double falloff = 0);
  // Matting: hammer strikes scattered (jittered grid, `spacing` mm) over the points inside
  // `area` and outside every `holes` contour grown by `keepOff`.
  void matte(const Path& area, const std::vector<Path>& holes, double spacing, double keepOff, double pressure,
             std::uint64_t seed, double size = 0);

  const std::vector<Operation>& operations() const { return ops_; }
  const Metal& metal() const { return metal_; }

 private:
  Metal metal_;
  double z_;
  std::vector<Operation> ops_;
};

}  // namespace emboss::art

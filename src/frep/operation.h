// Operations: the paper's tool applications, each one kernel, one support and one set of parameters.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "frep/box.h"
#include "frep/path_rows.h"
#include "frep/scalar.h"

namespace emboss {

// How offsets change the workpiece. Offset: the paper's literal algebra f_new = f +- f_offset (an
// offset made on one face shows mirrored on the other). Sheet: the sheet bends as a whole; the
// summed offsets D(x, y) move both faces along z, f_new(P) = f(x, y, z - D(x, y)).
enum class Deformation { Sheet, Offset };

// Which face the tool works from. Back raises the metal toward the viewer (+z), front lowers it.
enum class Side { Front, Back };

enum class OpKind { Trace, Punch, Press, Region, BlendUnion, Subtract, BlendSubtract, Patina };

struct Vec2 {
  double x = 0, y = 0;
};
struct Vec3 {
  double x = 0, y = 0, z = 0;
  bool operator==(const Vec3&) const = default;
};

// The shape of a punch for the set-theoretic operations (4): f_tool >= 0 inside the tool.
struct ToolShape {
  enum class Type { Sphere, Cylinder, Flat };
  Type type = Type::Sphere;
  Vec3 center;         // sphere centre; cylinder: one end of its axis; flat: centre of the face box
  Vec3 end;            // cylinder only: the other end of its axis (hemispherical ends)
  double r = 1.0;      // sphere and cylinder radius
  Vec3 half{1, 1, 1};  // flat only: half sizes of the rectangular face box

  // f_tool: sphere r^2 - |P - c|^2 (the paper's); cylinder r^2 - dist(P, axis segment)^2;
  // flat min(hx - |x - cx|, hy - |y - cy|, hz - |z - cz|).
  template <class T>
  T value(const P3<T>& p) const;
  // A box outside which f_tool < 0.
  Box3 bounds() const;
  // The tool's characteristic length L: its radius, or the smallest half size of a flat face.
  double size() const;
};

// Where a trace operation meets the piece of the same stroke before it (its first point) or after it
// (its last point). Both pieces hold the same joint: the direction `dir` there (any length, not
// zero) and the half width `r` (mm) of the stretch over which one piece hands over to the other.
// Each piece's line is continued straight along `dir` for `r` beyond the joint and weighted by a
// smooth step across it, so that the two weights sum to one: the joint is neither deepened (two
// profiles summed) nor dimpled. r = 0: no joint (a free end). See docs/kernels.md.
struct TraceJoin {
  Vec2 dir;
  double r = 0.0;
  bool on() const { return r > 0.0; }
};

// One operation. Only the fields of its kind are meaningful; they are exactly the parameters its
// equation uses (tools and metals have already been folded in when a stroke became an operation).
struct Operation {
  OpKind kind = OpKind::Punch;
  Side side = Side::Back;
  // trace: a; punch and press: a, p, q.
  double a = 1.0, p = 1.0, q = 1.0;
  std::vector<Vec2> points;  // trace and press: the path; region: the closed contour
  TraceJoin joinStart, joinEnd;  // trace: the joints with the stroke's previous and next pieces
  Vec3 at;                   // punch: P1
  double height = 0.5;       // region: the uniform offset inside
  double falloff = 2.0;      // region: the characteristic length of the descent outside (mm)
  ToolShape tool;            // blend_union, subtract, blend_subtract
  double a1 = 0.0, a2 = 1.0, a3 = 1.0;
  // patina: the tinge (an index into tinges(), 1..4: black, brown, green, golden), the brush's
  // strength (0..1) and its radius in `a`; the path in `points`. Colours the metal, moves nothing.
  int tinge = 1;
  double strength = 1.0;

  bool isPatina() const { return kind == OpKind::Patina; }
  // A set operation (4): combines f with a tool's f_tool.
  bool isSet() const { return kind == OpKind::BlendUnion || kind == OpKind::Subtract || kind == OpKind::BlendSubtract; }
  bool isOffset() const { return kind == OpKind::Trace || kind == OpKind::Punch || kind == OpKind::Press || kind == OpKind::Region; }
  // +1 where the operation raises toward the viewer (from behind), -1 where it lowers.
  double sign() const { return side == Side::Back ? 1.0 : -1.0; }
  // The characteristic length L: a for tracers and the patina brush, a / sqrt(q) for punches,
  // falloff for regions, the tool's size for set operations. Exact within 3 L of the tool, zero beyond 4 L.
  double characteristicLength() const;
};

// An operation made ready for evaluation: its parameters checked, its support computed, derived
// data (press points, segment frames) cached. Immutable afterwards; thread-safe to evaluate.
class PreparedOp {
 public:
  explicit PreparedOp(Operation op);
  const Operation& op() const { return op_; }
  // The support in the plate's plane: outside this rectangle the operation changes nothing,
  // exactly (for every z). Culling by it is exact.
  const Box2& support() const { return support_; }
  // The support as convex pieces: every point where the operation changes anything lies within
  // `radius` of the convex hull of one piece's points (a punch: its centre; a traced line, a
  // press, a patina stroke: each segment of its path; a region: its whole contour; a set
  // operation: its tool's box). support() is the box of their union. Far tighter than the box
  // for a round punch or a diagonal line: what a dirty update traces.
  struct SupportPieces {
    double radius = 0.0;
    std::vector<std::vector<Vec2>> pieces;
  };
  SupportPieces supportPieces() const;
  // The signed offset (positive toward the viewer) at p. Offset kinds only.
  template <class T>
  T offset(const P3<T>& p, Deformation model) const;
  // The sheet's offsets with their gradients at the points (xs[k], y), k < n: offset() of each
  // point (Deformation::Sheet), the same values bit for bit. A traced line's and a region's nearest
  // segments are found for the whole row in SIMD lanes (path_rows.h), and a region's inside test
  // from the row's crossings of its contour, not from every edge at every point.
  void offsetRow(double y, const double* xs, int n, Grad* out) const;
  // The set operation applied to f at p. Set kinds only.
  template <class T>
  T combine(const T& f, const P3<T>& p) const;
  // Patina only: how much of its tinge the brush leaves at (x, y), 0..strength: a soft round brush
  // of radius a along the path, (1 - (d/a)^4)^2 at distance d from it (full in the middle, a soft
  // rim, nothing beyond a).
  double patinaAt(double x, double y) const;
  // Region only: whether (x, y) lies inside its closed contour (odd parity, the same test its
  // offset makes).
  bool insideRegion(double x, double y) const;
  // Press only: where the program placed the punches along the path.
  const std::vector<Vec3>& pressPoints() const { return pressPoints_; }
  // op().characteristicLength(), worked out once (evaluation needs it at every point).
  double length() const { return length_; }
  // An upper bound of |grad offset| in the plane (mm/mm), for Lipschitz bounds.
  double maxSlope() const { return maxSlope_; }
  // A trace joint made ready: the joint point, dir / (|dir| r) (the weight's argument is
  // (P - point) . k), and the continuation segment e0-e1.
  struct Joint {
    bool on = false;
    double px = 0, py = 0, kx = 0, ky = 0;
    Vec2 e0, e1;
  };
  // Trace only: the joints with the stroke's previous (0) and next (1) pieces.
  const Joint& joint(int end) const { return joints_[end]; }

 private:
  // Trace and region: per segment of the path (closed for a region), what
  // kernels::segmentDistance2 works out from its ends alone, so that the nearest segment is
  // found without a division per segment.
  using Segment = PathSegment;
  template <class T>
  T pathDistance2(const T& x, const T& y) const;
  // Segment i's squared distance to (x, y), with its gradient.
  Grad segmentDistance2(size_t i, const Grad& x, const Grad& y) const;
  // A traced line's offset at p, its path's squared distance t2 found; a region's outside its
  // contour.
  template <class T>
  T traceOffset(T t2, const P3<T>& p) const;
  template <class T>
  T regionOutside(const T& t2) const;

  Operation op_;
  std::vector<Segment> segments_;
  PathFields pathFields_;   // segments_ field by field (pathDistance2 without gradients)
  ContourEdges contour_;    // a region's contour's edges (its inside test)
  Joint joints_[2];  // start, end
  Box2 support_;
  std::vector<Vec3> pressPoints_;
  double maxSlope_ = 0.0;
  double length_ = 0.0;
  double invA2_ = 0.0, invA3_ = 0.0;  // a blend's 1 / a2 and 1 / a3 (kernels::blendUnionByInverses)
  // Patina: the boxes of its path's segments kPatinaChunk at a time (the points' box, not grown).
  static constexpr size_t kPatinaChunk = 8;
  std::vector<Box2> patinaChunks_;
};

// The physical ranges of an operation's numbers, checked by validate(). Lengths in mm: a sheet and
// its tools fit in a 4 m square, a tool is at least a micrometre.
inline constexpr double kMaxLengthMm = 2000.0;  // sizes, radii, depths, heights; |coordinate| too
inline constexpr double kMinLengthMm = 0.001;   // sizes and radii (a, falloff, r, a2, a3, tool sizes)
inline constexpr double kMaxShape = 1000.0;     // |p| (depth over a) and q, dimensionless; q >= 1/kMaxShape
inline constexpr double kMaxPathPoints = 100000;  // points of a path or contour, punches of a press

// Checks an operation's parameters against their kinds and physical ranges; an empty string when
// it is valid, else what is wrong: the key, the value and the range ("a: 1e+308 is out of range:
// 0.001 to 2000 mm").
std::string validate(const Operation& op);
const char* opKindName(OpKind k);

extern template double PreparedOp::offset(const P3<double>&, Deformation) const;
extern template Grad PreparedOp::offset(const P3<Grad>&, Deformation) const;
extern template Interval PreparedOp::offset(const P3<Interval>&, Deformation) const;
extern template double PreparedOp::combine(const double&, const P3<double>&) const;
extern template Grad PreparedOp::combine(const Grad&, const P3<Grad>&) const;
extern template Interval PreparedOp::combine(const Interval&, const P3<Interval>&) const;

}  // namespace emboss

// The tool catalogue and how a stroke of a tool, on a metal, under a pressure, becomes operations.
#pragma once

#include <string>
#include <vector>

#include "frep/operation.h"
#include "tools/metal.h"

namespace emboss {

enum class ToolKind {
  Tracer,        // traced contour (2): a groove from the front or a raised line from behind
  Punch,         // round punch (3), from behind (raise) or the front (chasing)
  OvalPunch,     // an elongated punch: (3) pressed along a short path
  FlatPunch,     // a flat rectangular face: regions lowered from the front (beating the background down)
  Hammer,        // small front strikes for background texture
  RegionRaiser,  // raises a whole outlined region from behind
  BlendPunch,    // adds material with a blended union (4)
  PatinaBrush,   // a brush of a chemical tinge: colours the metal, settling into the hollows
};

struct ToolSpec {
  std::string name;  // shown on the overlay
  ToolKind kind;
  double size;       // mm: tracer width, punch diameter, hammer face, region falloff
  Side side;
  int tinge = 0;     // patina brush: the tinge (an index into tinges())
};

// The catalogue: tracers of three widths, round punches of several sizes, an oval and a flat
// punch, a hammer, a region raiser, a blending punch and a patina brush of each tinge.
const std::vector<ToolSpec>& toolCatalogue();

// One pen sample mapped onto the sheet: x, y in mm on the workpiece, z of the surface there.
struct StrokePoint {
  double x = 0, y = 0, z = 0;
  double pressure = 0;  // 0..1
};

// Depth of the tool's penetration: linear in pressure (the paper), scaled by the metal's ductility
// ("tip feel") and the tool's size. mm.
double penetrationDepth(const ToolSpec& tool, const Metal& metal, double pressure);

// The operations a whole stroke makes. Tracers: the path, simplified, split into segments of at
// most kTraceSegment mm (one trace operation each); punches and hammers: strikes spaced along the
// path; flat punch: its face lowered at points exactly evenly spaced, overlapping, turned along
// the stroke;
// region raiser: the stroke is the closed contour; blending punch: blended spheres along
// the path; patina brush: one patina operation along the whole stroke (handed out when the pen
// lifts), its strength from the mean pressure. The parameters are exactly those the equations use.
std::vector<Operation> strokeToOperations(const ToolSpec& tool, const Metal& metal, const std::vector<StrokePoint>& stroke);

// Single strikes, used by the stroke builder and the attract pieces.
Operation traceOp(const ToolSpec& tool, const Metal& metal, const std::vector<Vec2>& path, double pressure);
Operation punchOp(const ToolSpec& tool, const Metal& metal, const Vec3& at, double pressure);

inline constexpr double kTraceSegment = 4.0;  // mm
// The flat punch's strikes are regions of its face lowered from the front: their falloff round the
// face over the punch's size, and how many faces cover each point of a line (their spacing is the
// face's length along the stroke over this).
inline constexpr double kFlatPunchFalloff = 0.2;
inline constexpr int kFlatPunchOverlap = 3;
// The region's descent outside its contour integrated across, in units of its falloff (about 1.29):
// a line of strikes sinks by their height times (face + 2 falloffs x this) / spacing.
double flatPunchDescent();

// Joins the consecutive trace operations ops[first..] of one line where one ends at the point the
// next starts from (TraceJoin: no bead at the joints). The joint's direction bisects the turn from
// the piece before's last segment to the next piece's first, and its half width is
// min(1.5 a, 0.4 length, 1.6 mm) of the piece before times the cosine of half the turn (at least
// a quarter; docs/kernels.md, "Trace joints"). So a piece is final once the next piece's first
// segment is (StrokeBuilder::settled()).
// A closed line of two pieces or more (the last ends within kCloseTolerance of where the first
// starts: a drawn circle, a captured contour) is joined where it closes as well: the last piece's
// end is moved onto the first's start and the first piece gets that joint as its start. Only the
// whole line can say that it closes: the first piece changes then (StrokeBuilder::end() hands it
// out again); a pen's stroke ends that close to its start only when a program draws it.
inline constexpr double kCloseTolerance = 1e-6;  // mm
void joinTracePieces(std::vector<Operation>& ops, size_t first = 0);

}  // namespace emboss

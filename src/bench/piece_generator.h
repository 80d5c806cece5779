// Generated reliefs for benchmarks and tests: contours traced in short segments, punches from both
// sides, a few raised regions and blends, spread over a workpiece like a real chased piece.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "frep/model.h"
#include "scene/scene.h"

namespace emboss {

// A deterministic random source (the same numbers on every platform and library).
class PieceRandom {
 public:
  explicit PieceRandom(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  bool chance(double p) { return unit() < p; }
  int below(int n) { return static_cast<int>(unit() * n); }

 private:
  double unit() { return static_cast<double>(engine_() >> 5) * (1.0 / 134217728.0); }
  std::mt19937 engine_;
};

struct GeneratedPiece {
  std::shared_ptr<const Workpiece> workpiece;
  Deformation deformation = Deformation::Sheet;
  std::vector<Operation> operations;
  CameraSpec camera;  // defaultCamera() of the workpiece

  Result<Model> makeModel() const;
};

enum class PieceShape { Plate, Disc };

struct PieceOptions {
  PieceShape shape = PieceShape::Plate;
  double width = 297.0, height = 210.0;  // plate: A4; disc: the diameter is min(width, height)
  double halfThickness = 0.4;            // a 0.8 mm sheet
  Deformation deformation = Deformation::Sheet;
  // Scale of the tools (1: a museum piece's tracers and punches; tests use larger ones).
  double toolScale = 1.0;
};

// About `operations` operations (exactly that many) in the order an artist would make them:
// motif by motif, a raised region first (about one per thousand operations, at least one), the
// outline traced in segments of about 2.5 mm from the front, the inside bossed up with punches
// from behind, the background beaten down around it from the front, a blend (a soldered bead)
// now and then. Deterministic for a given (operations, seed, options).
GeneratedPiece generatePiece(int operations, unsigned seed, const PieceOptions& options = {});
// Moves every operation of the piece by (dx, dy) in the plate's plane (paths, points, tools):
// a relief generated around the origin put onto a workpiece centred elsewhere.
void moveOperations(GeneratedPiece& piece, double dx, double dy);

// An imported workpiece: a medallion outline from the vm generator (generateVmRelief(clauses,
// outlineSeed)), `scale` mm per unit and 2 halfThickness thick, with a relief of `operations`
// generated over its bounds (generatePiece with `seed`) and moved onto it; only the strokes when
// `strokesOnly` (a set operation on an outline sheet is traced with the program's own intervals,
// slowly). Seen by defaultCamera().
Result<GeneratedPiece> generateOutlinePiece(int clauses, unsigned outlineSeed, double scale, double halfThickness,
                                            int operations, unsigned seed, bool strokesOnly);

// One more stroke somewhere on the piece's surface (for dirty-update timings): a punch from
// behind, or one traced segment from the front.
Operation randomPunch(PieceRandom& rng, const GeneratedPiece& piece, double toolScale = 1.0);
Operation randomTraceSegment(PieceRandom& rng, const GeneratedPiece& piece, double toolScale = 1.0);
// A raised region from behind as a visitor draws one: a closed wobbly outline of 24 to 48 points,
// 6 to 14 mm across its radius (times toolScale).
Operation randomRegion(PieceRandom& rng, const GeneratedPiece& piece, double toolScale = 1.0);
// A random set operation (blend_union, subtract or blend_subtract) on the surface.
Operation randomSetOperation(PieceRandom& rng, const GeneratedPiece& piece, double toolScale = 1.0);

}  // namespace emboss

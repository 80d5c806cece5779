// The ray tracer: the model's function traced on the fixed thread pool, whole frames or dirty rectangles.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "frep/model.h"
#include "frep/op_grid.h"
#include "frep/vm_model.h"
#include "render/camera.h"
#include "render/height_field.h"
#include "render/image.h"
#include "render/patina_cache.h"
#include "render/pixel_spans.h"
#include "render/set_op_bins.h"
#include "render/set_op_bounds.h"
#include "render/shading.h"
#include "render/thread_pool.h"
#include "render/walk_lanes.h"
#include "util/uninitialized.h"

namespace emboss {

struct RenderStats {
  std::uint64_t rays = 0;
  std::uint64_t hits = 0;
  std::uint64_t steps = 0;        // root-finder steps (jumps, cells, interval tests, subdivisions) over all rays
  std::uint64_t evaluations = 0;  // function evaluations (point, gradient and interval)
  std::uint64_t opsVisited = 0;   // operation kernels evaluated over all evaluations
  std::uint64_t fieldEvaluations = 0;  // evaluations whose displacement came from the cached field
  double traceSeconds = 0.0;      // time spent finding surfaces (wall clock per tile, summed over tiles)
  double shadeSeconds = 0.0;      // time spent on the second pass: edges' extra rays, sRGB (likewise)
  std::uint64_t edgePixels = 0;   // pixels anti-aliased with two extra rays
  std::uint64_t reshaded = 0;     // rays not traced again: their kept hit shaded anew
  std::uint64_t denseRays = 0;    // field-tracer rays through a tangle of set operations (kDenseSetOps)
  std::uint64_t laneRays = 0;     // field-tracer rays whose walk went into SIMD lanes (walk_lanes.h)
  std::uint64_t setOpsLeftOut = 0;  // set operations whose support meets a ray's reach but whose box it misses
  std::uint64_t windowSteps = 0;  // Lipschitz steps inside set operations' windows (RenderOptions::lipschitzInWindows)
  std::uint64_t farSteps = 0;     // steps inside balls' far windows, alone or in lanes (RenderOptions::ballFarWindows)
  std::uint64_t pileSkips = 0;    // skips above the pile's tops inside set operations' windows (RenderOptions::pileTops)
  double meanStepsPerRay() const { return rays ? static_cast<double>(steps) / rays : 0.0; }
  double meanOpsPerEvaluation() const { return evaluations ? static_cast<double>(opsVisited) / evaluations : 0.0; }
  double meanEvaluationsPerRay() const { return rays ? static_cast<double>(evaluations) / rays : 0.0; }
  RenderStats& operator+=(const RenderStats& o) {
    rays += o.rays, hits += o.hits, steps += o.steps, evaluations += o.evaluations, opsVisited += o.opsVisited;
    fieldEvaluations += o.fieldEvaluations, edgePixels += o.edgePixels, traceSeconds += o.traceSeconds, shadeSeconds += o.shadeSeconds;
    reshaded += o.reshaded, denseRays += o.denseRays, laneRays += o.laneRays, setOpsLeftOut += o.setOpsLeftOut;
    windowSteps += o.windowSteps, farSteps += o.farSteps, pileSkips += o.pileSkips;
    return *this;
  }
};

struct RenderOptions {
  bool naive = false;  // no index and no field: every active operation at every point (for comparison)
  int tileSize = 32;
  bool exact = false;  // sheet model: trace the exact function through the index instead of the field
  // Outline sheets: their program specialised per leaf of the column map (false: the whole
  // program everywhere; the same picture, slower; for comparison).
  bool specialisedOutline = true;
  // Outline sheets without set operations: a cell of a ray near the outline (in the slab, its
  // interval test failed) is scanned point by point for its first point with f >= 0 (false:
  // bisected, each half's interval tested first; the same picture, slower; for comparison).
  bool scanOutlineCells = true;
  // Pixels outside the projection of the box that holds every surface are misses without a ray
  // (false: every pixel traced; the same picture, slower; for tests).
  bool cullOutsideClip = true;
  // Field tracer: a ray's list of set operations holds those whose box (support and z range) it
  // crosses or passes within a hair of (false: every one whose support meets the ray's reach; the
  // same picture, slower; for tests).
  bool cullRaySetOps = true;
  // Field tracer: inside a window of subtractions a ray takes Lipschitz steps from high above the
  // sheet, the subtractions' bumps counted (RayContext::winRaise), before the interval tests
  // (false: the interval tests alone; the same picture, slower; for tests).
  bool lipschitzInWindows = true;
  // Field tracer, dirty updates: a pixel whose ray's hit the change cannot move (only its shading:
  // the cavity term, a patina stroke) is shaded again at the hit kept from its last trace instead
  // of traced (false: every ray traced; the same picture, slower; for comparison).
  bool reuseHits = true;
  // Field tracer, plates, discs and outline sheets: a row's rays walk several at once in SIMD lanes
  // where their walks are plain Lipschitz steps (walk_lanes.h), and their normals are found in
  // lanes (false: every ray alone; the same picture, slower; for comparison).
  bool walkLanes = true;
  // Field tracer: an appended raised region over more than kFieldBandMinSamples field samples
  // (the one offset that comes whole, when its contour closes, and the biggest; a stroke's live
  // preview is replaced at every pen event) is added for about this long in sync() (whole rows,
  // at least eight), and the rest by continueField(), so that no frame waits for all of it. The
  // field ends with the same bits however it is cut. 0: at once.
  double fieldBandMs = 0.0;
  // Field tracer, plates and discs, full frames: inside a window of set operations a ray first
  // skips the stretch above the pile's top, column by column (Renderer::pileTop(): each column's
  // bound, found once by intervals and kept until the model changes there), before the window's
  // own steps and interval tests (false: those alone; the same picture, slower; for comparison).
  bool pileTops = true;
  // Field tracer: a ball's window is the ray's stretch in the capsule where it can act, not in its
  // box alone (SetOp::round; false: the box; the same picture, slower; for comparison).
  bool roundWindows = true;
  // Field tracer: a ball's smooth union splits its window into the stretch near the tool and the
  // stretches beyond it (SetOp::farRaise), where a ray takes Lipschitz steps as outside the
  // windows (false: interval tests over the whole window; the same picture, slower; for comparison).
  bool ballFarWindows = true;
  // Patina strokes of a brush at least PatinaCache::kMinReach wide: a hit reads their amounts from
  // a lattice of nodes kept block by block (patina_cache.h) instead of its distance to each stroke
  // (false: every stroke worked out at every hit; nearly the same picture, slower; for comparison).
  bool patinaLattice = true;
};

// Two tracers share one contract (docs/rendering.md): a pixel's colour depends on nothing but the
// model, the camera and the pixel -- not on the tile, the thread, earlier frames or the model's
// overall bounds -- so a dirty update gives exactly the bytes of a full render.
//
// The field tracer (sheet model; the default): f(P) = W(x, y, z - D(x, y)) with D from the
// HeightField cache, the set operations applied exactly on top (their shifts cached the same
// way). The points of a ray are t = q h / 16 for integers q, fixed by the camera and the
// workpiece; the hit is the first of them with f >= 0, refined inside [q - 1, q]. Bounds only
// prove stretches empty, never decide: a Lipschitz walk (plate, disc, bowl, and 2D vm outlines
// through their column map) with D's slopes from the field's pyramid, interval bounds where set
// operations act or the workpiece has no known bound.
//
// The exact tracer (offset model, --naive, RenderOptions::exact): the model's own function
// through the operation grid (or every operation), interval-bounded spans of 8 steps and
// thin-feature splits, as the definition demands; slower, independent of any cache.
class Renderer {
 public:
  explicit Renderer(ThreadPool& pool) : pool_(pool) {}

  // Brings the index and the field up to date with the model (call after edits, never during a
  // render). Appends cost the new operation's support; undo recomputes the samples under it.
  void sync(const Model& model);
  void setCamera(const Camera& camera);
  // How many backdrops setCamera() has computed: one per picture size, unless that size has
  // fallen out of the kept ones (backdrops_).
  size_t backdropsMade() const { return backdropsMade_; }
  // Also builds the metal's shading tables on the pool the first time a metal is seen.
  void setShading(const ShadingParams& shading) {
    shading_ = shading;
    prepareShading(shading_.metal, &pool_);
  }
  void setOptions(const RenderOptions& options) { options_ = options; }

  // Traces every pixel of `rect` into `image` (sized to the camera). Returns false if cancelled
  // (the pixels of `rect` are then partly old); a frame superseded by a newer one is cancelled by
  // setting `cancel` from any thread. With RenderOptions::reuseHits a pixel the last sync() cannot
  // have moved the hit of is shaded at its kept hit; renderFull() traces every ray.
  bool render(Image& image, const Rect& rect, RenderStats* stats = nullptr, const std::atomic_bool* cancel = nullptr);
  // The same over the pixels of `spans` (a dirty update's, dirtySpans()).
  bool render(Image& image, const PixelSpans& spans, RenderStats* stats = nullptr, const std::atomic_bool* cancel = nullptr);
  bool renderFull(Image& image, RenderStats* stats = nullptr, const std::atomic_bool* cancel = nullptr);
  // Renders started from now on stop, as if cancelled, within a row of a tile once the clock
  // passes `deadline` (none: never); the rays traced before it keep their hits, so the pixels
  // traced again after it are shaded again rather than traced.
  void setDeadline(std::optional<std::chrono::steady_clock::time_point> deadline) { deadline_ = deadline; }
  // Renders from now on give an edge pixel its two more rays (the default), or one ray every
  // pixel and no ring around the spans (a coarse picture the kiosk enlarges: at 16 pixels a
  // sample nearly every pixel over a pile of set operations is a crease, and its extra rays
  // tripled the picture's cost).
  void setAntialias(bool on) { antialias_ = on; }

  // The pixels whose rays can see a change made by operation `index` of the model (just appended,
  // or just undone): the projection of the 3D box where f can change sign or where a hit's
  // neighbourhood (its normal, its cavity term) can change, grown by one ray cell, and by one
  // pixel for the anti-aliasing. Call after sync().
  // Row by row: for a stroke (an offset or a patina stroke on the field tracer) the projection of
  // its support's convex pieces (PreparedOp::supportPieces) rather than of its box; a round
  // punch's is about three quarters of its rectangle, a diagonal line's much less.
  PixelSpans dirtySpans(const Model& model, size_t index) const;

  // Whether an append is still being added to the field a band of rows at a time
  // (RenderOptions::fieldBandMs): the picture then shows its rows added so far.
  bool fieldPending() const { return pending_.active; }
  // The point of the surface on the ray through image point (sx, sy) of `camera`, as the
  // renderer traces it (nullopt: the ray misses), into `hit`; false when the renderer cannot
  // answer for that model and camera: another model, or the model edited since the last sync(),
  // a field still rising a band at a time, or another camera. (The kiosk's pen, over a pile of
  // set operations: one ray instead of the exact model's intervals along it.)
  bool pick(const Model& model, const Camera& camera, double sx, double sy, std::optional<glm::dvec3>& hit) const;
  // Adds the next rows of that append for about `budgetMs` (whole rows, at least eight)
  // and returns the pixels that can change with them (to trace, as dirtySpans()); the last rows
  // end it. Nothing pending: nothing done, empty spans. Call between renders, as sync().
  PixelSpans continueField(double budgetMs);
  // An append over fewer field samples than this is added at once whatever fieldBandMs says.
  static constexpr long kFieldBandMinSamples = 16384;
  // An append under set operations over at most this many field samples has its values kept for
  // their shift fields (32 bytes a sample while sync() runs).
  static constexpr long kSharedValuesMaxSamples = 1L << 19;
  // A run's set operation shares the shift field of the group before it while the group's box
  // stays within this many times the area of its members' windows (SetOp::shift).
  static constexpr double kShiftShareSlack = 1.5;
  // The pixels of the rows the last sync() added of an append that was still pending
  // (SyncInfo::pendingRows): to trace beside the new operations' dirtySpans().
  PixelSpans pendingSpans() const;

  const OpGrid& grid() const { return grid_; }
  const HeightField& field() const { return field_; }
  double stepLength() const { return step_; }
  // Whether render() uses the field tracer with the current options.
  bool usesField() const { return fieldReady_ && !options_.naive && !options_.exact; }
  // D(x, y) as the field tracer sees it (the field inside its domain, the exact sum outside).
  double displacementAt(double x, double y) const;
  // What the last sync() did (for benchmarks and tests).
  struct SyncInfo {
    bool rebuilt = false;      // the whole field was (re)built
    long samplesUpdated = 0;   // field samples added to or recomputed
    // The rows of an append still pending (fieldPending()) that it added first, the model having
    // changed; empty when none: their pixels are pendingSpans().
    Box2 pendingRows{0, 0, -1, -1};
    double pendingPeak = 0.0;
    // Samples of the set operations' shift fields an append was added to (since the sync,
    // continueField() included): from its values found once on the field's lattice, or evaluated
    // by the shift field itself.
    long shiftSamplesShared = 0, shiftSamplesComputed = 0;
  };
  const SyncInfo& lastSync() const { return lastSync_; }
  // For tests: the set operations (in index order) and their shift fields (null: none).
  size_t setOperationCount() const { return setOps_.size(); }
  const HeightField* shiftField(size_t k) const { return setOps_[k].shift.get(); }
  // For tests: W over a box as the field tracer bounds it (after sync(); outline sheets through
  // their specialised tapes).
  Interval workpieceBound(const P3<Interval>& box) const { return workpieceValue(box); }
  // For tests: an outline sheet's column bounds of min(O, d) at (x, y) (after sync()): the ones the
  // walk reads (a sub-cell's where the outline crosses or comes near the block), and its block's.
  struct ColumnBounds {
    float lo, hi, blockLo, blockHi;
    bool sub;  // the block has sub-cells
  };
  ColumnBounds columnBoundsAt(double x, double y) const {
    const ColumnMap& c = columns_;
    const ColumnMap::Column a = c.at(x, y);
    const int i = floorToInt((x - c.x0) * c.inv), j = floorToInt((y - c.y0) * c.inv);
    const ColumnMap::Column b = c.block(i, j);
    return {a.lo, a.hi, b.lo, b.hi, c.subCellsOf(i, j) >= 0};
  }
  // The bytes held for the model followed: the height field, the index, the set operations'
  // shift fields.
  size_t memoryBytes() const;

 private:
  struct Hit {
    glm::dvec3 p, n, dir;
    double t = 0.0;  // p = origin + t dir of the pixel's ray
  };
  // The centre rays' hits at one camera: per pixel t along the ray, +inf a miss, NaN not known.
  // Kept while the geometry those rays saw stands: sync() forgets the pixels a change can move
  // (the projection of what it changes in f, without the shading's reach), a change of the set
  // operations or a rebuild all of them. The last three cameras' (the frame's, a preview's or a
  // coarse picture's, and the coarsest a stopped coarse picture falls back to).
  // An edge pixel's two sample rays' hits are kept the same way (forgotten by the same test, ray
  // by ray), so that an edge a change cannot reach is shaded again rather than sampled again.
  // `t` and `samples` are left uninitialized when they grow (UninitializedVector): `t` is filled
  // before it is read (`blank`), and of `samples` only the edges' slots are ever written, so only
  // their pages are touched. Value-initialized, the three slots' first growth at 1280x800 (25 MB
  // each) cost a camera in motion's second and third frames 50 to 80 ms each in page faults
  // (attract mode's first tick missed; docs/performance.md, "Stop 72").
  struct HitCache {
    std::optional<Camera> camera;
    UninitializedVector<double> t;
    // Per pixel its edge samples' t (+inf a miss, NaN not known), two a pixel, read only where
    // `sampled` is 1. `sampled` is empty when none is known (a new camera, everything forgotten)
    // and set up by the next render() that anti-aliases.
    UninitializedVector<double> samples;
    std::vector<std::uint8_t> sampled;
    // Set by setCamera() for a new camera: `t` is to be all NaN, filled by the next render() (a
    // camera in motion is set several times a frame, and each fill was 8 MB at 1280x800).
    bool blank = false;
  };
  HitCache hitCaches_[3];  // [0]: the current camera's, then by last use
  std::optional<std::chrono::steady_clock::time_point> deadline_;  // setDeadline()
  bool antialias_ = true;                                         // setAntialias()
  // Forgets the kept hits a sync() may have moved: `followed` whether the model was the one
  // followed before, `setIdsBefore` the set operations' ids before it.
  void forgetMovedHits(bool followed, const std::vector<std::uint64_t>& setIdsBefore);
  bool render(Image& image, const PixelSpans& spans, RenderStats* stats, const std::atomic_bool* cancel, bool reuse);
  struct SetOp {
    std::uint32_t index;
    Box2 support;
    double zlo = 0.0, zhi = 0.0;  // where the operation can change f, the later offsets' shift included
    // Where its tool can change f along z before the shift, with a margin past rounding: at a
    // point whose z less the shift lies outside, combine() is exactly the identity (the taper's
    // zero beyond kSupportSpan tool sizes).
    double toolZlo = 0.0, toolZhi = 0.0;
    // How far past its box (support, zlo..zhi) a ray's list still keeps it (beginWalkFrom()): a
    // millionth of the box's largest coordinate, past the rounding of the ray's points and of the
    // z range's margin.
    double hair = 0.0;
    // A ball's (a sphere tool's): where it can change f is a capsule standing upright, the points
    // within `radius` (its own, kSupportSpan tool sizes and a margin) of its centre moved by any
    // shift between the shift field's bounds, from (cx, cy, czlo) to (cx, cy, czhi). A ray's window
    // is its stretch in the capsule and the box: about a fifth of the box's rays miss the capsule.
    bool round = false;
    double cx = 0.0, cy = 0.0, czlo = 0.0, czhi = 0.0, radius = 0.0;
    // A ball's smooth union (blend_union with a sphere) raises f without bound only near its
    // tool: within `nearRadius` of the capsule's axis. Farther out, f < 0 wherever W < -farRaise
    // (ballFarBound(); docs/rendering.md, "A ball's far windows"), so a ray walks there as
    // outside the windows, its steps shortened by farRaise. farRaise infinite: no such bound
    // (every other set operation).
    double nearRadius = 0.0, farRaise = std::numeric_limits<double>::infinity();
    SetOpUpper upper;  // its upper bounds: over a box (second pass), wherever its tool is (first pass)
    std::uint64_t id = 0;
    // The offsets after it, summed over its support: the shift that moves its tool with the
    // sheet, kept like D (same lattice spacing, same update rules, bit-exact). Its lattice
    // reaches a sample past the support's every side, so that a patch inside the support reads
    // only samples whose twists are central differences: then the set operations of a run (no
    // offset between them: the same offsets after each) hold the same bits wherever their
    // supports meet, and a point reads the run's shift once (fieldValue()). The operations of a
    // run that crowd together (a pile) share one such field over the box of their windows
    // (syncSetOps(), kShiftShareSlack): its owner, the group's first, follows the changes.
    std::shared_ptr<HeightField> shift;
    std::uint32_t run = 0;    // the index in setOps_ of its run's first set operation
    std::uint32_t owner = 0;  // the index in setOps_ of the first set operation sharing its shift
    bool sharesShift = false;  // its shift field is its group's (more than one member)
    // The owner's: its field's samples under the last offset it added, when that was the model's
    // last operation (savedId): put back when a live preview replaces that offset, as the field's are.
    std::shared_ptr<HeightField::Saved> saved;
    std::uint64_t savedId = 0;
  };
  // What a sync changed in the field, for the set operations' shift fields.
  struct FieldChange {
    bool append;          // operation `index` appended (else: `region` recomputed)
    std::uint32_t index;
    Box2 region;
    double peak = 0.0;    // how far the operation appended or removed moves the sheet at most
    const PreparedOp* op = nullptr;  // that operation, while sync() runs (null: not known)
    // An append made a band of rows at a time (the field's pending append): only these rows of
    // the field's lattice.
    bool band = false;
    HeightField::SampleRect rows{};
    // The append's values on the field's lattice, found once for the shift fields under it.
    std::shared_ptr<const HeightField::OffsetValues> values{};
    // A recomputed region that is the field's last append (this operation id) put back: a shift
    // field that saved its samples under it puts them back too.
    std::uint64_t undoneId = 0;
    // Appended right after such an undo: added by the shift fields that put theirs back, summed
    // again by the others.
    bool afterUndo = false;
  };
  // Forgets the kept hits these changes of the field can move (together they move the sheet by
  // at most the sum of their peaks).
  void forgetHitsNear(const std::vector<FieldChange>& changes);
  struct RayContext;

  void syncField(const Model& model);
  void rebuildField(const Model& model);
  void recomputeField(const Model& model, const HeightField::SampleRect& r);
  void syncSetOps(const Model& model);
  // Brings set operation s's shift field up to date with `changes` (`inRegion`: for each change
  // that recomputes a region, the offsets that may reach it, ascending).
  void followFieldChanges(SetOp& s, std::span<const FieldChange> changes,
                          std::span<const std::vector<std::uint32_t>> inRegion, std::vector<const PreparedOp*>& list);
  // Every shift field follows `changes` (in parallel), then the set operations' z ranges.
  void followFieldChanges(std::span<const FieldChange> changes, std::span<const std::vector<std::uint32_t>> inRegion);
  // Each set operation's z range from its tool and its shift field's bounds.
  void refreshSetOpRanges();
  // The offsets after set operation i among `candidates` (ascending) into `list`, the pending
  // append left out (its rows are added as they come).
  std::span<const PreparedOp* const> offsetsAfter(size_t i, std::span<const std::uint32_t> candidates,
                                                  std::vector<const PreparedOp*>& list) const;
  // The box that holds every surface of the field tracer's function (fieldClip_).
  void updateFieldClip(const Model& model);
  double peakOf(const Operation& o) const;
  // Adds rows of the pending append for about `budgetMs` (at least eight), then their
  // twists, bounds and cavities (finish()); returns the rows added.
  // The rows of the field's lattice a band of the pending append stands for, for the shift
  // fields (which can reach past the field's samples): its own, all before it for its first band,
  // all after it for its last; every column.
  HeightField::SampleRect bandRows(const HeightField::SampleRect& band) const;
  // The box of those rows' samples, for the kept hits and the pixels they can change.
  Box2 bandBox(const HeightField::SampleRect& band) const;
  // The values added are kept in `keep` when given (HeightField::add()).
  HeightField::SampleRect addPendingRows(double budgetMs, HeightField::OffsetValues* keep = nullptr);
  // The pixels that rows of samples in `box` can change, an operation moving the sheet by at most
  // `peak` there (as dirtySpans() for an offset).
  PixelSpans fieldRowsSpans(const Box2& box, double peak) const;

  // Rays through image point (sx, sy) (pixel x's centre is x + 0.5).
  std::optional<Hit> traceExact(double sx, double sy, RenderStats& st, std::vector<std::uint32_t>& scratch) const;
  // Without `normal`, the hit's n is left zero: the caller finds it (fieldNormal()).
  std::optional<Hit> traceField(double sx, double sy, RenderStats& st, std::vector<std::uint32_t>& scratch,
                                bool normal = true) const;
  // traceField() in two halves: the ray's set-up (false: it misses the clip box; `rayOps` holds
  // its set operations until its end; its start under the sheet's front face found again up to
  // `startRefinements` times), and its walk from the state `walk` holds. The hit is the same
  // whatever the start (the first grid point with f >= 0).
  struct Walk;
  struct RayStart;
  bool beginWalk(double sx, double sy, RenderStats& st, std::vector<const SetOp*>& rayOps, Walk& walk,
                 int startRefinements) const;
  // beginWalk() of a ray already clipped to the field's box (the rays of findFieldHits(), set up
  // in lanes: ray_lanes.h). Does not count the ray.
  bool beginWalkFrom(const RayStart& start, RenderStats& st, std::vector<const SetOp*>& rayOps, Walk& walk,
                     int startRefinements) const;
  std::optional<Hit> endWalk(Walk& walk, RenderStats& st, std::vector<std::uint32_t>& scratch, bool normal) const;
  // The walk's hit inside the bracket [bq - 1, bq], f there bfa < 0 <= bfb (counted).
  Hit bracketHit(const Walk& walk, long bq, double bfa, double bfb, RenderStats& st, std::vector<std::uint32_t>& scratch,
                 bool normal) const;
  // The hit of the ray through (sx, sy), nothing where it misses. Image points outside `reach`
  // miss. `kept` (field tracer, optional): the pixel's kept hit, used when `reuse` and known, else
  // written with what the trace found. Without `fieldNormal`, a field tracer's hit comes without
  // its normal (n zero), for the caller to find.
  std::optional<Hit> findHit(double sx, double sy, bool field, const Rect& reach, RenderStats& st,
                             std::vector<std::uint32_t>& scratch, double* kept, bool reuse,
                             bool fieldNormal = true) const;
  // Whether the ray through (sx, sy) misses for certain, outside `reach` (findHit()).
  bool missesSurely(double sx, double sy, bool field, const Rect& reach) const;
  // findHit() of the field tracer, without normals, for the rays through image points (xs[i],
  // ys[i]) into out[i], i < count (`kept`: their kept hits, or null), their walks taken in lanes
  // as far as they can be (walk_lanes.h): the same hits.
  void findFieldHits(const double* xs, const double* ys, int count, const Rect& reach, RenderStats& st,
                     std::vector<std::uint32_t>& scratch, double* kept, bool reuse, std::optional<Hit>* out) const;
  // fieldNormal() at n hits with D and its slopes there, in lanes (sheetNormalLanes()) for a plate,
  // a disc or an outline sheet's slab: done[k] says whether (nx, ny, nz)[k] was found (else the caller calls
  // fieldNormal()). Counts the evaluations.
  void sheetNormals(const double* x, const double* y, const double* z, const double* dv, const double* dgx,
                    const double* dgy, int n, double* nx, double* ny, double* nz, bool* done, RenderStats& st) const;
  // Whether the field tracer's walks and normals go into SIMD lanes (RenderOptions::walkLanes,
  // plates, discs and outline sheets, where SIMD has two lanes or more).
  bool walksInLanes() const;
  // The sheet as the lanes read it (walk_lanes.h).
  WalkSheet walkSheet() const;
  // Whether a set-up walk can go into the lanes: after the skips it starts with (which it takes),
  // a plain walk step (no window but a ball's far one, no set operation's support, the slope
  // bound known); `window` gets the next window's first point, `end` the point where the lane is
  // to stop, `far` the ball's far window it may walk through (WalkLanes::farLo..after).
  struct LaneFar {
    long lo = 1, hi = 0, after = 0;
    double raise = 0.0;
  };
  bool walkFitsLanes(Walk& walk, RenderStats& st, long& window, long& end, LaneFar& far) const;
  // The patina's tinges at (x, y) on the sheet: each tinge's strokes there built up.
  Patina patinaAt(double x, double y, std::vector<std::uint32_t>& scratch) const;
  // dirtySpans() before the anti-aliasing's one pixel.
  PixelSpans dirtySpansOfRays(const Model& model, size_t index) const;
  template <class T>
  T exactDisplacement(const P3<T>& p, std::span<const std::uint32_t> candidates, RenderStats& st) const;
  double fieldValue(const RayContext& rc, const glm::dvec3& p, RenderStats& st, std::vector<std::uint32_t>& scratch,
                    double* lipschitzValue = nullptr) const;
  double sheetValue(const glm::dvec3& p) const;
  bool fieldExcluded(const RayContext& rc, const glm::dvec3& a, const glm::dvec3& b, RenderStats& st,
                     std::vector<std::uint32_t>& scratch) const;
  // Whether the set operations `ops` (those of a ray or a column, in the model's order) keep f < 0
  // over `box` (its plane's rectangle `xy`), given f's upper end `fHi` there before them.
  bool setOpsExclude(const SetOp* const* ops, int n, const P3<Interval>& box, const Box2& xy, double fHi,
                     RenderStats& st) const;
  // The pile's top over column (i, j) of pileTops_: f < 0 above it there (found on first use).
  float pileTop(int i, int j) const;
  // The last grid point from q on (at most qEnd) that the pile's tops prove outside along the ray
  // (each point up to it is above its column's top), or q - 1.
  long pileSkip(const Ray& ray, double h8, long q, long qEnd) const;
  // The unit normal of the field model at p. `d`: D and its slopes at p as the field gives them
  // (HeightField::valuesAndGradients()), for the field not to be read again.
  glm::dvec3 fieldNormal(const glm::dvec3& p, RenderStats& st, std::vector<std::uint32_t>& scratch,
                         const Grad* d = nullptr) const;
  Rect projectBox(const Box3& b) const { return projectBox(*camera_, b); }
  static Rect projectBox(const Camera& camera, const Box3& b);
  // The pixels near the projection of a support's convex pieces grown by `grow` (mm), between the
  // box's lowest and highest z (the box's projection where a point is behind the camera).
  static PixelSpans piecesSpans(const Camera& camera, const PreparedOp::SupportPieces& pieces, double grow, const Box3& box);
  // Where an offset over `support` can change f (the field tracer): the support grown by `grow`,
  // between the sheet's lowest and highest z there (workpiece `wb` moved by the field's range)
  // widened by `peak` (what the offset moves it by at most) and a cell, and the heights of the set
  // operations' tools over it.
  Box3 offsetReach(const Box3& wb, const Box2& support, double grow, double peak) const;

  ThreadPool& pool_;
  const Model* model_ = nullptr;
  std::uint64_t syncedRevision_ = 0;  // model_->revision() at the last sync()
  // Its workpiece then, held (so that another model at the same address is never taken for it).
  std::shared_ptr<const Workpiece> syncedWorkpiece_;
  OpGrid grid_;
  // The patina strokes alone (a hit's colour looks them up), in cells as wide as grid_'s.
  OpGrid patinaGrid_{0.0, [](const Operation& o) { return o.isPatina(); }};
  // The amounts of the strokes the lattice keeps (PatinaCache::kept()), and which strokes those are
  // (their ids and supports: the blocks under one that comes or goes are forgotten at sync()).
  PatinaCache patinaCache_;
  std::vector<std::pair<std::uint64_t, Box2>> patinaKept_;
  bool patinaLattice_ = false;  // the lattice serves this model (options_.patinaLattice when synced)
  bool patinaExact_ = false;    // an active stroke the lattice does not keep: looked up at each hit
  void syncPatina(const Model& model, bool followed);
  // Fills a block of the lattice (PatinaCache::at()): the kept strokes' amounts at its nodes
  // (false, nothing written: none reaches it).
  bool patinaBlock(int i0, int j0, float* values) const;
  std::optional<Camera> camera_;
  ShadingParams shading_{};
  RenderOptions options_{};
  double step_ = 0.25;
  Box3 bounds_{};                   // exact tracer: the model's bounds
  std::vector<std::uint32_t> all_;  // 0..active-1, for the naive mode
  // render()'s per-pixel buffers for the ring of its spans, kept between calls (a full frame's are
  // 25 MB: allocated and zeroed anew, their page faults cost a frame a few percent).
  std::vector<glm::vec3> centre_, normal_;
  std::vector<std::uint8_t> hits_;
  // The backdrop of a picture's size, 3 bytes a pixel (it never changes): [0] the camera's, then
  // the sizes before by last use (the frame's while a preview or a coarse picture is traced), so
  // that going back and forth between them computes none again. As many as the sizes a kiosk
  // traces at: the frame's, its preview's, and a coarse picture's at each scale it takes (2 to 16
  // pixels a ray: a scale not kept cost the pen's step up to 2 ms a picture, its rays none; the
  // coarse ones together hold under 2 MB).
  struct Backdrop {
    int w = 0, h = 0;
    std::vector<std::uint8_t> bytes;
  };
  static constexpr size_t kBackdropSizes = 20;
  Backdrop backdrops_[kBackdropSizes];
  size_t backdropsMade_ = 0;

  // The field tracer's state.
  HeightField field_;
  bool fieldReady_ = false;
  bool hasPatina_ = false;  // an active patina stroke: the shading looks them up at each hit
  std::shared_ptr<const Workpiece> fieldWorkpiece_;  // held: its address is never another workpiece's
  std::vector<std::uint64_t> fieldIds_;  // ids of the operations summed into the field, by index
  std::vector<Box2> fieldSupports_;      // their supports
  std::vector<double> fieldPeaks_;       // and how far each moves the sheet at most (peakOf)
  // The samples under the last offset appended, as they were before it (an undo or a replacement
  // of it puts them back).
  struct SavedSamples {
    std::uint64_t id = 0;
    bool valid = false;
    HeightField::Saved samples;
  };
  SavedSamples saved_;
  std::atomic<long> shiftShared_{0}, shiftComputed_{0};  // followFieldChanges()' counts, summed into lastSync_
  // The last offset appended while it is added a band of rows at a time (fieldBandMs):
  // rows r.j0 .. nextRow - 1 of its samples hold it, the rest not yet.
  struct PendingAppend {
    bool active = false;
    std::uint64_t id = 0;
    size_t index = 0;
    HeightField::SampleRect r;
    int nextRow = 0;
    double peak = 0.0;
    bool share = false;  // under set operations: each band's values kept for their shift fields
  };
  PendingAppend pending_;
  int workpieceKind_ = 0;  // 1 plate, 2 disc, 3 bowl (known Lipschitz bounds), 4 outline sheet (2D vm), 0 other
  // Plates, discs and outline sheets: W(x, y, z') <= d - z', so f < 0 wherever z > D + d (above the
  // sheet's front face). d there, else negative.
  double frontThickness_ = -1.0;
  // Outline sheets, W = min(O(x, y), d - |z|), over blocks of 2 x 2 field cells: bounds of
  // min(O, d) per column. Where the slab d - |z'| <= lo, W is the slab bit for bit; where hi < 0,
  // W < 0 at every z.
  // The outline O is evaluated with its program specialised to the block a point or box lies in
  // (where the outline is near), to the leaf of 8 x 8 blocks, or to the region of 4 x 4 leaves
  // (VmProgram::specialised): the same values from a much shorter tape.
  struct ColumnMap {
    static constexpr int kLeaf = 8;    // blocks a leaf is wide
    static constexpr int kRegion = 4;  // leaves a region is wide
    double x0 = 0, y0 = 0, size = 1, inv = 1;
    int nx = 0, ny = 0, leavesX = 0, leavesY = 0, regionsX = 0, regionsY = 0;
    std::vector<float> lo, hi;
    double halfThickness = 0;
    const VmWorkpiece* vm = nullptr;
    std::vector<VmProgram> leafTape, regionTape;
    // The blocks the outline crosses or comes near (neither bound decides W) have their own tape,
    // specialised from their leaf's: blockTape[blockTapeOf[k]] for block k, -1 for none.
    std::vector<VmProgram> blockTape;
    std::vector<std::int32_t> blockTapeOf;
    // Those blocks' sub-cells' bounds (WalkSheet::Columns: kSub x kSub a block, in the order of
    // their tapes): the outline's program is wanted only in the sub-cells it crosses or comes near.
    std::vector<float> subLo, subHi;
    std::vector<std::uint8_t> leafOutside;  // per leaf: 1 when a block of it is outside (hi < 0)
    std::vector<std::uint8_t> leafInside;   // per leaf: 1 when a block of it is not outside
    // Whether some block under the box (mm) is outside, or the box leaves the map.
    bool anyOutside(const Box2& xy) const;
    // The blocks under a box (mm), inclusive; they may lie beyond the map.
    struct Blocks {
      int i0, j0, i1, j1;
    };
    Blocks under(const Box2& xy) const;
    struct Column {
      float lo, hi;
    };
    // The bounds at (x, y): its block's, or its sub-cell's where the block has them (view().at()).
    Column at(double x, double y) const;
    Column block(int i, int j) const;
    // Block (i, j)'s set of sub-cells (its tape's index: WalkSheet::Columns::subIndex), -1 for none
    // or beyond the map.
    std::int32_t subCellsOf(int i, int j) const {
      return i < 0 || j < 0 || i >= nx || j >= ny ? -1 : blockTapeOf[static_cast<size_t>(j) * nx + i];
    }
    // The map as the lanes read it.
    WalkSheet::Columns view() const {
      return {x0, y0, inv, nx, ny, lo.data(), hi.data(), blockTapeOf.data(), subLo.data(), subHi.data()};
    }
    // The program specialised to a box holding (x, y); the whole program beyond the map.
    const VmProgram& tapeAt(double x, double y) const;
    // W over a box: through the tape of the box's block, leaf or region when it lies in one; a
    // box across the edges of at most 2 x 2 leaves (or regions) is cut along them and W is the
    // hull of its parts', each through its own leaf's (or region's) tape, which is much shorter
    // than the region's (or the whole program) and bounds tighter. The whole program beyond the map.
    Interval valueOver(const P3<Interval>& p) const;
    size_t memoryBytes() const;
  };
  void buildColumns();
  // Outline sheets: which 8 x 8 pixel tiles a ray can hit a surface from (the projections of the
  // column leaves that are not all outside and of the set operations' boxes, at every height the
  // field tracer's clip box allows). Rebuilt by render() when the camera, the clip box or the set
  // operations changed; empty for other pieces.
  static constexpr int kMaskTile = 8;
  void updateOutlineMask();
  bool outlineMaskMisses(double sx, double sy) const {
    const int tx = std::clamp(static_cast<int>(sx) / kMaskTile, 0, maskTilesX_ - 1);
    const int ty = std::clamp(static_cast<int>(sy) / kMaskTile, 0, maskTilesY_ - 1);
    return outlineMask_[static_cast<size_t>(ty) * maskTilesX_ + tx] == 0;
  }
  std::vector<std::uint8_t> outlineMask_;
  int maskTilesX_ = 0, maskTilesY_ = 0;
  std::vector<double> outlineMaskKey_;
  std::uint64_t cameraGeneration_ = 0;
  // The workpiece at p (an outline sheet's: through the tapes; any other: as it is).
  double workpieceValue(const P3<double>& p) const;
  Grad workpieceValue(const P3<Grad>& p) const;
  Interval workpieceValue(const P3<Interval>& p) const;
  ColumnMap columns_;
  std::vector<SetOp> setOps_;            // active set operations, ascending index
  // The pile of set operations bounded from above column by column (RenderOptions::pileTops): a
  // grid of squares over the field's domain, each holding the height above which f < 0 over it
  // (the workpiece, D and every set operation there, by intervals), NaN until a ray first asks
  // (pileTop(); from any thread: the same value whoever finds it). What the model's changes can
  // move is set back to NaN (refreshPileTops()). Only proves stretches empty: the picture is the
  // same without it.
  struct PileTops {
    double x0 = 0.0, y0 = 0.0, size = 0.0, inv = 0.0;
    int nx = 0, ny = 0;
    std::unique_ptr<std::atomic<float>[]> top;
  };
  mutable PileTops pileTops_;
  bool pileTopsNow_ = false;  // the render under way reads them: a full frame (render())
  // After sync(): every square forgotten (`all`), else those over `changed`; none kept without
  // set operations or for a workpiece other than a plate or a disc.
  void refreshPileTops(bool all, const std::vector<Box2>& changed);
  // Their supports, and which of them meet a place (a ray's set-up, a hit's normal).
  SetOpBins setOpSupports_;
  Box3 fieldClip_{};                     // a box holding every surface of the field tracer's function
  SyncInfo lastSync_{};
  std::vector<FieldChange> fieldChanges_;  // during sync()
};

}  // namespace emboss

// `emboss bench`: the renderer's benchmark on generated pieces, printed as a table.
#include <algorithm>
#include <iterator>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "app/frame_composer.h"
#include "app/view_orbit.h"
#include "bench/baseline_2d.h"
#include "bench/host_cpu.h"
#include "bench/piece_generator.h"
#include "cli/bench_kiosk.h"
#include "frep/path_rows.h"
#include "frep/vm_generate.h"
#include "frep/vm_model.h"
#include "render/renderer.h"
#include "tools/metal.h"

namespace emboss::cli {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
double cpuMs() { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}
double worst(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

struct Row {
  std::string piece;
  size_t ops = 0;
  double buildMs = 0, frameMs = 0, frameCpuMs = 0, traceCpuMs = 0, shadeCpuMs = 0;
  double punchMs = 0, punchWorstMs = 0, segmentMs = 0, segmentWorstMs = 0, undoMs = 0;
  double regionMs = 0, regionWorstMs = 0, regionPixels = 0;
  double punchPixels = 0, segmentPixels = 0;
  double punchReshaded = 0, segmentReshaded = 0;  // of their centre rays, shaded at kept hits (mean)
  // The same strokes as the kiosk shows them (FrameComposer): the first picture presented, and
  // the last exact pixel traced (means, worst); how many punches were shown coarse first.
  double shownPunchMs = 0, shownPunchWorstMs = 0, shownPunchExactMs = 0, shownSegmentMs = 0, shownSegmentWorstMs = 0;
  long shownPunchCoarse = 0;
  double opsPerEval = 0, stepsPerRay = 0, evalsPerRay = 0;
  double laneShare = 0;  // of a full frame's rays, those whose walk went into SIMD lanes
  double baselineMs = 0;  // the baseline's frames interleaved with this piece's (median)
  double exactOpsPerEval = 0, exactWindowMs = 0;
  double naiveWindowMs = 0, fieldWindowMs = 0, naiveFullEstimateMs = 0;
  std::string window;
  double rendererMb = 0;
  long hits = 0;
  double candidates = 0, candidatesMax = 0;  // the grid's candidates at random points of the piece
  long dirtyDiffer = -1;  // bytes where the picture the strokes' dirty updates left differs from a full frame
};

struct Setup {
  int width, height, threads, frames, strokes;
  bool quick;
};

// The yardstick timed in the same run (bench/baseline_2d.h).
struct Baseline {
  int clauses = 0, size = 0;
  double ms = 0;  // median
  long intervalEvals = 0, pointEvals = 0;
  double inside = 0;  // fraction of the pixels
  double leafTape = 0;
  std::size_t fullTape = 0;
  std::shared_ptr<const VmProgram> program;
  // One more frame of it (ms), or 0 without a program.
  double frame(ThreadPool& pool) const { return program ? renderBaseline2d(*program, size, 1.1, pool).ms : 0.0; }
};

// The piece's default camera moved round its target (the same distance and field of view) to
// `degrees` off the sheet's normal, toward the visitor's side.
CameraSpec tiltedCamera(const CameraSpec& c, double degrees) {
  Orbit o = orbitOf(c);
  o.azimuthDeg = 0.0, o.elevationDeg = 90.0 - degrees;
  return cameraAt(o, c);
}

Baseline measureBaseline(ThreadPool& pool, bool quick) {
  Baseline b;
  b.clauses = quick ? 1000 : 7866;
  b.size = quick ? 256 : 1024;
  auto program = VmProgram::parse(generateVmRelief(b.clauses, 11), "baseline");
  if (!program) {
    std::fprintf(stderr, "emboss bench: baseline: %s\n", program.error().c_str());
    return b;
  }
  b.program = std::make_shared<VmProgram>(std::move(*program));
  std::vector<double> ms;
  for (int i = 0; i < (quick ? 2 : 5); ++i) {
    const Baseline2dResult r = renderBaseline2d(*b.program, b.size, 1.1, pool);
    ms.push_back(r.ms);
    b.intervalEvals = r.intervalEvals, b.pointEvals = r.pointEvals;
    b.leafTape = r.meanLeafTape, b.fullTape = r.fullTape;
    b.inside = static_cast<double>(r.insidePixels) / (static_cast<double>(b.size) * b.size);
  }
  b.ms = median(ms);
  return b;
}

ShadingParams shadingFor(const Model& m) { return sheetShading("copper", "none", m.workpiece().bounds().z1); }

// Times the same window of the frame with the given options; returns ms and fills the stats.
double timeWindow(Renderer& r, const RenderOptions& o, const Rect& window, Image& image, RenderStats& st) {
  r.setOptions(o);
  const auto t0 = Clock::now();
  r.render(image, window, &st);
  const double ms = msSince(t0);
  r.setOptions(RenderOptions{});
  return ms;
}

Row measure(const std::string& name, const GeneratedPiece& piece, const Setup& s, ThreadPool& pool, int naiveWindow,
            const Baseline& baseline) {
  Row row;
  row.piece = name;
  row.ops = piece.operations.size();
  auto built = piece.makeModel();
  if (!built) {
    std::fprintf(stderr, "emboss bench: %s\n", built.error().c_str());
    return row;
  }
  Model model = std::move(*built);
  Renderer r(pool);
  const Camera camera(piece.camera, s.width, s.height);
  r.setCamera(camera);
  r.setShading(shadingFor(model));
  auto t0 = Clock::now();
  r.sync(model);
  row.buildMs = msSince(t0);
  row.rendererMb = r.memoryBytes() / 1e6;  // the field, the index, the shift fields, the outline's tapes
  {
    // What the index alone would make an exact evaluation touch: its candidates at random points
    // of the piece's surface.
    PieceRandom prng(99);
    const Box3 b = model.workpiece().bounds();
    std::vector<std::uint32_t> scratch;
    long n = 0, sum = 0, most = 0;
    for (int i = 0; i < 20000; ++i) {
      const double x = prng.uniform(b.x0, b.x1), y = prng.uniform(b.y0, b.y1);
      if (model.workpiece().value(P3<double>{x, y, 0.0}) < 0.0) continue;
      const long c = static_cast<long>(r.grid().at(x, y, scratch).size());
      ++n, sum += c, most = std::max(most, c);
    }
    row.candidates = n ? static_cast<double>(sum) / n : 0.0;
    row.candidatesMax = static_cast<double>(most);
  }

  // Full frames, no hit reused between them (the model's caches are kept: the field, and the pile's
  // tops the first frame finds), each after a frame of the baseline: the ratio of their medians
  // holds when the machine's speed drifts during the run (a shared host).
  Image image;
  std::vector<double> wall, cpu, base;
  RenderStats st;
  for (int i = 0; i < s.frames; ++i) {
    base.push_back(baseline.frame(pool));
    RenderStats fs;
    const double c0 = cpuMs();
    t0 = Clock::now();
    r.renderFull(image, &fs);
    wall.push_back(msSince(t0));
    cpu.push_back(cpuMs() - c0);
    st = fs;
  }
  row.frameMs = median(wall);
  row.baselineMs = median(base);
  row.frameCpuMs = mean(cpu);
  row.traceCpuMs = st.traceSeconds * 1000.0;
  row.shadeCpuMs = st.shadeSeconds * 1000.0;
  row.opsPerEval = st.meanOpsPerEvaluation();
  row.stepsPerRay = st.meanStepsPerRay();
  row.evalsPerRay = st.meanEvaluationsPerRay();
  row.laneShare = st.rays ? static_cast<double>(st.laneRays) / static_cast<double>(st.rays) : 0.0;
  row.hits = static_cast<long>(st.hits);

  // One more stroke, traced as the kiosk does: add, sync, its dirty spans only. Each is
  // undone again (timed apart) so that every stroke lands on the same piece.
  PieceRandom rng(1234);
  // Adds op and traces its dirty spans (timed, into ms and px), then undoes it (into undoMs).
  auto stroke = [&](const Operation& op, std::vector<double>& ms, double& px, std::vector<double>& undoMs,
                    double* reshaded = nullptr) {
    auto t = Clock::now();
    (void)model.add(op);
    r.sync(model);
    PixelSpans dirty = r.dirtySpans(model, model.activeCount() - 1);
    RenderStats st;
    r.render(image, dirty, &st);
    ms.push_back(msSince(t));
    px += static_cast<double>(dirty.area());
    if (reshaded) *reshaded += static_cast<double>(st.reshaded);
    t = Clock::now();
    model.undo();
    r.sync(model);
    dirty = r.dirtySpans(model, model.activeCount());
    r.render(image, dirty);
    undoMs.push_back(msSince(t));
  };
  std::vector<double> punch, segment, undo;
  double punchPx = 0, segmentPx = 0, punchReshaded = 0, segmentReshaded = 0;
  for (int i = 0; i < 2 * s.strokes; ++i) {
    const bool isPunch = i % 2 == 0;
    const Operation op = isPunch ? randomPunch(rng, piece) : randomTraceSegment(rng, piece);
    stroke(op, isPunch ? punch : segment, isPunch ? punchPx : segmentPx, undo, isPunch ? &punchReshaded : &segmentReshaded);
  }
  // Raised regions (the biggest field update a visitor makes): fewer of them, their undos apart.
  std::vector<double> region, regionUndo;
  double regionPx = 0;
  const int regions = std::max(3, s.strokes / 4);
  for (int i = 0; i < regions; ++i) stroke(randomRegion(rng, piece), region, regionPx, regionUndo);
  // Bit-exact dirty updates: every stroke above was undone again, so the picture their dirty
  // updates left must be the same bytes as a fresh full frame, on any instruction set (under
  // qemu-user arm64 this is the check of the NEON lanes).
  {
    Image full;
    r.renderFull(full);
    row.dirtyDiffer = 0;
    if (full.rgba.size() != image.rgba.size()) row.dirtyDiffer = static_cast<long>(std::max(full.rgba.size(), image.rgba.size()));
    else
      for (size_t i = 0; i < full.rgba.size(); ++i) row.dirtyDiffer += full.rgba[i] != image.rgba[i];
  }
  // The same punches and segments as the kiosk shows them while a visitor draws (FrameComposer,
  // kiosk_app.cpp's step): the first picture presented, coarse where the exact pixels would not
  // fit in the pen's frame, then the rest traced exactly (flush()). The composer follows the
  // model with a renderer of its own; after the strokes and their undos its frame must be a full
  // frame's bytes too.
  {
    FrameComposer composer(pool, s.width, s.height);
    const ShadingParams shading = shadingFor(model);
    std::vector<Rect> changed;
    ViewChanges all;
    all.full = true;
    composer.show(model, piece.camera, shading, all, false);
    composer.flush(changed);
    PieceRandom again(1234);  // the strokes above, again
    std::vector<double> punchFirst, punchExact, segmentFirst;
    for (int i = 0; i < 2 * s.strokes; ++i) {
      const bool isPunch = i % 2 == 0;
      const Operation op = isPunch ? randomPunch(again, piece) : randomTraceSegment(again, piece);
      const std::uint64_t coarseBefore = composer.counters().coarseRects;
      const auto t = Clock::now();
      (void)model.add(op);
      ViewChanges added;
      added.ops.push_back(model.activeCount() - 1);
      composer.show(model, piece.camera, shading, added, false);
      changed.clear();
      composer.work(FrameComposer::kPenStepMs, changed, true, false, t + FrameComposer::kPenFrame);
      (isPunch ? punchFirst : segmentFirst).push_back(msSince(t));
      composer.flush(changed);
      if (isPunch) {
        punchExact.push_back(msSince(t));
        row.shownPunchCoarse += composer.counters().coarseRects > coarseBefore;
      }
      model.undo();
      ViewChanges undone;
      undone.ops.push_back(model.activeCount());
      composer.show(model, piece.camera, shading, undone, false);
      composer.flush(changed);
    }
    row.shownPunchMs = mean(punchFirst), row.shownPunchWorstMs = worst(punchFirst), row.shownPunchExactMs = mean(punchExact);
    row.shownSegmentMs = mean(segmentFirst), row.shownSegmentWorstMs = worst(segmentFirst);
    Image full;
    r.renderFull(full);
    const Image& shown = composer.frame();
    if (full.rgba.size() != shown.rgba.size()) row.dirtyDiffer += static_cast<long>(std::max(full.rgba.size(), shown.rgba.size()));
    else
      for (size_t i = 0; i < full.rgba.size(); ++i) row.dirtyDiffer += full.rgba[i] != shown.rgba[i];
  }
  row.regionMs = mean(region), row.regionWorstMs = worst(region), row.regionPixels = regionPx / regions;
  row.punchMs = mean(punch), row.punchWorstMs = worst(punch);
  row.segmentMs = mean(segment), row.segmentWorstMs = worst(segment);
  row.undoMs = mean(undo);
  row.punchPixels = s.strokes ? punchPx / s.strokes : 0;
  row.segmentPixels = s.strokes ? segmentPx / s.strokes : 0;
  row.punchReshaded = s.strokes ? punchReshaded / s.strokes : 0;
  row.segmentReshaded = s.strokes ? segmentReshaded / s.strokes : 0;

  // The naive renderer (every operation at every point) and the exact tracer through the index,
  // over a window at the centre of the piece; the field tracer over the same window.
  const int ww = naiveWindow, wh = std::max(1, naiveWindow * 5 / 8);
  const Rect window{s.width / 2 - ww / 2, s.height / 2 - wh / 2, ww, wh};
  row.window = std::to_string(ww) + "x" + std::to_string(wh);
  RenderStats fw, nw, ew;
  row.fieldWindowMs = timeWindow(r, RenderOptions{}, window, image, fw);
  RenderOptions naive;
  naive.naive = true;
  row.naiveWindowMs = timeWindow(r, naive, window, image, nw);
  RenderOptions exact;
  exact.exact = true;
  row.exactWindowMs = timeWindow(r, exact, window, image, ew);
  row.exactOpsPerEval = ew.meanOpsPerEvaluation();
  // The naive full frame, scaled from the window by the rays that meet the piece (the window
  // is all piece; rays that miss it cost next to nothing in either renderer).
  row.naiveFullEstimateMs = nw.hits ? row.naiveWindowMs * static_cast<double>(row.hits) / nw.hits : 0.0;
  return row;
}

std::string table(const std::vector<Row>& rows, const Setup& s, int cores, const Baseline& b, const std::string& host) {
  std::string t;
  t += "Machine: " + std::to_string(cores) + " cores reported, " + std::to_string(s.threads) + " render threads; " +
       std::to_string(s.width) + "x" + std::to_string(s.height) + " pixels; medians of " + std::to_string(s.frames) +
       " full frames; means of " + std::to_string(s.strokes) + " strokes of each kind.\n";
  if (!host.empty()) t += "Host, while the baseline and the pieces ran: " + host + ".\n";
  t += "Baseline (same run, same threads): a plain interval-pruning 2D renderer (bench/baseline_2d.h) of a generated " +
       std::to_string(b.clauses) + "-clause vm model at " + std::to_string(b.size) + "x" + std::to_string(b.size) + ": " +
       fmt("%.1f", b.ms) + " ms (median; " + std::to_string(b.intervalEvals) + " interval and " + std::to_string(b.pointEvals) +
       " point evaluations, tapes pruned from " + std::to_string(b.fullTape) + " to " + fmt("%.0f", b.leafTape) +
       " nodes on average in the 8x8 cells, " + fmt("%.0f", 100.0 * b.inside) + "% inside). Target: a full frame <= 1.5x it. "
       "A frame of it runs before each full frame of a piece: \"/ baseline\" is the ratio of the two medians.\n\n";
  t += "| piece | ops | build ms | full frame ms | baseline ms | / baseline | CPU ms/frame (trace + shade) | punch update ms (worst) | segment update ms (worst) | region update ms (worst) | undo ms | shown by the kiosk: punch ms (worst), exact; segment ms (worst) | ops/eval field | index candidates/point (max) | ops/eval exact index | steps/ray | evals/ray | naive window | naive ms (est. full frame) | naive / indexed | renderer MB | dirty = full |\n";
  t += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    const double ratio = r.fieldWindowMs > 0 ? r.naiveWindowMs / r.fieldWindowMs : 0.0;
    t += "| " + r.piece + " | " + std::to_string(r.ops) + " | " + fmt("%.0f", r.buildMs) + " | " + fmt("%.1f", r.frameMs) +
         " | " + fmt("%.1f", r.baselineMs) + " | " + (r.baselineMs > 0 ? fmt("%.2fx", r.frameMs / r.baselineMs) : std::string("-")) + " | " + fmt("%.0f", r.frameCpuMs) + " (" + fmt("%.0f", r.traceCpuMs) + " + " + fmt("%.0f", r.shadeCpuMs) + ")" +
         " | " + fmt("%.2f", r.punchMs) + " (" + fmt("%.2f", r.punchWorstMs) + ")" + " | " + fmt("%.2f", r.segmentMs) + " (" +
         fmt("%.2f", r.segmentWorstMs) + ")" + " | " + fmt("%.1f", r.regionMs) + " (" + fmt("%.1f", r.regionWorstMs) + ")" +
         " | " + fmt("%.2f", r.undoMs) + " | " + fmt("%.2f", r.shownPunchMs) + " (" + fmt("%.2f", r.shownPunchWorstMs) + "), " +
         fmt("%.1f", r.shownPunchExactMs) + "; " + fmt("%.2f", r.shownSegmentMs) + " (" + fmt("%.2f", r.shownSegmentWorstMs) + ")" +
         " | " + fmt("%.2f", r.opsPerEval) + " | " +
         fmt("%.1f", r.candidates) + " (" + fmt("%.0f", r.candidatesMax) + ") | " + fmt("%.1f", r.exactOpsPerEval) + " | " + fmt("%.2f", r.stepsPerRay) + " | " + fmt("%.2f", r.evalsPerRay) + " | " +
         r.window + ": " + fmt("%.0f", r.naiveWindowMs) + " ms vs " + fmt("%.1f", r.fieldWindowMs) + " ms | " +
         fmt("%.0f", r.naiveFullEstimateMs) + " | " + fmt("%.0f", ratio) + "x | " + fmt("%.0f", r.rendererMb) + " | " +
         (r.dirtyDiffer == 0 ? std::string("yes") : r.dirtyDiffer < 0 ? std::string("-") : "NO: " + std::to_string(r.dirtyDiffer) + " bytes") + " |\n";
  }
  t += "\nplate of the vm's size: the vm row's relief and strokes on a plain plate of the medallion's size and thickness, "
       "seen by the same camera (no program: the vm row less this one is what the outline costs).\n";
  t += "build: the first sync (index and displacement field). full frame: wall time of renderFull(). CPU: process CPU time "
       "per frame; trace + shade: thread time summed over tiles. punch / segment update: add + sync + dirty spans (dirtySpans()) "
       "traced, wall time (mean pixels traced, and of their centre rays those shaded at the hit kept from the last trace "
       "instead of traced: ";
  for (const Row& r : rows)
    t += r.piece + " " + fmt("%.0f", r.punchPixels) + " / " + fmt("%.0f", r.segmentPixels) + " (" + fmt("%.0f", r.punchReshaded) +
         " / " + fmt("%.0f", r.segmentReshaded) + "); ";
  t += "). region update: the same for a raised region of 24 to 48 points, 6 to 14 mm in radius (the field under it "
       "found a row at a time in " + std::string(simdTargetName()) + " lanes; mean pixels traced: ";
  for (const Row& r : rows) t += r.piece + " " + fmt("%.0f", r.regionPixels) + "; ";
  t += "). steps/ray, evals/ray: a full frame's; of its rays, those whose walk went into " + std::string(simdTargetName()) +
       " lanes (" + std::to_string(walkLaneCount()) + " rays at once; docs/rendering.md, \"Rays in lanes\"): ";
  for (const Row& r : rows) t += r.piece + " " + fmt("%.0f", 100.0 * r.laneShare) + " %; ";
  t += "(the others miss the piece's box, or start inside a window or a set operation's support). undo: the same after undoing the stroke. shown by the kiosk: the same strokes "
       "through the kiosk's frame composer as a visitor draws (FrameComposer::work() with the pen's step's budget and "
       "frame, as kiosk_app.cpp calls it): from the stroke to its first picture presented, coarse first where the exact "
       "pixels would not fit in the pen's frame (punches shown coarse first: ";
  for (const Row& r : rows) t += r.piece + " " + std::to_string(r.shownPunchCoarse) + " of " + std::to_string(s.strokes) + "; ";
  t += "), and to the last exact pixel traced (flush()). ops/eval field: operation kernels evaluated per function evaluation "
       "by the field tracer (the displacement field stands for the offsets). index candidates: operations the grid "
       "lists at random points of the piece (what an exact evaluation through the index touches). ops/eval exact "
       "index: kernels per evaluation of the exact tracer through the grid over the window. naive: every operation at every point, timed over a window "
       "at the centre against the field tracer over the same window (ratio); the full-frame estimate scales the window "
       "by the rays that hit the piece. renderer MB: what the renderer holds for the model (the displacement field, the index, the set operations' shift fields, an outline's specialised tapes). dirty = full: "
       "after the strokes and their undos, the picture their dirty updates left, and the kiosk's frame composer's, are the same bytes as a fresh full frame "
       "(the bench exits 1 when it is not).\n";
  return t;
}

}  // namespace

int benchMain(const std::string& out, int threads, bool quick, const std::string& only, const std::string& kioskRecording,
              int kioskLoops) {
  auto wanted = [&](const std::string& name) { return only.empty() || name.find(only) != std::string::npos; };
  // A filter that takes no piece (a typing slip) says so instead of printing an empty table.
  const char* const pieces[] = {"A4 plate", "plate 200x150", "disc", "vm medallion"};
  if (!only.empty() && only != "kiosk" && std::none_of(std::begin(pieces), std::end(pieces), wanted)) {
    std::fprintf(stderr, "emboss bench: --only '%s' names no piece (A4 plate, plate 200x150, disc, vm medallion; kiosk: none)\n",
                 only.c_str());
    return 2;
  }
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  ThreadPool pool(threads);
  const std::optional<HostCpuTimes> hostBefore = readHostCpuTimes();
  Setup s{quick ? 320 : 1280, quick ? 200 : 800, pool.size(), quick ? 2 : 5, quick ? 3 : 20, quick};
  std::fprintf(stderr, "emboss bench: baseline, plain interval-pruning 2D renderer...\n");
  const Baseline baseline = measureBaseline(pool, quick);
  std::vector<Row> rows;
  const std::vector<int> sizes = quick ? std::vector<int>{10, 200} : std::vector<int>{10, 850, 3500};
  for (int n : sizes) {
    if (!wanted("A4 plate")) break;
    const GeneratedPiece piece = generatePiece(n, 2001);
    std::fprintf(stderr, "emboss bench: A4 plate, %d operations...\n", n);
    rows.push_back(measure("A4 plate", piece, s, pool, quick ? 16 : (n >= 3500 ? 24 : 48), baseline));
  }
  // Pieces of other character, so the figures hold beyond the A4 generator's own: a smaller plate
  // as densely worked, seen 30 degrees off straight above (rays cross more relief before they
  // hit); a disc of fine tools (punches and tracers at 0.6 of their size: more, smaller features)
  // seen straight down.
  if (wanted("plate 200x150")) {
    PieceOptions o;
    o.width = 200, o.height = 150;
    GeneratedPiece piece = generatePiece(quick ? 200 : 3500, 2003, o);
    piece.camera = tiltedCamera(piece.camera, 30.0);
    std::fprintf(stderr, "emboss bench: plate 200x150, %zu operations, 30 degrees off vertical...\n", piece.operations.size());
    rows.push_back(measure("plate 200x150 at 30°", piece, s, pool, quick ? 16 : 24, baseline));
  }
  if (wanted("disc")) {
    PieceOptions o;
    o.shape = PieceShape::Disc;
    o.width = o.height = 180;
    o.toolScale = 0.6;
    GeneratedPiece piece = generatePiece(quick ? 200 : 3500, 2004, o);
    piece.camera = tiltedCamera(piece.camera, 0.0);
    std::fprintf(stderr, "emboss bench: disc 180 mm of fine tools, %zu operations, from above...\n", piece.operations.size());
    rows.push_back(measure("disc 180 fine tools, above", piece, s, pool, quick ? 16 : 24, baseline));
  }
  // A large imported model: a medallion outline of thousands of vm clauses as the workpiece,
  // with a relief on it.
  if (wanted("vm medallion")) {
    const int clauses = quick ? 400 : 3000;
    std::fprintf(stderr, "emboss bench: vm medallion, %d clauses...\n", clauses);
    // The relief is generated over the model's bounds and moved onto it; strokes only.
    auto piece = generateOutlinePiece(clauses, 7, 45.0, 0.4, quick ? 50 : 300, 2002, true);
    if (!piece) {
      std::fprintf(stderr, "emboss bench: %s\n", piece.error().c_str());
      return 1;
    }
    rows.push_back(measure("vm " + std::to_string(clauses) + " clauses", *piece, s, pool, quick ? 8 : 16, baseline));
    // The same relief on a plain plate of the medallion's size, seen the same way, with the same
    // strokes: what they cost at that view without the program (the row above less this one is
    // the outline's share; docs/performance.md, "Stop 52").
    const Box3 b = piece->workpiece->bounds();
    PieceOptions o;
    o.width = b.x1 - b.x0, o.height = b.y1 - b.y0, o.halfThickness = piece->workpiece->halfThickness();
    GeneratedPiece plate = generatePiece(quick ? 50 : 300, 2002, o);
    std::erase_if(plate.operations, [](const Operation& op) { return !op.isOffset(); });
    std::fprintf(stderr, "emboss bench: the vm medallion's relief on a plain plate of its size...\n");
    rows.push_back(measure("plate of the vm's size", plate, s, pool, quick ? 8 : 16, baseline));
  }
  std::string text = table(rows, s, cores, baseline, stealSentence(hostBefore, readHostCpuTimes()));
  if (!kioskRecording.empty()) {
    std::string error;
    KioskBenchOptions ko{kioskRecording, kioskLoops, threads, quick, s.width, s.height, {}, {}};
    if (baseline.program) ko.baselineFrame = [&] { return baseline.frame(pool); };
    // Beside the report: bench.md keeps the sheet as bench-sheet.json and bench-sheet.png.
    if (!out.empty()) {
      const std::filesystem::path report(out);
      ko.keepSheet = (report.parent_path() / (report.stem().string() + "-sheet")).string();
    }
    const std::string kiosk = kioskBench(ko, error);
    if (kiosk.empty()) {
      std::fprintf(stderr, "emboss bench: kiosk: %s\n", error.c_str());
      return 1;
    }
    text += kiosk;
  }
  std::fputs(text.c_str(), stdout);
  if (!out.empty()) {
    std::ofstream f(out);
    f << text;
    if (!f) {
      std::fprintf(stderr, "emboss bench: cannot write '%s'\n", out.c_str());
      return 1;
    }
  }
  for (const Row& r : rows)
    if (r.dirtyDiffer > 0) {
      std::fprintf(stderr, "emboss bench: %s: the dirty updates left a picture other than a full frame (%ld bytes differ)\n",
                   r.piece.c_str(), r.dirtyDiffer);
      return 1;
    }
  return 0;
}

}  // namespace emboss::cli

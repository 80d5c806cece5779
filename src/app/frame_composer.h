// The frame on screen: dirty rectangles traced at once, whole-frame changes as a quick coarse
// preview refined band by band, so the kiosk answers the pen while a big redraw is under way.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "app/view_changes.h"
#include "render/renderer.h"

namespace emboss {

// Uses only the Renderer's public API. A pixel's final value depends only on the model, the
// camera and the shading (the renderer's guarantee), so tracing a region twice, or in any order,
// gives the same frame as one full render: the composer is free to schedule.
class FrameComposer {
 public:
  FrameComposer(ThreadPool& pool, int width, int height);

  int width() const { return w_; }
  int height() const { return h_; }

  // What to show now. `changes` are the view's changes since the last call. A different model,
  // a full change, another shading or a moved camera start a preview and a refinement; changed
  // operations add their dirty rectangles. With `moving`, a camera in motion: only previews.
  // The two models shown last keep their renderer (index and height field): switching between
  // them does not rebuild either.
  void show(const Model& model, const CameraSpec& camera, const ShadingParams& shading, const ViewChanges& changes,
            bool moving);

  // The renderer that follows `model`, if one does, catches up with it now, though another model
  // is shown: what it held for operations the model no longer has (their index lists, a set
  // operation's field) goes back. For the bench cleared when a visitor leaves.
  void release(const Model& model);
  // The bytes its renderers hold for the models they follow (Renderer::memoryBytes).
  size_t memoryBytes() const;

  // Traces dirty rectangles (always all of them: they are what the visitor just did), then
  // refinement until about `budgetMs` have passed. Appends the rectangles of frame() that
  // changed. Dirty rectangles that would take longer than the dirty budget (a raised region, a
  // big punch close up) are traced coarse first, like a preview, and the call returns so that
  // they are presented at once; their exact pixels come in the next calls, before the bands.
  // `dirtyAlone`: a call that traced dirty rectangles returns after them (a visitor drawing:
  // the stroke is presented before any refinement). `mayWait` (attract mode, on a fixed grid of
  // ticks): dirty rectangles wait for a call with at least kWaitUnlessMs of budget, the start of
  // a period, so that they do not make the next tick late; bands are sized with a margin.
  // `presentBy` (a visitor drawing: the step's start and a frame): the time the dirty rectangles
  // are to be on the screen by. What the step spent before the call (a raised region's field over
  // a pile of set operations) comes off the dirty budget; past it a coarse picture is shown.
  void work(double budgetMs, std::vector<Rect>& changed, bool dirtyAlone = false, bool mayWait = false,
            std::optional<std::chrono::steady_clock::time_point> presentBy = std::nullopt);
  // The last work() left its work for the start of the next period (mayWait): nothing to do
  // until then.
  bool waiting() const { return waiting_; }
  // The kiosk's step while a visitor draws (kiosk_app.cpp, and the bench's strokes as the kiosk
  // shows them): work()'s budget (a pen event that arrives meanwhile waits at most this long
  // before its own stroke is traced), and its presentBy, this long after the step took its pen
  // events (the model's side of the step included): the stroke on the screen, coarse where its
  // exact pixels would not fit in what is left, with the wait for the step within a frame at 60 Hz.
  static constexpr double kPenStepMs = 6.0;
  static constexpr std::chrono::milliseconds kPenFrame{12};
  // The time dirty rectangles may take before the big ones are shown coarse first (6 ms).
  void setDirtyBudget(double ms) { dirtyMs_ = ms; }
  // Traces everything pending (for snapshots, saving and exit); with a limit, stops after about
  // limitMs (between two bands) and returns false when something is still pending.
  bool flush(std::vector<Rect>& changed, double limitMs = std::numeric_limits<double>::infinity());
  bool pending() const {
    return !urgent_.empty() || !coarse_.empty() || nextBand_ < h_ || needPreview_ || blankCopied_ || renderer_->fieldPending();
  }
  // A raised region whose field takes longer than this to add rises a band of rows a turn, each
  // band's field work about this long (RenderOptions::fieldBandMs).
  static constexpr double kFieldBandMs = 3.0;
  // Dirty rectangles that may wait (work()'s mayWait) are traced when this much is left of the
  // budget: at the start of a 30 Hz period, not late in it.
  static constexpr double kWaitUnlessMs = 20.0;
  // Another time (0: every region's field at once; for tests).
  void setFieldBandMs(double ms);
  // The preview's scale (pixels a sample each way), which follows the preview's time: set for
  // tests, whose coarse pictures would otherwise depend on how busy the machine was.
  int previewScale() const { return previewScale_; }
  // Setting it also holds a coarse dirty rectangle's scale at it (else that follows its cost).
  void setPreviewScale(int scale) { previewScale_ = std::clamp(scale, 2, 8), coarseScaleHeld_ = true; }
  // A coarse dirty rectangle is traced at the preview's scale, or coarser (up to this) where the
  // last coarse traces say it would not fit in the dirty budget.
  static constexpr int kMaxCoarseScale = 16;
  // A coarse picture stops after this many times its budget (at least kMinCoarseMs), and the
  // picture at kMaxCoarseScale is shown instead.
  static constexpr double kCoarseOverrun = 1.25;
  static constexpr double kMinCoarseMs = 1.0;
  // The least of the dirty budget that work()'s presentBy leaves.
  static constexpr double kMinDirtyMs = 1.0;
  // Those two least times, for tests (a nanosecond: every trace stops; a long time: none does).
  void setLeastBudgets(double dirtyMs, double coarseMs) { minDirtyMs_ = dirtyMs, minCoarseMs_ = coarseMs; }
  // The scale of the last coarse picture (kMaxCoarseScale after one stopped).
  int lastCoarseScale() const { return lastCoarseScale_; }
  bool refining() const { return nextBand_ < h_; }

  const Image& frame() const { return frame_; }
  // Renderer::pick() through the frame's renderer (Workbench::Picker).
  bool pick(const Model& model, const Camera& camera, double sx, double sy, std::optional<glm::dvec3>& hit) const {
    return renderer_ && renderer_->pick(model, camera, sx, sy, hit);
  }
  const CameraSpec& camera() const { return camera_; }

  // Counters for the diagnostics screen.
  struct Counters {
    std::uint64_t dirtyRects = 0, dirtyPixels = 0, previews = 0, bands = 0, blankReuses = 0;
    std::uint64_t coarseRects = 0;  // dirty rectangles shown coarse first
    std::uint64_t dirtyWaits = 0;   // calls whose dirty rectangles waited for the next (mayWait)
    std::uint64_t fieldBands = 0;   // bands of a big raised region added after its first
    std::uint64_t fieldRebuilds = 0;  // a model's height field built from scratch
    std::uint64_t bandsStopped = 0;   // exact bands of coarse rectangles stopped at the budget's end
    std::uint64_t dirtyStopped = 0;   // dirty rectangles stopped at kDirtyOverrun and shown coarse
    std::uint64_t coarseStopped = 0;  // coarse pictures stopped at kCoarseOverrun (the coarsest shown)
    double lastPreviewMs = 0;
    RenderStats render;
  };
  const Counters& counters() const { return counters_; }

 private:
  using BlankKey = std::tuple<const void*, std::string, std::string>;
  void preview(std::vector<Rect>& changed);
  // The frame's pixels in r from low_, a picture of the same view scaled to lw x lh (bilinear).
  void enlarge(int lw, int lh, const PixelSpans& r);
  // r traced at the preview's scale, or coarser when that would cost more than budgetMs, and
  // enlarged into the frame; one ray a low pixel. Stopped past kCoarseOverrun budgets, and the
  // picture at kMaxCoarseScale enlarged instead.
  void traceCoarse(const PixelSpans& r, std::vector<Rect>& changed, double budgetMs);
  // Traces r into the frame (ms); `onPiece`: a dirty rectangle's pixels, which set the speed the
  // dirty budget is judged by.
  double renderRect(const Rect& r, std::vector<Rect>& changed, bool onPiece);
  // The same over spans (their box is what changed); with a deadline it stops there, *stopped
  // then set (some of the pixels left as they were).
  double renderSpans(const PixelSpans& s, std::vector<Rect>& changed, bool onPiece,
                     std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt,
                     bool* stopped = nullptr);
  // Pixels a millisecond where strokes land: as dirty rectangles measured it, else as the dearest
  // row of a band did (0: nothing traced yet).
  double dirtySpeed() const { return pxPerMs_ > 0 ? pxPerMs_ : maxRowMs_ > 0 ? w_ / maxRowMs_ : 0.0; }
  // The rows of the next refinement band that fit in leftMs.
  int bandRows(double leftMs) const;
  BlankKey blankKey() const;

  // One renderer per model shown recently (the attract piece and the bench): each keeps its model's
  // index and height field, so going from one to the other and back costs no rebuild.
  struct Slot {
    std::unique_ptr<Renderer> renderer;
    const Model* model = nullptr;
    std::string shadingKey;
    std::optional<CameraSpec> camera;  // the camera its renderer was last given
    std::uint64_t lastUse = 0;
  };
  Slot& slotFor(const Model& model);

  ThreadPool& pool_;
  std::array<Slot, 2> slots_;
  std::uint64_t uses_ = 0;
  Slot* slot_ = nullptr;      // the one showing model_
  Renderer* renderer_ = nullptr;
  int w_, h_;
  Image frame_, low_;
  std::vector<std::uint16_t> across_;  // enlarge()'s low rows enlarged across
  bool waiting_ = false;
  const Model* model_ = nullptr;
  std::uint64_t revision_ = ~0ull;
  CameraSpec camera_;
  bool cameraSet_ = false;
  std::string shadingKey_;
  ShadingParams shading_{};
  std::vector<PixelSpans> urgent_;  // the strokes' dirty spans (Renderer::dirtySpans)
  std::vector<PixelSpans> coarse_;  // dirty spans the frame shows coarse: traced exactly next
  bool needPreview_ = false;
  bool blankCopied_ = false;      // frame_ was just replaced by a remembered bare sheet
  bool refineAfterMove_ = false;  // the camera moved: refine once it stops
  int nextBand_ = 0;      // rows [nextBand_, h) still show the preview
  int bandRows_ = 16;
  int previewScale_ = 3;
  bool coarseScaleHeld_ = false;
  double coarseMsPerPx_ = 0;  // what the last coarse traces cost a pixel of theirs (0: none yet)
  int lastCoarseScale_ = 0;
  double minDirtyMs_ = kMinDirtyMs, minCoarseMs_ = kMinCoarseMs;
  // What the next exact band of coarse_ is expected to cost a pixel: what the band before cost,
  // or at first the dearest coarse ray since (0: nothing pending).
  double bandMsPerPx_ = 0;
  static constexpr long kMinBandPixels = 64;
  // A dirty rectangle traced exactly stops after this many dirty budgets and is shown coarse.
  static constexpr double kDirtyOverrun = 1.5;
  double pxPerMs_ = 0;    // measured tracing speed of dirty rectangles
  double fieldBandMs_ = kFieldBandMs;
  std::vector<float> rowMs_;  // per row of the frame: its cost the last time a band traced it (0: not yet)
  double maxRowMs_ = 0;       // the dearest row measured
  double dirtyMs_ = 6.0;
  std::map<BlankKey, Image> blanks_;  // the bare sheet per workpiece, shading and camera
  Counters counters_;
};

// The rectangles merged where that saves work (a union no bigger than the parts plus a quarter).
std::vector<Rect> mergeRects(std::vector<Rect> rects);
// Spans likewise (a union of no more pixels than the parts plus a quarter).
std::vector<PixelSpans> mergeSpans(std::vector<PixelSpans> spans);

}  // namespace emboss

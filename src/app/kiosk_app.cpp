// The kiosk's main-loop step: input -> states -> bench or attract -> tracing -> overlay -> present.
#include "app/kiosk_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "app/kiosk_app_detail.h"
#include "app/memory_display.h"
#include "frep/workpieces.h"

namespace emboss {

namespace fs = std::filesystem;
using namespace kiosk_detail;

namespace {

constexpr double kFrameSeconds = 1.0 / 60.0;  // one display frame: how much of a recording --fast feeds per step
constexpr double kBudgetMs = 35.0;            // tracing per step beyond the dirty rectangles
// With a visitor at the bench: FrameComposer::kPenStepMs and kPenFrame.
constexpr double kAnimationPeriod = 1.0 / 30.0;
constexpr double kMaxAttractGap = 0.25;       // a longer step is a stall: attract mode does not catch up

}  // namespace

KioskApp::KioskApp(KioskConfig config, std::vector<AttractPiece> pieces, Display& display, KioskLog log, Clock clock,
                   KioskStart start)
    : config_(std::move(config)),
      display_(&display),
      log_(std::move(log)),
      clock_(std::move(clock)),
      states_(KioskTimings{config_.idleSeconds, config_.countdownSeconds, config_.staffIdleSeconds, config_.staffChordSeconds},
              config_.staffChord, clock_()) {
  const int w = display.width(), h = display.height();
  pool_ = std::make_unique<ThreadPool>(config_.threads);
  composer_ = std::make_unique<FrameComposer>(*pool_, w, h);
  BenchSetup setup;
  setup.workpiece = std::make_shared<Plate>(config_.sheetWidth / 2, config_.sheetHeight / 2, config_.sheetThickness / 2);
  setup.metal = config_.metal;
  setup.width = w, setup.height = h;
  setup.tabletAspect = config_.tabletAspect;
  bench_ = std::make_unique<Workbench>(setup);
  connectPicker();
  attract_ = std::make_unique<AttractPlayer>(std::move(pieces), w, h, config_.attractSpeed);
  sessions_ = std::make_unique<SessionStore>(config_.sessionsDir, log_);
  journal_ = std::make_unique<SessionJournal>(config_.sessionsDir, log_);
  // The bare sheet of the bench, traced once now: a visitor's first touch then shows at once.
  {
    std::vector<Rect> ignored;
    composer_->show(bench_->model(), bench_->camera(), bench_->shading(), ViewChanges{true, false, {}}, false);
    composer_->flush(ignored);
    benchShown_ = true;
  }
  const double now = clock_();
  started_ = lastStep_ = now;
  startAttract(now, attract_->empty() ? 0 : start.attractPiece % attract_->size(), start.attractDone);
  pruneSessions(now);
  restoreSession(now);
  if (start.staff) {
    states_.enterStaff(now);
    handleEvents(now);
  }
}

KioskApp::~KioskApp() = default;

void KioskApp::setPen(PenSource* pen, PenMapping mapping, bool fast) {
  pen_ = pen;
  mapping_ = mapping;
  fast_ = fast;
  penLost_ = false;
  queue_.clear();
  lastTip_ = lastBarrel1_ = lastBarrel2_ = false;
}

void KioskApp::addButtons(ButtonSource* buttons) {
  if (buttons) buttons_.push_back(buttons);
}

void KioskApp::setDisplay(Display& display) {
  display_ = &display;
  displayLost_ = false;
  firstPresent_ = true;
  if (display.width() != composer_->width() || display.height() != composer_->height()) {
    // Another screen size: a new frame, bench and attract loop for it; the visitor's work is kept.
    saveSession("the screen changed");
    const int w = display.width(), h = display.height();
    composer_ = std::make_unique<FrameComposer>(*pool_, w, h);
    BenchSetup setup;
    setup.workpiece = bench_->model().workpiecePtr();
    setup.metal = config_.metal;
    setup.width = w, setup.height = h;
    setup.tabletAspect = config_.tabletAspect;
    bench_ = std::make_unique<Workbench>(setup);
    connectPicker();
    const double now = clock_();
    states_.resetToAttract(now);
    states_.takeEvents();
    benchShown_ = false;
    log_("display: now " + display.name() + " " + std::to_string(w) + "x" + std::to_string(h));
    startAttract(now, attract_->pieceIndex(), 0.0);
  }
}

void KioskApp::setDeviceNote(const std::string& key, const std::string& value) {
  if (value.empty())
    deviceNotes_.erase(key);
  else
    deviceNotes_[key] = value;
}

void KioskApp::setCamera(CameraSource* camera) {
  if (camera != camera_ && capture_.phase == CapturePhase::Running && capture_.job.valid()) {
    capture_.job.wait();  // the still under way uses the old camera
    pollCapture(clock_());
  }
  camera_ = camera;
  cameraLost_ = false;
  lastCameraCheck_ = clock_();
}

const FpsMeter& KioskApp::fps(KioskMode m) const {
  static const FpsMeter none;
  const auto it = fps_.find(m);
  return it == fps_.end() ? none : it->second;
}

bool KioskApp::busy() const {
  return composer_->pending() || !queue_.empty() || bench_->moving() || attract_->moving() ||
         (fast_ && pen_ && !pen_->finished());
}

double KioskApp::idleSeconds() const {
  // Attract mode: a camera in motion keeps busy() true, but once its preview is traced (or while
  // the work waits for the next period) the next thing to do is the tick's present.
  if (states_.mode() != KioskMode::Attract || !queue_.empty() || (composer_->pending() && !composer_->waiting())) return 0.0;
  return std::max(0.0, nextAnimation_ - clock_());
}

double KioskApp::wakeWithin() const {
  if (!animated()) return std::numeric_limits<double>::infinity();
  return std::max(0.0, nextAnimation_ - clock_());
}

bool KioskApp::animated() const { return states_.mode() != KioskMode::Visitor || capture_.phase == CapturePhase::Running; }

bool KioskApp::feedDone() const { return fast_ && (!pen_ || pen_->finished()) && queue_.empty(); }

void KioskApp::startAttract(double now, size_t index, double done) {
  if (attract_->empty()) return;
  attract_->start(now, index, done);
  if (log_) log_("attract: playing '" + attract_->title() + "'");
}

void KioskApp::saveSession(const std::string& why) {
  bench_->finishStroke();  // a stroke in progress is part of the session
  lastCommitted_ = bench_->committed();  // (not a pen event's latency: the stroke ends here)
  journalSync();
  if (journalOpen_) {
    journal_->end();
    journalOpen_ = false;
    journaledIds_.clear();
    journalState_ = {};
  }
  if (bench_->model().activeCount() == 0) {
    setLogSession(0);
    return;
  }
  // The picture: the bench as the visitor last saw it, traced to the end.
  ViewChanges ch = bench_->takeChanges();
  if (!benchShown_) ch.full = true;
  benchShown_ = true;
  composer_->show(bench_->model(), bench_->camera(), bench_->shading(), ch, false);
  std::vector<Rect> changed;
  composer_->flush(changed);
  const std::string stamp = fileStamp();
  const Scene scene = bench_->scene("Visitor session " + stamp);
  lastSessionJson_ = sceneToJson(scene, &bench_->model());
  if (log_) log_("session: saving (" + why + ")");
  sessions_->save(scene, bench_->model(), &composer_->frame(), stamp);
  setLogSession(0);  // the lines about the session, its saving included, are logged
  changed_.insert(changed_.end(), changed.begin(), changed.end());
}

Overlay KioskApp::overlay(double now) const {
  OverlayState s;
  s.mode = states_.mode();
  s.now = now;
  s.width = composer_->width();
  s.height = composer_->height();
  s.bench = bench_.get();
  s.title = attract_->empty() ? std::string() : attract_->title();
  s.progress = attract_->empty() ? 0.0 : attract_->progress();
  s.countdownLeft = states_.countdownLeft(now);
  s.countdownTotal = config_.countdownSeconds;
  s.staff = staff_;
  s.capturing = capture_.phase == CapturePhase::Running;
  s.captureOffered = capture_.phase == CapturePhase::Offer;
  if (now < capture_.messageUntil) {
    s.captureMessage = capture_.message;
    s.captureMessageIsError = capture_.messageIsError;
  }
  if (capture_.offer && (s.mode == KioskMode::Visitor || s.mode == KioskMode::StillThere)) {
    // The traced lines on the plate's front face, through the bench's camera as it is now.
    const Camera cam(bench_->camera(), composer_->width(), composer_->height());
    const double z = bench_->model().workpiecePtr()->bounds().z1;
    for (const auto& line : capture_.offer->polylines) {
      std::vector<std::pair<double, double>> screen;
      for (const Vec2& p : line)
        if (const auto q = cam.project({p.x, p.y, z})) screen.emplace_back(q->x, q->y);
      if (!screen.empty()) s.guide.push_back(std::move(screen));
    }
  }
  return buildOverlay(s);
}

void KioskApp::present(double now, std::vector<Rect>& changed, bool modelChanged) {
  if (!display_) return;
  const Overlay o = overlay(now);
  std::vector<Rect> dirty = mergeRects(changed);
  if (firstPresent_) dirty = {Rect{0, 0, composer_->width(), composer_->height()}};
  if (!display_->present(composer_->frame(), dirty, o)) {
    if (!displayLost_ && log_) log_("display: '" + display_->name() + "' lost its output");
    displayLost_ = true;
    return;
  }
  firstPresent_ = false;
  const double t = clock_();
  if (t >= nextAnimation_)  // the next tick of the grid; a new grid after a stall of more than a period
    nextAnimation_ = t - nextAnimation_ > kAnimationPeriod ? t + kAnimationPeriod : nextAnimation_ + kAnimationPeriod;
  if (presents_++ == 0 && log_) log_(fmt("first frame on the screen %.1f s after start", t - started_));
  fps_[states_.mode()].frame(t);
  if (!changed.empty()) ++pictureUpdates_;
  if (modelChanged) latency_.presented(t);
}

bool KioskApp::step() {
  // Wall-clock phases of this step, for the log line of a stalled step (see the end).
  using Steady = std::chrono::steady_clock;
  const Steady::time_point tStart = Steady::now();
  const double now = clock_();
  fps_[states_.mode()].time(std::max(0.0, now - lastStep_));
  if (states_.mode() != fpsMode_) fps_[fpsMode_].pause(), fpsMode_ = states_.mode();
  // After a stall (a slow start, a long trace on a slow board) attract mode goes on where it was:
  // catching up would add the stall's operations at once and make the next step slow in turn.
  if (const double gap = now - lastStep_; gap > kMaxAttractGap && states_.mode() == KioskMode::Attract && !attract_->empty())
    attract_->hold(gap - kFrameSeconds);
  lastStep_ = now;
  const size_t queuedBefore = queue_.size();
  pollInput(now);
  bool input = queue_.size() != queuedBefore;
  if (fast_) {
    // As fast as possible, yet frame by frame where it matters: hovering runs straight through,
    // and from the first touch on, one display frame's worth of the recording per step.
    double firstTip = -1;
    while (!queue_.empty()) {
      const PenSample s = queue_.front().s;
      if (firstTip >= 0 && s.time_s - firstTip >= kFrameSeconds) break;
      queue_.pop_front();
      handlePen(s, clock_(), now);
      input = true;
      if (s.tip && firstTip < 0) firstTip = s.time_s;
    }
  } else {
    while (!queue_.empty()) {
      const QueuedSample q = queue_.front();
      queue_.pop_front();
      handlePen(q.s, q.arrival, now);
    }
  }
  states_.tick(now);
  handleEvents(now);
  journalSync();
  journalReport();
  if (now - lastPrune_ > 3600.0) pruneSessions(now);
  pollCapture(now);
  pollExport();
  checkCamera(now);
  if (!capture_.message.empty() && now >= capture_.messageUntil) {
    capture_.message.clear();
    overlayChanged_ = true;
  }

  const Steady::time_point tInput = Steady::now();
  const KioskMode m = states_.mode();
  const bool showBench = m == KioskMode::Visitor || m == KioskMode::StillThere ||
                         (m == KioskMode::Staff && states_.modeBeforeStaff() != KioskMode::Attract);
  bool modelChanged = false;
  if (showBench) {
    bench_->update(now);
    ViewChanges ch = bench_->takeChanges();
    if (!benchShown_) ch.full = true;
    benchShown_ = true;
    modelChanged = ch.any();
    composer_->show(bench_->model(), bench_->camera(), bench_->shading(), ch, bench_->moving());
  } else if (!attract_->empty()) {
    if (m == KioskMode::Attract) {  // paused under the staff screen
      const size_t before = attract_->pieceIndex();
      attract_->update(now);
      if (attract_->pieceIndex() != before && log_) log_("attract: playing '" + attract_->title() + "'");
    }
    ViewChanges ch = attract_->takeChanges();
    if (benchShown_) ch.full = true;
    benchShown_ = false;
    composer_->show(attract_->model(), attract_->camera(), attract_->shading(), ch, attract_->moving());
  }
  const Steady::time_point tModel = Steady::now();
  const bool animated = this->animated();
  // Refinement bands fill the step's budget; on an animated screen they stop short of the next
  // tick of the grid below (the dirty rectangles are traced whatever the budget).
  const bool drawing = m == KioskMode::Visitor;
  const double budgetMs = animated  ? std::clamp((nextAnimation_ - clock_()) * 1000.0 - 2.0, 2.0, kBudgetMs)
                          : drawing ? FrameComposer::kPenStepMs
                                    : kBudgetMs;
  // In attract mode nobody waits for a stroke: what would not be traced before the next tick
  // waits for the turn after it.
  composer_->work(budgetMs, changed_, drawing, m == KioskMode::Attract,
                  drawing ? std::optional(tStart + FrameComposer::kPenFrame) : std::nullopt);
  const Steady::time_point tTrace = Steady::now();
  // Animated screens (attract mode, the countdown, the capture) are presented on a fixed 30 Hz
  // grid: timing each frame from the last present would add the loop's wake-up delay to every
  // period (28 to 29 fps). In attract mode nobody waits for a stroke: what was traced between two
  // ticks waits for the next one, so every frame on the grid carries the pieces' progress.
  const bool due = animated && clock_() >= nextAnimation_;
  const bool paced = m == KioskMode::Attract;
  if ((paced ? due : !changed_.empty() || due) || input || firstPresent_ || overlayChanged_) {
    overlayChanged_ = false;
    present(clock_(), changed_, modelChanged && !changed_.empty());
    changed_.clear();
  }
  if (m == KioskMode::Staff) updateStaffView(now);
  if (sessions_->pendingCount() && now - lastRetry_ > 30.0) {
    lastRetry_ = now;
    sessions_->retryPending();
  }
  // A step that holds the loop up for a second or more is logged (at most every 10 s) with where
  // its time went: on a slow board that is the first thing to look at.
  const auto secs = [](Steady::time_point a, Steady::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  const Steady::time_point tEnd = Steady::now();
  StepTimes& st = stepTimes_[static_cast<size_t>(m)];
  ++st.steps;
  st.input += secs(tStart, tInput), st.model += secs(tInput, tModel), st.tracing += secs(tModel, tTrace);
  st.presenting += secs(tTrace, tEnd);
  if (secs(tStart, tEnd) >= 1.0 && log_ && secs(lastSlowLog_, tEnd) >= 10.0) {
    lastSlowLog_ = tEnd;
    char buf[200];
    std::snprintf(buf, sizeof buf, "slow step: %.2f s (input %.2f, model %.2f, tracing %.2f, presenting %.2f; %zu operations on the bench)",
                  secs(tStart, tEnd), secs(tStart, tInput), secs(tInput, tModel), secs(tModel, tTrace), secs(tTrace, tEnd),
                  bench_->model().activeCount());
    log_(buf);
  }
  return !quit_;
}

void KioskApp::finish(bool completeFrame, double limitMs) {
  if (export_) {  // an export under way stops between two files; what it copied is complete
    export_->stop();
    pollExport();
  }
  const double now = clock_();
  // Take what is still queued (a recording fed with --fast), then end any stroke.
  while (!queue_.empty()) {
    const QueuedSample q = queue_.front();
    queue_.pop_front();
    handlePen(q.s, fast_ ? clock_() : q.arrival, now);
  }
  const KioskMode m = states_.mode();
  const bool visitor = m == KioskMode::Visitor || m == KioskMode::StillThere ||
                       (m == KioskMode::Staff && states_.modeBeforeStaff() != KioskMode::Attract);
  if (visitor) {
    bench_->update(now + 60.0);  // a turn under way ends where it was going
    saveSession("the kiosk is stopping");
  }
  if (!completeFrame) return;
  std::vector<Rect> changed;
  if (visitor) {
    ViewChanges ch = bench_->takeChanges();
    if (!benchShown_) ch.full = true;
    benchShown_ = true;
    composer_->show(bench_->model(), bench_->camera(), bench_->shading(), ch, false);
  } else if (!attract_->empty()) {
    ViewChanges ch = attract_->takeChanges();
    if (benchShown_) ch.full = true;
    benchShown_ = false;
    composer_->show(attract_->model(), attract_->camera(), attract_->shading(), ch, false);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const bool traced = composer_->flush(changed, limitMs);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!traced && log_) {
    log_(fmt("stopping: the last frame was not traced to the end within %.1f s; it is presented as far as it got", took));
  } else if (took >= 1.0 && log_) {
    log_(fmt("stopping: the last frame took %.1f s to trace", took));
  }
  changed.insert(changed.end(), changed_.begin(), changed_.end());
  changed_.clear();
  if (m == KioskMode::Staff) updateStaffView(now);
  present(clock_(), changed, true);
}

Status KioskApp::writeSnapshot(const fs::path& path) {
  Image shot = display_ ? display_->screenshot() : Image();
  if (shot.width != composer_->width() || shot.height != composer_->height() || shot.rgba.empty()) {
    shot = composer_->frame();
    drawOverlayInto(shot, overlay(clock_()));
  }
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  return writePng(shot, path);
}

Status KioskApp::writeSession(const fs::path& path) {
  std::string json;
  if (bench_->model().activeCount() > 0) json = sceneToJson(bench_->scene("Visitor session"), &bench_->model());
  else if (lastSessionJson_) json = *lastSessionJson_;
  else json = sceneToJson(bench_->scene("Visitor session (nothing embossed)"), &bench_->model());
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  return writeFileAtomically(path, json);
}

std::string KioskApp::statsReport() const {
  std::string out;
  char buf[256];
  for (KioskMode m : {KioskMode::Attract, KioskMode::Visitor, KioskMode::StillThere, KioskMode::Staff}) {
    const FpsMeter& f = fps(m);
    if (f.seconds() <= 0 && f.frames() == 0) continue;
    // Attract mode is presented on a fixed grid: its pace once its first frame was shown is the
    // rate a visitor sees (the other modes present when something changed).
    if (m == KioskMode::Attract)
      std::snprintf(buf, sizeof buf, "stats: %s: %zu frames in %.1f s = %.1f fps; %.1f fps from its first frame on (%zu intervals in %.2f s)\n",
                    kioskModeName(m), f.frames(), f.seconds(), f.meanFps(), f.paceFps(), f.intervals(), f.intervalSeconds());
    else
      std::snprintf(buf, sizeof buf, "stats: %s: %zu frames in %.1f s = %.1f fps\n", kioskModeName(m), f.frames(), f.seconds(), f.meanFps());
    out += buf;
    if (const StepTimes& st = stepTimes_[static_cast<size_t>(m)]; st.steps > 0) {
      const double k = 1000.0 / static_cast<double>(st.steps);
      std::snprintf(buf, sizeof buf,
                    "stats: %s: %zu turns of the loop, each %.2f ms on average: input %.2f, model %.2f, tracing %.2f, "
                    "presenting %.2f\n",
                    kioskModeName(m), st.steps, (st.input + st.model + st.tracing + st.presenting) * k, st.input * k, st.model * k,
                    st.tracing * k, st.presenting * k);
      out += buf;
    }
  }
  if (latency_.count()) {
    std::snprintf(buf, sizeof buf,
                  "stats: stroke-to-screen latency: %zu updates, mean %.1f ms, median %.1f ms, 95%% %.1f ms, 99%% %.1f ms, max %.1f ms\n",
                  latency_.count(), latency_.meanMs(), latency_.percentileMs(50), latency_.percentileMs(95), latency_.percentileMs(99),
                  latency_.maxMs());
  } else {
    std::snprintf(buf, sizeof buf, "stats: stroke-to-screen latency: no strokes\n");
  }
  out += buf;
  const auto& c = composer_->counters();
  std::snprintf(buf, sizeof buf,
                "stats: tracing: %llu dirty rectangles (%llu pixels), %llu previews (last %.1f ms), %llu refinement bands, "
                "%llu rays; %zu presents (%zu with new pixels)\n",
                static_cast<unsigned long long>(c.dirtyRects), static_cast<unsigned long long>(c.dirtyPixels),
                static_cast<unsigned long long>(c.previews), c.lastPreviewMs, static_cast<unsigned long long>(c.bands),
                static_cast<unsigned long long>(c.render.rays), presents_, pictureUpdates_);
  out += buf;
  return out;
}

}  // namespace emboss

// The kiosk: states, bench, attract loop, sessions and the frame, driven one main-loop step at a
// time through the device interfaces (src/devices) only.
#pragma once

#include <algorithm>
#include <chrono>
#include <array>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/attract_player.h"
#include "app/frame_composer.h"
#include "app/frame_meter.h"
#include "app/kiosk_config.h"
#include "app/kiosk_log.h"
#include "app/kiosk_overlay.h"
#include "app/kiosk_states.h"
#include "app/session_export.h"
#include "app/session_store.h"
#include "app/workbench.h"
#include "capture/capture_drawing.h"
#include "devices/buttons.h"
#include "devices/camera.h"
#include "devices/display.h"
#include "devices/pen.h"
#include "staff/staff_protocol.h"
#include "store/session_journal.h"

namespace emboss {

// How a pen's 0..1 coordinates reach the screen.
enum class PenMapping {
  Tablet,  // absolute onto the visible sheet, the tablet's aspect kept (a pressure tablet)
  Screen,  // 1:1 onto the screen (the mouse over the window)
};

struct KioskStart {
  bool staff = false;       // start in staff mode (--staff)
  size_t attractPiece = 0;     // the first attract piece (index, wraps)
  double attractDone = 0.35;  // and how far along it starts
};

// Not thread-safe: one main loop calls step(). Times come from `clock` (seconds, monotonic);
// tests pass a fake one.
class KioskApp {
 public:
  using Clock = std::function<double()>;

  KioskApp(KioskConfig config, std::vector<AttractPiece> pieces, Display& display, KioskLog log, Clock clock,
           KioskStart start = {});
  ~KioskApp();

  // The pen (null: none). With `fast`, a recording is fed as fast as the kiosk can take it: one
  // display frame's worth of its samples per step, each stamped when taken.
  void setPen(PenSource* pen, PenMapping mapping, bool fast = false);
  // Whether the pen finds the metal through the frame's renderer (the default: one ray as the
  // picture was traced), or on the model alone (pickSurface(): what a replay of the same samples
  // through a Workbench gives, bit for bit, whatever the machine's speed).
  void setPickThroughRenderer(bool on) {
    pickThroughRenderer_ = on;
    connectPicker();
  }
  void addButtons(ButtonSource* buttons);
  // Whether a button source is still in use (one that stopped answering has been dropped).
  bool hasButtons(const ButtonSource* buttons) const { return std::find(buttons_.begin(), buttons_.end(), buttons) != buttons_.end(); }
  // A display lost and re-created by main().
  void setDisplay(Display& display);
  // A line for the staff screen's device list ("Tablet", "no tablet found: ..."), set by main();
  // an empty value removes it.
  void setDeviceNote(const std::string& key, const std::string& value);
  // The staff screen's diagnostics lines as last shown (staff mode only).
  const std::vector<std::string>& staffLines() const { return staff_.lines; }
  // Where the staff export's postcards get their caption painter (the platform's FreeType).
  void setTextPainterFactory(std::function<std::unique_ptr<TextPainter>()> factory) { textFactory_ = std::move(factory); }
  // The camera for capture drawing (null: none). A capture under way finishes first.
  void setCamera(CameraSource* camera);

  // One main-loop iteration: input, states, views, tracing within a frame budget, presenting.
  // Returns false once quitting was asked for (the keyboard's Escape in development).
  bool step();
  // True while there is work that should not wait (pending tracing, queued pen samples, a turn).
  bool busy() const;
  // While busy(): how long the loop may sleep now (attract mode with nothing to trace before
  // its next 30 Hz tick, or its work waiting for the start of the next period), else 0.
  double idleSeconds() const;
  // While not busy(): within how many seconds step() has timed work of its own: the next tick of
  // an animated screen's 30 Hz grid (attract mode, the countdown, the staff screen, a capture);
  // infinity on the visitor's screen, which waits for input.
  double wakeWithin() const;
  // The pen stopped answering (unplugged); main() may look for another and call setPen().
  bool penLost() const { return penLost_; }
  // A recording fed with fast has been played to its end and every sample taken.
  bool feedDone() const;
  bool displayLost() const { return displayLost_; }
  // The camera stopped answering (CameraSource::present() false, checked every 2 s while no
  // capture runs); main() may drop it, look for another and call setCamera().
  bool cameraLost() const { return cameraLost_; }

  // Capture drawing (docs/kiosk.md): the capture action (a button, the key 'c', the staff menu)
  // takes a still and traces it off the render thread; the traced lines are then shown on the
  // plate as a guide and offered: the capture action again embosses them (one stroke, one undo),
  // undo discards them.
  enum class CapturePhase { Idle, Running, Offer };
  CapturePhase capturePhase() const { return capture_.phase; }
  // The traced drawing on offer (CapturePhase::Offer), else null.
  const CaptureResult* captureOffer() const { return capture_.offer ? &*capture_.offer : nullptr; }
  // The last capture's outcome as shown to the visitor (empty once it has faded).
  const std::string& captureMessage() const { return capture_.message; }

  // At exit: ends a stroke in progress, saves a visitor's session (nothing is lost on shutdown; its
  // picture is traced to the end), and with `completeFrame` finishes tracing the screen and
  // presents the last frame (for a snapshot; without, SIGTERM is not kept waiting for a frame).
  // The tracing stops after about limitMs (systemd's stop timeout is 15 s; an emulated CPU can
  // take a minute for an exact 1280x800 frame): the frame is then presented as far as it got, and
  // the log says so.
  void finish(bool completeFrame = true, double limitMs = std::numeric_limits<double>::infinity());
  // The last frame as on screen (overlay included), as a PNG written atomically.
  Status writeSnapshot(const std::filesystem::path& path);
  // The visitor's session as a scene file: the one in progress, else the last one saved this run,
  // else a bare sheet.
  Status writeSession(const std::filesystem::path& path);
  // Frames per second per mode, stroke-to-screen latency, tracing counters.
  std::string statsReport() const;

  KioskMode mode() const { return states_.mode(); }
  const Workbench& bench() const { return *bench_; }
  const AttractPlayer& attract() const { return *attract_; }
  const LatencyMeter& latency() const { return latency_; }
  const FpsMeter& fps(KioskMode m) const;
  const SessionStore& sessions() const { return *sessions_; }
  // The journal of the session in progress (docs/sessions.md); null when it could not be opened.
  SessionJournal* journal() const { return journal_ && journal_->ok() ? journal_.get() : nullptr; }
  // Waits (at most `seconds`) until every operation made so far is durable. True when it is.
  bool journalFlush(double seconds);
  const FrameComposer& composer() const { return *composer_; }
  size_t presents() const { return presents_; }
  // Staff mode's last message (export result, reset).
  const std::string& staffMessage() const { return staff_.message; }
  // A staff request (src/staff/staff_protocol.h) from embossctl: the answer, one JSON line, or
  // nothing yet (an export runs on a thread of its own; ask staffPoll() on later steps for its
  // progress lines and its answer).
  std::optional<std::string> staffCommand(const std::string& line);
  StaffPending staffPoll();
  // An export under way (from the staff screen or embossctl).
  bool exporting() const { return export_ != nullptr; }
  // What the kiosk is doing, for the service manager's STATUS= (attract, visitor, staff, exporting...).
  std::string statusLine() const;
  // Runs a staff menu entry by index (0 resume, 1 export, 2 reset, 3 capture a drawing), as a tap
  // or press would.
  void staffActivate(size_t index);

 private:
  struct QueuedSample {
    PenSample s;
    double arrival;
  };
  void pollInput(double now);
  void handleButton(const ButtonEvent& e, double now);
  void handlePen(const PenSample& s, double arrival, double now);
  // The bench's pen finds the metal through the frame's renderer (Workbench::setPicker).
  void connectPicker();
  bool pickThroughRenderer_ = true;
  void handleEvents(double now);
  // The screen is presented on the 30 Hz grid (not only when the picture changes).
  bool animated() const;
  void saveSession(const std::string& why);
  // The journal learns what changed on the bench since the last call (operations, undo, metal).
  void journalSync();
  // Logs the strokes the journal made durable since the last call.
  void journalReport();
  // At start: an unfinished session in the journal is brought back, or closed when too old.
  void restoreSession(double now);
  // Drops sessions beyond the retention age and size (at start, then every hour).
  void pruneSessions(double now);
  void startAttract(double now, size_t index, double done);
  void updateStaffView(double now);
  // Starts the one staff export (the menu's and embossctl's), the session in progress included.
  // A refusal (no stick, one already under way) comes back at once.
  Status startExport(ExportRequest request);
  // Follows the export under way: its progress and its outcome on the staff screen, in the log and
  // for embossctl. Called every step.
  void pollExport();
  void present(double now, std::vector<Rect>& changed, bool modelChanged);
  Overlay overlay(double now) const;
  void startCapture(double now);
  void pollCapture(double now);
  void acceptCapture(double now);
  void discardCapture(const std::string& why);
  void captureNote(double now, const std::string& message, bool error);
  void checkCamera(double now);
  void dropCamera();  // the camera is gone: no longer used, reported lost

  KioskConfig config_;
  Display* display_;
  KioskLog log_;
  Clock clock_;
  std::unique_ptr<ThreadPool> pool_;
  std::unique_ptr<FrameComposer> composer_;
  std::unique_ptr<Workbench> bench_;
  std::unique_ptr<AttractPlayer> attract_;
  std::unique_ptr<SessionStore> sessions_;
  KioskStates states_;

  PenSource* pen_ = nullptr;
  PenMapping mapping_ = PenMapping::Tablet;
  bool fast_ = false;
  bool penLost_ = false;
  bool displayLost_ = false;
  std::deque<QueuedSample> queue_;
  bool lastTip_ = false, lastBarrel1_ = false, lastBarrel2_ = false;
  std::vector<ButtonSource*> buttons_;
  std::map<std::string, std::string> deviceNotes_;

  CameraSource* camera_ = nullptr;
  bool cameraLost_ = false;
  double lastCameraCheck_ = 0;
  struct Capture {
    CapturePhase phase = CapturePhase::Idle;
    std::future<Result<CaptureResult>> job;  // while Running
    bool dropResult = false;                 // the visitor left while it ran
    std::optional<CaptureResult> offer;      // while Offer
    std::string message;
    bool messageIsError = false;
    double messageUntil = 0;
    double started = 0;
  } capture_;
  bool overlayChanged_ = false;  // present even when the picture did not change
  std::chrono::steady_clock::time_point lastSlowLog_{};

  bool quit_ = false;
  bool benchShown_ = false;  // the composer shows the bench (else the attract piece)
  double started_ = 0, lastStep_ = 0, lastRetry_ = 0, sessionStarted_ = 0;
  double nextAnimation_ = 0;  // when an animated screen is presented next (a 30 Hz grid)
  // Where the loop's time goes, per mode (--stats): seconds summed over the turns.
  struct StepTimes {
    size_t steps = 0;
    double input = 0, model = 0, tracing = 0, presenting = 0;
  };
  std::array<StepTimes, 4> stepTimes_{};  // by KioskMode
  std::uint64_t lastCommitted_ = 0;
  size_t presents_ = 0;
  bool firstPresent_ = true;
  std::optional<std::string> lastSessionJson_;
  std::unique_ptr<SessionExport> export_;     // the export under way, null when none
  std::function<std::unique_ptr<TextPainter>()> textFactory_;  // the postcards' caption painter
  bool exportForSocket_ = false;              // embossctl asked for it and waits for the answer
  bool exportProgressLines_ = false;          // ... and for progress lines
  std::vector<std::string> exportLines_;      // progress lines not yet sent to embossctl
  std::optional<std::string> exportAnswer_;   // the answer not yet sent to embossctl
  SessionStore::ExportProgress exportShown_;  // the progress last shown
  std::unique_ptr<SessionJournal> journal_;
  bool journalOpen_ = false;                 // the bench's session has been begun in the journal
  std::int64_t journalId_ = 0;
  std::vector<std::uint64_t> journaledIds_;  // the model's operation ids as the journal has them
  std::uint64_t journalRev_ = ~std::uint64_t(0);
  JournalState journalState_;
  std::int64_t durableSession_ = 0;
  std::uint64_t durableLogged_ = 0;
  double lastPrune_ = 0;
  LatencyMeter latency_;
  std::map<KioskMode, FpsMeter> fps_;
  KioskMode fpsMode_ = KioskMode::Attract;  // the mode the frames were last counted for
  size_t pictureUpdates_ = 0;
  StaffView staff_;
  std::vector<Rect> changed_;
};

}  // namespace emboss

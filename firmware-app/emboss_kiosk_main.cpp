// emboss-kiosk: the exhibit's program -- wires the configuration, the platform back ends and the
// kiosk (src/app) together and runs its main loop.
#include <CLI/CLI.hpp>

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "gl/text_image.h"
#include "app/attract_library.h"
#include "app/kiosk_app.h"
#include "app/kiosk_config.h"
#include "app/memory_display.h"
#include "app/pointer_input.h"
#include "gpio/buttons_gpio.h"
#include "camera/camera_file.h"
#include "camera/camera_v4l2.h"
#include "devices/button_config.h"
#include "display/display_factory.h"
#include "display/display_kms.h"
#include "display/display_x11.h"
#include "system/journal_log.h"
#include "pen/pen_probe.h"
#include "pen/pen_replay.h"
#include "pieces/pieces.h"
#include "render/table_cache.h"
#include "system/staff_socket.h"
#include "system/system_notify.h"
#include "util/progress_beat.h"
#include "util/heap_release.h"
#include "version.h"

namespace fs = std::filesystem;
using namespace emboss;

namespace {

volatile sig_atomic_t gStop = 0;
void onSignal(int) { gStop = 1; }

// Where the package installs the configuration (the unit passes it with --config).
constexpr const char* kDefaultConfig = "/etc/emboss/kiosk.conf";
// How long SIGTERM waits for the last frame to be traced for --snapshot (the unit gives 15 s).
constexpr double kLastFrameLimitMs = 10000.0;
// The longest the main loop sleeps with nothing to do and no descriptor readable (seconds).
constexpr double kIdleWaitS = 0.05;

// Log lines may start with a syslog priority, "<7>" (debug) .. "<3>" (error); none is info (6).
// Lines above --log-level are not written. When stderr is the journal (JOURNAL_STREAM names it)
// each line is a journal entry of its own: PRIORITY, MESSAGE, and EMBOSS_SESSION (the journal id of
// the visitor's session the kiosk is working on) so that `journalctl EMBOSS_SESSION=12` shows one
// session's story; should the journal not take it, the line goes to stderr with its "<N>" prefix,
// which journald reads as the priority. On a terminal the line is plain text.
int gLogLevel = 6;
bool gOnJournal = false;

void logLine(const std::string& line) {
  const LogLine l = splitLogPriority(line);
  if (l.priority > gLogLevel) return;
  if (gOnJournal) {
    if (sendToJournal(journalFields(l.text, l.priority, logSession(), "emboss-kiosk"))) return;
    std::fprintf(stderr, "<%d>%.*s\n", l.priority, int(l.text.size()), l.text.data());
  } else {
    std::fprintf(stderr, "emboss-kiosk: %.*s\n", int(l.text.size()), l.text.data());
  }
}

int logLevelByName(const std::string& name) {
  if (name == "error") return 3;
  if (name == "warn" || name == "warning") return 4;
  if (name == "debug") return 7;
  return 6;
}

fs::path defaultSessionsDir() {
  if (const char* s = std::getenv("STATE_DIRECTORY"); s && *s) {
    std::string first(s);
    if (const auto colon = first.find(':'); colon != std::string::npos) first.resize(colon);
    return fs::path(first) / "sessions";
  }
  if (const char* s = std::getenv("XDG_STATE_HOME"); s && *s) return fs::path(s) / "emboss-kiosk" / "sessions";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".local" / "state" / "emboss-kiosk" / "sessions";
  return fs::temp_directory_path() / "emboss-kiosk-sessions";
}

int writePieces(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (const auto& p : generateAttractPieces()) {
    Status s = saveScene(p.scene, nullptr, dir / p.file);
    if (!s) {
      logLine(s.error());
      return 1;
    }
    std::printf("wrote %s (%zu operations)\n", (dir / p.file).c_str(), p.scene.operations.size());
  }
  return 0;
}

PointerEvent toPointer(const X11Event& e) {
  PointerEvent p;
  p.x = e.x, p.y = e.y;
  switch (e.type) {
    case X11Event::Type::kMove: p.type = PointerEvent::Type::Move; break;
    case X11Event::Type::kPenDown: p.type = PointerEvent::Type::Down; break;
    case X11Event::Type::kPenUp: p.type = PointerEvent::Type::Up; break;
    case X11Event::Type::kKey: p.type = PointerEvent::Type::Key, p.key = e.key; break;
    case X11Event::Type::kClose: p.type = PointerEvent::Type::Leave; break;
  }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  // First of all: a SIGTERM that comes while the kiosk is still starting ends it with status 0 too.
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  CLI::App cli{"emboss-kiosk: the virtual embossing exhibit (attract mode, the visitor's bench, staff mode)"};
  std::string display, tablet, buttons, camera, configPath, size, snapshot, sessionOut, sessionsDir, piecesDir, exportDir, writePiecesDir;
  bool attractOnly = false, staff = false, fast = false, stats = false;
  double runFor = 0;
  int threads = -1;
  cli.add_option("--display", display, "auto | kms | x11 | headless | osmesa (default: the config's, else auto)")
      ->check(CLI::IsMember({"auto", "kms", "x11", "headless", "osmesa"}));
  cli.add_option("--tablet", tablet, "auto (find a tablet) | evemu:PATH (replay a recording) | none");
  cli.add_option("--buttons", buttons, "auto (GPIO, built-in wiring) | PATH of a buttons.json | none");
  cli.add_option("--camera", camera, "auto (the first V4L2 camera) | /dev/videoN | file:PNG | none: for capture drawing");
  cli.add_flag("--attract", attractOnly, "Attract mode only: play the pieces, ignore pen and buttons");
  cli.add_flag("--staff", staff, "Start in staff mode");
  cli.add_option("--run-for", runFor, "Stop after SECONDS")->check(CLI::NonNegativeNumber);
  cli.add_option("--snapshot", snapshot, "Write the last frame (overlay included) to OUT.png at exit");
  cli.add_option("--session-out", sessionOut, "Write the visitor's session as a scene file at exit");
  cli.add_flag("--fast", fast, "Feed the --tablet=evemu: recording as fast as possible (the same operations on every run), then exit 0");
  cli.add_option("--config", configPath, "A key = value configuration file (installed as " + std::string(kDefaultConfig) + ")");
  std::string checkConfigPath;
  auto* checkConfig = cli.add_option("--check-config", checkConfigPath,
                                     "Check a configuration strictly (default: the --config file, else " +
                                         std::string(kDefaultConfig) + "), name each bad line as FILE:LINE: message, "
                                         "exit 0 when it is good and 1 when not; the kiosk does not start")
                          ->expected(0, 1);
  cli.set_version_flag("--version", std::string("emboss-kiosk ") + versionString());
  cli.add_option("--size", size, "Picture size WxH for headless, osmesa and x11 (default 1280x800)");
  cli.add_flag("--stats", stats, "Print frames per second and stroke-to-screen latency at exit");
  cli.add_option("--sessions-dir", sessionsDir, "Where visitors' sessions are saved");
  cli.add_option("--pieces", piecesDir, "The folder of attract pieces (*.json)");
  cli.add_option("--export-dir", exportDir, "Where staff export sessions to (a USB stick's mount point)");
  std::string staffSocketPath;
  cli.add_option("--staff-socket", staffSocketPath, "The staff socket embossctl talks to (default $RUNTIME_DIRECTORY/staff.sock; none: off)");
  std::string logLevel = "info";
  cli.add_option("--log-level", logLevel, "error | warn | info | debug (debug: every stroke made durable)")
      ->check(CLI::IsMember({"error", "warn", "info", "debug"}));
  cli.add_option("--threads", threads, "Render threads (0: one per core)")->check(CLI::Range(0, 256));
  std::string attractStart;
  cli.add_option("--attract-start", attractStart, "INDEX:FRACTION: the first attract piece and how far along it starts")
      ->group("");
  cli.add_option("--write-pieces", writePiecesDir, "Write the built-in attract pieces as scene files into DIR, then exit")
      ->group("");
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  emboss::tuneHeapForKiosk();  // the kiosk's memory comes back down after each piece (util/heap_release.h)
  if (!writePiecesDir.empty()) return writePieces(writePiecesDir);
  if (checkConfig->count() > 0) {
    const fs::path file = !checkConfigPath.empty() ? checkConfigPath : !configPath.empty() ? configPath : kDefaultConfig;
    const auto problems = checkKioskConfigFile(file);
    for (const auto& p : problems) std::fprintf(stderr, "%s\n", p.c_str());
    if (!problems.empty()) {
      std::fprintf(stderr, "emboss-kiosk: %s: %zu problem%s\n", file.c_str(), problems.size(), problems.size() == 1 ? "" : "s");
      return 1;
    }
    std::printf("%s: ok\n", file.c_str());
    return 0;
  }
  gLogLevel = logLevelByName(logLevel);
  gOnJournal = stderrIsJournal();

  try {
    // ---- configuration: the file, then the command line
    KioskConfig config;
    std::vector<std::string> warnings;
    if (!configPath.empty()) config = loadKioskConfig(configPath, config, warnings);
    for (const auto& w : warnings) logLine("config: " + w);
    if (!display.empty()) config.display = display;
    if (!tablet.empty()) config.tablet = tablet;
    if (!buttons.empty()) config.buttons = buttons;
    if (!camera.empty()) {
      if (!isCameraSpec(camera)) {
        logLine("--camera must be auto, none, /dev/videoN or file:PNG, not '" + camera + "'");
        return 2;
      }
      config.camera = camera;
    }
    if (!size.empty() && !parseSizeWxH(size, config.width, config.height)) {
      logLine("--size must be WxH, e.g. 1280x800 (16..16384 each), not '" + size + "'");
      return 2;
    }
    if (!sessionsDir.empty()) config.sessionsDir = sessionsDir;
    if (config.sessionsDir.empty()) config.sessionsDir = defaultSessionsDir();
    if (!piecesDir.empty()) config.piecesDir = piecesDir;
    if (!exportDir.empty()) config.exportDir = exportDir;
    if (threads >= 0) config.threads = threads;
    // The metals' shading tables are kept between starts (a restart shows its first frame sooner).
    setTableCache(defaultTableCacheDir(), logLine);
    const bool replay = config.tablet.rfind("evemu:", 0) == 0;
    if (fast && !replay) {
      logLine("--fast feeds a recording: give --tablet=evemu:PATH as well");
      return 2;
    }

    auto notifier = createSystemNotifier();
    // A stop asked for while starting ends the start with status 0: nothing a visitor made is in
    // memory yet (an unfinished session is in the journal, and comes back at the next start).
    const auto stoppedWhileStarting = [&] {
      if (gStop) logLine("stopping (signal) before the first frame");
      return gStop != 0;
    };

    // ---- the display: the one asked for, else the memory fallback (auto only)
    std::string tries;
    Result<std::unique_ptr<Display>> made = fail("display: not tried");
    bool gpu = false;
    std::error_code ec;
    for (fs::directory_iterator it("/dev/dri", ec), end; !ec && it != end; it.increment(ec))
      gpu |= it->path().filename().string().rfind("card", 0) == 0;
    if (config.display == "kms" && gpu) {
      // On the board the screen may come up after the kiosk (or be unplugged): wait a while,
      // saying why. Without any GPU driver there is nothing to wait for.
      std::string last;
      made = waitForKmsDisplay(std::chrono::seconds(60), {}, [&](const std::string& error) {
        if (error != last) logLine(error + "; waiting for a screen"), last = error;
        notifier->status("waiting for a screen: " + error);
        notifier->alive(monotonicSeconds());
        return gStop == 0;
      });
    } else {
      made = createDisplay(config.display, config.width, config.height, &tries);
    }
    if (stoppedWhileStarting()) return 0;
    std::unique_ptr<Display> screen;
    if (made) {
      screen = std::move(*made);
      logLine("display: " + screen->name() + " " + std::to_string(screen->width()) + "x" + std::to_string(screen->height()));
    } else if (config.display == "auto") {
      logLine(made.error() + "; drawing into memory only (snapshots still work)");
      screen = std::make_unique<MemoryDisplay>(config.width, config.height, "no display back end started");
    } else {
      logLine(made.error());
      return 1;
    }
    X11Display* x11 = asX11Display(screen.get());
    // A lost display is looked for again as the same kind: with auto, a screen that was unplugged
    // from the board must come back on kms, not be replaced by the headless fallback.
    std::string reprobe = config.display;
    if (reprobe == "auto" && made) {
      for (const char* kind : {"kms", "x11", "headless", "osmesa"})
        if (screen->name().rfind(kind, 0) == 0) reprobe = kind;
    }

    // ---- the attract pieces: from disk, else built in
    std::vector<AttractPiece> pieces;
    if (const auto dir = findPiecesDir(config.piecesDir, argv[0])) {
      pieces = loadAttractPieces(*dir, logLine);
      logLine("attract: " + std::to_string(pieces.size()) + " pieces from " + dir->string());
    } else if (!config.piecesDir.empty()) {
      logLine("attract: '" + config.piecesDir.string() + "' is not a folder");
    }
    if (pieces.empty()) {
      pieces = builtinAttractPieces();
      logLine("attract: playing the " + std::to_string(pieces.size()) + " built-in pieces");
    }

    if (stoppedWhileStarting()) return 0;
    const auto clock = [] { return monotonicSeconds(); };
    KioskStart start;
    start.staff = staff;
    if (!attractStart.empty()) {
      unsigned index = 0;
      double fraction = 0;
      if (std::sscanf(attractStart.c_str(), "%u:%lf", &index, &fraction) != 2 || fraction < 0 || fraction > 1) {
        logLine("--attract-start must be INDEX:FRACTION, e.g. 2:0.8");
        return 2;
      }
      start.attractPiece = index;
      start.attractDone = fraction;
    }
    // Declared before the app: a still under way on the app's capture thread uses it until the app is gone.
    std::unique_ptr<CameraSource> cam;
    KioskApp app(config, std::move(pieces), *screen, logLine, clock, start);
    app.setTextPainterFactory([]() -> std::unique_ptr<TextPainter> {
      auto painter = AtlasTextPainter::create();
      if (painter) return std::move(*painter);
      logLine("export: " + painter.error() + "; the postcards get no caption");
      return nullptr;
    });
    app.setDeviceNote("Service manager", notifier->name());

    // ---- input: a recording, a tablet, the mouse; GPIO buttons, the keyboard
    std::unique_ptr<PenSource> pen;
    std::unique_ptr<MousePen> mouse;
    std::unique_ptr<KeyButtons> keys;
    std::unique_ptr<ButtonSource> gpio;
    bool recordingFailed = false;
    if (x11 && !attractOnly) {
      mouse = std::make_unique<MousePen>(screen->width(), screen->height(), clock);
      keys = std::make_unique<KeyButtons>(config.keys, clock);
      app.addButtons(keys.get());
    }
    // Why no tablet is in use (a tablet that was found but cannot be used is named, with the
    // reason), for the staff screen; the whole text is in the log.
    auto tabletNote = [&](const std::string& why) {
      app.setDeviceNote("Tablet", why.size() > 160 ? why.substr(0, 157) + "..." : why);
    };
    auto attachPen = [&] {
      if (attractOnly) return;
      if (pen) {
        app.setPen(pen.get(), PenMapping::Tablet, fast);
        // A recording fed as fast as possible makes the same operations on every run: its points
        // are found on the model alone, not through a frame whose progress depends on the speed.
        app.setPickThroughRenderer(!fast);
      } else if (mouse) app.setPen(mouse.get(), PenMapping::Screen);
      else app.setPen(nullptr, PenMapping::Tablet);
    };
    if (replay) {
      auto r = openEvemuReplay(config.tablet.substr(6), fast);
      if (r) {
        pen = std::move(*r);
        logLine("tablet: " + pen->name() + (fast ? " (fed as fast as possible)" : " (replayed in real time)"));
      } else {
        logLine("tablet: " + r.error() + "; going on without a pen");
        recordingFailed = true;
      }
    } else if (config.tablet == "auto" && !attractOnly) {
      auto r = openFirstTablet();
      if (r) {
        pen = std::move(*r);
        logLine("tablet: " + pen->name());
      } else {
        logLine("tablet: " + r.error() + (mouse ? "; the mouse stands in" : "; looking again every second"));
        tabletNote(r.error());
      }
    } else if (config.tablet != "none" && config.tablet != "auto") {
      logLine("tablet: unknown '" + config.tablet + "' (auto, evemu:PATH or none); going on without a pen");
    }
    attachPen();
    std::optional<ButtonConfig> gpioConfig;  // the wiring, kept to open the buttons again
    if (!attractOnly && config.buttons != "none") {
      Result<ButtonConfig> bc = config.buttons == "auto" ? Result<ButtonConfig>(defaultButtonConfig()) : loadButtonConfig(config.buttons);
      if (bc) gpioConfig = *bc;
      if (!bc) {
        logLine("buttons: " + bc.error() + "; going on without GPIO buttons (the keyboard stands in)");
      } else if (auto g = openGpioButtons(*bc)) {
        gpio = std::move(*g);
        app.addButtons(gpio.get());
        logLine("buttons: " + gpio->name());
      } else {
        logLine("buttons: " + g.error() + "; the keyboard stands in, looking again every 3 s");
      }
    }

    // ---- the camera for capture drawing: optional; looked for again every 3 s while there is none
    const bool wantCamera = !attractOnly && config.camera != "none";
    std::string lastCameraError;
    auto openCamera = [&] {
      Result<std::unique_ptr<CameraSource>> r = config.camera.rfind("file:", 0) == 0 ? openFileCamera(config.camera.substr(5))
                                                                                      : openV4l2Camera(config.camera);
      if (r) {
        cam = std::move(*r);
        app.setCamera(cam.get());
        logLine("camera: " + cam->name() + " (capture drawing on)");
        lastCameraError.clear();
      } else if (r.error() != lastCameraError) {
        lastCameraError = r.error();
        logLine(r.error() + (lastCameraError.find("capture drawing") == std::string::npos ? "; capture drawing is off" : "") +
                "; looking again every 3 s");
      }
    };
    if (wantCamera) openCamera();

    // The staff socket (embossctl): answered on the main loop; an export runs on a thread of its own.
    std::unique_ptr<StaffSocket> staffSocket;
    if (staffSocketPath != "none") {
      if (auto r = StaffSocket::listen(staffSocketPath.empty() ? StaffSocket::defaultPath() : staffSocketPath)) {
        staffSocket = std::move(*r);
        logLine("staff: embossctl socket " + staffSocket->path());
      } else {
        logLine("<4>" + r.error() + "; embossctl cannot reach this kiosk");
      }
    }
    notifier->ready(attractOnly ? "attract mode only" : "attract mode");
    // The watchdog is fed from a thread of its own while work is being done: turns of this loop and
    // tiles traced (util/progress_beat.h). A first frame that takes longer than WatchdogSec on a slow
    // board is then not taken for a hang; a stuck loop (nothing moves) or a stopped process still is.
    struct Feeder {
      std::atomic_bool stop{false};
      std::thread thread;
      ~Feeder() {
        stop = true;
        if (thread.joinable()) thread.join();
      }
    } feeder;
    if (const double wd = notifier->watchdogSeconds(); wd > 0) {
      feeder.thread = std::thread([&, wd] {
        WatchdogFeeder due(wd / 4);
        while (!feeder.stop.load()) {
          const double now = monotonicSeconds();
          if (due.due(progressBeats().load(std::memory_order_relaxed), now)) notifier->alive(now);
          std::this_thread::sleep_for(std::chrono::milliseconds(250));
        }
      });
    }
    std::string lastStatus;
    const double t0 = monotonicSeconds();
    double lastProbe = t0, lastDisplayTry = t0, lastCameraProbe = t0, lastGpioProbe = t0;
    std::vector<X11Event> xev;
    std::vector<pollfd> waitFds;
    bool closed = false;
    bool displayMissing = false;  // the display was lost; a stand-in in memory is shown meanwhile
    while (!gStop) {
      if (x11) {
        xev.clear();
        if (!x11->pollX11Events(xev)) closed = true;
        for (const auto& e : xev) {
          if (e.type == X11Event::Type::kClose) closed = true;
          const PointerEvent p = toPointer(e);
          if (attractOnly) {
            if (p.type == PointerEvent::Type::Key && (p.key == "Escape" || p.key == "q")) closed = true;
            continue;
          }
          if (mouse) mouse->feed(p);
          if (keys) keys->feed(p);
        }
        if (closed) break;
      }
      if (!app.step()) break;
      if (staffSocket)
        staffSocket->poll([&](const std::string& line) { return app.staffCommand(line); }, [&] { return app.staffPoll(); });
      const double now = monotonicSeconds();
      progressBeat();
      // STATUS= in systemctl status: what the kiosk is doing now.
      if (std::string st = app.statusLine(); st != lastStatus) {
        notifier->status(st);
        lastStatus = std::move(st);
      }
      if (runFor > 0 && now - t0 >= runFor) break;
      if (fast && (recordingFailed || app.feedDone())) break;
      // A lost tablet: look for one again every second (the mouse stands in meanwhile), so a replugged
      // tablet is back within two seconds of the kernel seeing it.
      if (app.penLost() && !replay) {
        pen.reset();
        attachPen();
      }
      if (!pen && !replay && config.tablet == "auto" && !attractOnly && now - lastProbe > 1.0) {
        lastProbe = now;
        if (auto r = openFirstTablet()) {
          pen = std::move(*r);
          logLine("tablet: " + pen->name());
          tabletNote("");
          attachPen();
        } else {
          tabletNote(r.error());  // the log has it once (logOnce); the staff screen keeps it current
        }
      }
      // GPIO buttons that stopped answering (a USB GPIO adapter pulled out, a chip's driver gone)
      // were dropped by the app; they are opened again every 3 s, as is a chip that was not there
      // at start (its driver may come up after the kiosk). The keyboard stands in meanwhile.
      if (gpio && !app.hasButtons(gpio.get())) {
        gpio.reset();
        lastGpioProbe = now;
      }
      if (!gpio && gpioConfig && now - lastGpioProbe > 3.0) {
        lastGpioProbe = now;
        if (auto g = openGpioButtons(*gpioConfig)) {
          gpio = std::move(*g);
          app.addButtons(gpio.get());
          logLine("buttons: back: " + gpio->name());
        }
      }
      // A lost camera: dropped, and looked for again every 3 s (capture drawing is off meanwhile).
      if (app.cameraLost()) {
        app.setCamera(nullptr);
        cam.reset();
        lastCameraProbe = now;
      }
      if (wantCamera && !cam && now - lastCameraProbe > 3.0) {
        lastCameraProbe = now;
        openCamera();
      }
      // A lost display is let go of at once (a stand-in in memory keeps its size for the app and the
      // snapshot): a KMS output stays owned (DRM master) by its file while it is open, and the
      // display taken again must be able to set its mode.
      if (app.displayLost() && !displayMissing) {
        auto standIn = std::make_unique<MemoryDisplay>(screen->width(), screen->height(), "display lost");
        app.setDisplay(*standIn);
        screen = std::move(standIn);
        x11 = nullptr;
        displayMissing = true;
      }
      if (displayMissing && now - lastDisplayTry > 2.0) {
        lastDisplayTry = now;
        std::string log;
        if (auto d = createDisplay(reprobe, config.width, config.height, &log)) {
          screen = std::move(*d);
          x11 = asX11Display(screen.get());
          app.setDisplay(*screen);
          displayMissing = false;
          logLine("display: back: " + screen->name());
        }
      }
      // Tracing: attract mode's next work may wait for the next tick (a camera in motion: its next
      // preview; the loop turned thousands of times a second), at most 5 ms. Nothing to trace: the
      // loop sleeps until a descriptor is readable (the pen, the GPIO buttons, embossctl), a source
      // must be polled (a pen without a descriptor, a recording's next sample, a button's debounce
      // or long-press deadline) or an animated screen's next tick is due (attract mode paused, the
      // countdown); at most kIdleWaitS, the lateness the loop's other clocks allow (the probes, the
      // idle timeout, an export's progress). It turned every 5 ms, which cost about 2 % of a core
      // with the screen unchanged. An X11 window keeps the 5 ms: Xlib may hold events it read in
      // passing, with nothing left on its socket to wake a poll.
      double wait = app.busy() ? std::min(kPollPaceS, app.idleSeconds()) : std::min(x11 ? kPollPaceS : kIdleWaitS, app.wakeWithin());
      if (pen) wait = std::min(wait, pen->pollWithin());
      if (gpio) wait = std::min(wait, gpio->pollWithin());
      if (wait > 0.0) {
        waitFds.clear();
        if (pen && pen->fd() >= 0) waitFds.push_back({pen->fd(), POLLIN, 0});
        if (gpio && gpio->fd() >= 0) waitFds.push_back({gpio->fd(), POLLIN, 0});
        if (staffSocket) staffSocket->addPollFds(waitFds);
        const timespec ts{static_cast<time_t>(wait), static_cast<long>((wait - std::floor(wait)) * 1e9)};
        ::ppoll(waitFds.data(), waitFds.size(), &ts, nullptr);
      }
    }
    if (gStop) logLine("stopping (signal)");
    feeder.stop = true;
    if (feeder.thread.joinable()) feeder.thread.join();
    notifier->stopping();
    // The screen's last frame traced to the end only for a snapshot, and for at most 10 s: the
    // unit's stop timeout is 15 s, and the session is saved before.
    app.finish(!snapshot.empty(), kLastFrameLimitMs);
    int rc = 0;
    if (!snapshot.empty()) {
      Status s = app.writeSnapshot(snapshot);
      if (s) std::printf("emboss-kiosk: wrote snapshot %s (%dx%d)\n", fs::absolute(snapshot).c_str(), screen->width(), screen->height());
      else logLine("snapshot: " + s.error()), rc = 1;
    }
    if (!sessionOut.empty()) {
      Status s = app.writeSession(sessionOut);
      if (s) std::printf("emboss-kiosk: wrote session %s\n", fs::absolute(sessionOut).c_str());
      else logLine("session: " + s.error()), rc = 1;
    }
    if (stats) std::fputs(app.statsReport().c_str(), stdout);
    if (fast && recordingFailed) rc = 1;
    return rc;
  } catch (const std::exception& e) {
    logLine(std::string("stopped by an unexpected error: ") + e.what());
    return 1;
  }
}

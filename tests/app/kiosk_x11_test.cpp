// The kiosk on a desktop: the X11 window's mouse is the pen (left button = tip) and its keyboard
// the buttons, end to end under Xvfb (skipped without it).
#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "app/kiosk_app.h"
#include "app/pointer_input.h"
#include "display/display_x11.h"
#include "frep/workpieces.h"
#include "test_support.h"

// Xlib last: its macros (None, Status, ...) would clash with the project's names.
#include <X11/Xlib.h>
#include <X11/keysym.h>

namespace emboss {
namespace {

class XvfbServer {
 public:
  XvfbServer() {
    const char* binary = ::access("/usr/bin/Xvfb", X_OK) == 0 ? "/usr/bin/Xvfb" : nullptr;
    if (!binary) return;
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      std::freopen("/dev/null", "w", stderr);
      ::execl(binary, "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "800x600x24", "-nolisten", "tcp", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline && ::poll(&p, 1, 100) >= 0) {
      if (!(p.revents & (POLLIN | POLLHUP))) continue;
      char c;
      if (::read(fds[0], &c, 1) != 1) break;
      if (c == '\n') {
        display_ = ":" + number;
        break;
      }
      number += c;
    }
    ::close(fds[0]);
  }
  ~XvfbServer() {
    if (pid_ > 0) ::kill(pid_, SIGTERM), ::waitpid(pid_, nullptr, 0);
  }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

void send(::Display* x, unsigned long window, XEvent e, long mask) {
  e.xany.window = window;
  e.xany.display = x;
  e.xany.send_event = 1;
  XSendEvent(x, window, 0, mask, &e);
  XFlush(x);
}

// The same translation emboss-kiosk's main() makes.
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

TEST(KioskX11, MouseDragEmbossesAndKeysAreButtons) {
  XvfbServer server;
  if (server.display().empty()) GTEST_SKIP() << "Xvfb not available; the mouse path is not tested here";
  const char* old = std::getenv("DISPLAY");
  const std::string saved = old ? old : "";
  ::setenv("DISPLAY", server.display().c_str(), 1);
  auto made = createX11Display(480, 300);
  ASSERT_TRUE(made) << made.error();
  X11Display* x11 = asX11Display(made->get());
  ASSERT_NE(x11, nullptr);

  const auto dir = test::scratchDir("kiosk-x11");
  KioskConfig config;
  config.sessionsDir = dir / "sessions";
  config.threads = 2;
  const auto clock = [] { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); };
  Scene piece;
  piece.workpiece = std::make_shared<Plate>(30.0, 20.0, 0.5);
  Operation op;
  op.kind = OpKind::Punch;
  op.a = 3, op.p = 0.2, op.at = {0, 0, 0.5};
  piece.operations = {op};
  KioskApp app(config, {{"tiny", piece}}, **made, {}, clock);
  MousePen mouse(480, 300, clock);
  KeyButtons keys(config.keys, clock);
  app.setPen(&mouse, PenMapping::Screen);
  app.addButtons(&keys);

  ::Display* client = XOpenDisplay(server.display().c_str());
  ASSERT_NE(client, nullptr);
  const unsigned long window = x11->windowId();
  auto pump = [&](int steps) {
    for (int i = 0; i < steps; ++i) {
      std::vector<X11Event> ev;
      x11->pollX11Events(ev);
      for (const auto& e : ev) {
        mouse.feed(toPointer(e));
        keys.feed(toPointer(e));
      }
      app.step();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  };
  pump(3);
  EXPECT_EQ(app.mode(), KioskMode::Attract);
  // A drag across the middle of the sheet with the left button.
  XEvent e{};
  e.xbutton.type = ButtonPress, e.xbutton.x = 170, e.xbutton.y = 150, e.xbutton.button = Button1, e.xbutton.same_screen = 1;
  send(client, window, e, ButtonPressMask);
  for (int x = 172; x <= 320; x += 4) {
    e = XEvent{};
    e.xmotion.type = MotionNotify, e.xmotion.x = x, e.xmotion.y = 150 + (x - 170) / 6, e.xmotion.state = Button1Mask;
    e.xmotion.same_screen = 1;
    send(client, window, e, PointerMotionMask);
    pump(1);
  }
  e = XEvent{};
  e.xbutton.type = ButtonRelease, e.xbutton.x = 320, e.xbutton.y = 175, e.xbutton.button = Button1, e.xbutton.same_screen = 1;
  send(client, window, e, ButtonReleaseMask);
  pump(20);
  EXPECT_EQ(app.mode(), KioskMode::Visitor);
  EXPECT_EQ(app.bench().strokes(), 1u);
  EXPECT_GT(app.bench().model().activeCount(), 10u);  // about 25 mm of tracer, in 4 mm pieces and more
  // Keys: Right is the next tool, z undoes the stroke.
  for (KeySym k : {XK_Right, XK_z}) {
    e = XEvent{};
    e.xkey.type = KeyPress, e.xkey.keycode = XKeysymToKeycode(client, k), e.xkey.same_screen = 1;
    send(client, window, e, KeyPressMask);
    pump(10);
  }
  EXPECT_EQ(app.bench().toolIndex(), 2u);
  EXPECT_EQ(app.bench().model().activeCount(), 0u);
  XCloseDisplay(client);
  made->reset();
  if (old) ::setenv("DISPLAY", saved.c_str(), 1);
  else ::unsetenv("DISPLAY");
}

}  // namespace
}  // namespace emboss

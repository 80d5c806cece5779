// The X11 display: an X window with a visual matching an EGL config, EGL_PLATFORM_X11_KHR window
// surface, the GL presenter, and the window's pointer and keys translated into X11Events.
#include "display/display_x11.h"

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#undef Status  // Xlib's macro; emboss::Status is meant below

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <thread>

#include "gl/gl_egl.h"

namespace emboss {
namespace {

constexpr std::size_t kMaxQueuedEvents = 4096;  // when the app never polls, old events are dropped

// Protocol errors (a BadWindow from a vanished window) must not end the kiosk: Xlib's default
// handler exits. Returning from the I/O error handler is allowed since libX11 1.7; the per
// display exit handler then marks the output lost instead of calling exit().
int onXError(::Display* /*x*/, XErrorEvent* /*event*/) { return 0; }
int onXIoError(::Display* /*x*/) { return 0; }

void installErrorHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    XSetErrorHandler(onXError);
    XSetIOErrorHandler(onXIoError);
  });
}

class X11DisplayImpl final : public X11Display {
 public:
  X11DisplayImpl(::Display* x, int width, int height) : x_(x), width_(width), height_(height) {
    XSetIOErrorExitHandler(x_, &X11DisplayImpl::onConnectionLost, this);
  }

  ~X11DisplayImpl() override {
    if (session_ && session_->makeCurrent()) presenter_.reset();
    presenter_.reset();
    session_.reset();  // the EGL surface before its window
    if (!lost_) {
      if (window_ != 0) XDestroyWindow(x_, window_);
      if (colormap_ != 0) XFreeColormap(x_, colormap_);
    }
    XCloseDisplay(x_);
  }

  emboss::Status start(const GlPresenterSettings& settings) {
    if (!hasEglExtension(EGL_NO_DISPLAY, "EGL_KHR_platform_x11") &&
        !hasEglExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_x11")) {
      return fail("x11: this EGL cannot draw into X windows (no EGL_KHR_platform_x11; install libegl-mesa0)");
    }
    auto session = EglSession::open(EGL_PLATFORM_X11_KHR, x_, "x11");
    if (!session) return fail(session.error());
    session_ = std::move(*session);
    // An opaque 24-bit visual if there is one (a 32-bit ARGB one would let a compositor show
    // through), else whatever visual the config has.
    const EGLDisplay display = session_->display();
    auto visualDepth = [this, display](EGLConfig config) {
      EGLint id = 0;
      if (!eglGetConfigAttrib(display, config, EGL_NATIVE_VISUAL_ID, &id) || id == 0) return 0;
      XVisualInfo wanted{};
      wanted.visualid = static_cast<VisualID>(id);
      int count = 0;
      XVisualInfo* info = XGetVisualInfo(x_, VisualIDMask, &wanted, &count);
      const int depth = info != nullptr && count > 0 ? info->depth : 0;
      if (info != nullptr) XFree(info);
      return depth;
    };
    if (!session_->createContext(EGL_WINDOW_BIT, [&](EGLConfig c) { return visualDepth(c) == 24; })) {
      if (emboss::Status s = session_->createContext(EGL_WINDOW_BIT, [&](EGLConfig c) { return visualDepth(c) > 0; });
          !s) {
        return s;
      }
    }
    EGLint visualId = 0;
    eglGetConfigAttrib(display, session_->config(), EGL_NATIVE_VISUAL_ID, &visualId);
    XVisualInfo wanted{};
    wanted.visualid = static_cast<VisualID>(visualId);
    int count = 0;
    XVisualInfo* visual = XGetVisualInfo(x_, VisualIDMask, &wanted, &count);
    if (visual == nullptr || count == 0) return fail("x11: the X server has no visual for the EGL config");
    const Window root = RootWindow(x_, visual->screen);
    colormap_ = XCreateColormap(x_, root, visual->visual, AllocNone);
    XSetWindowAttributes attributes{};
    attributes.colormap = colormap_;
    attributes.background_pixel = BlackPixel(x_, visual->screen);
    attributes.border_pixel = 0;
    attributes.event_mask = StructureNotifyMask | KeyPressMask | ButtonPressMask | ButtonReleaseMask |
                            PointerMotionMask | EnterWindowMask | LeaveWindowMask;
    window_ = XCreateWindow(x_, root, 0, 0, static_cast<unsigned>(width_), static_cast<unsigned>(height_), 0,
                            visual->depth, InputOutput, visual->visual,
                            CWBackPixel | CWBorderPixel | CWColormap | CWEventMask, &attributes);
    XFree(visual);
    if (window_ == 0) return fail("x11: cannot create a " + sizeText() + " window");
    XStoreName(x_, window_, "emboss");
    XClassHint classHint{};
    char resName[] = "emboss";
    char resClass[] = "Emboss";
    classHint.res_name = resName;
    classHint.res_class = resClass;
    XSetClassHint(x_, window_, &classHint);
    XSizeHints* hints = XAllocSizeHints();
    if (hints != nullptr) {  // fixed size: the frame is width x height
      hints->flags = PMinSize | PMaxSize;
      hints->min_width = hints->max_width = width_;
      hints->min_height = hints->max_height = height_;
      XSetWMNormalHints(x_, window_, hints);
      XFree(hints);
    }
    wmDelete_ = XInternAtom(x_, "WM_DELETE_WINDOW", False);
    XSetWMProtocols(x_, window_, &wmDelete_, 1);
    XMapWindow(x_, window_);
    waitUntilMapped();
    if (lost_) return fail("x11: the X server went away while the window was opening");

    if (emboss::Status s = session_->createWindowSurface(&window_); !s) return s;
    if (!session_->makeCurrent()) {
      return fail("x11: cannot make the GLES context current (" + eglErrorName(eglGetError()) + ")");
    }
    session_->setSwapInterval(1);
    auto presenter = GlPresenter::create(session_->procLoader(), GlFlavor::kGles2, width_, height_, false, settings);
    if (!presenter) return fail("x11: " + presenter.error());
    presenter_ = std::move(*presenter);
    name_ = "x11 (EGL window " + sizeText() + ", " + presenter_->renderer() + ")";
    return Ok{};
  }

  std::string name() const override { return name_; }
  int width() const override { return width_; }
  int height() const override { return height_; }

  bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) override {
    pumpEvents();  // notices a closed window or a dead server even if the app never polls
    if (lost_ || closed_) return false;
    if (!session_->makeCurrent()) return false;
    if (!presenter_->draw(frame, dirty, overlay)) return false;
    if (!session_->swapBuffers()) return false;
    return !lost_;
  }

  Image screenshot() override {
    if (lost_ || !session_->makeCurrent()) return Image();
    return presenter_->screenshot();
  }

  bool pollX11Events(std::vector<X11Event>& out) override {
    pumpEvents();
    out.insert(out.end(), std::make_move_iterator(queue_.begin()), std::make_move_iterator(queue_.end()));
    queue_.clear();
    return !(lost_ || closed_);
  }

  X11Input input() const override { return input_; }
  unsigned long windowId() const override { return window_; }

 private:
  static void onConnectionLost(::Display* /*x*/, void* self) { static_cast<X11DisplayImpl*>(self)->lost_ = true; }

  std::string sizeText() const { return std::to_string(width_) + "x" + std::to_string(height_); }

  void waitUntilMapped() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!lost_ && std::chrono::steady_clock::now() < deadline) {
      XEvent event;
      if (XCheckTypedWindowEvent(x_, window_, MapNotify, &event)) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }

  void push(X11Event::Type type, float x, float y, std::uint32_t time, std::string key = {}) {
    if (queue_.size() >= kMaxQueuedEvents) queue_.pop_front();
    X11Event e;
    e.type = type;
    e.x = x;
    e.y = y;
    e.penDown = input_.penDown;
    e.key = std::move(key);
    e.timeMs = time;
    queue_.push_back(std::move(e));
  }

  void pumpEvents() {
    while (!lost_ && XPending(x_) > 0) {
      XEvent event;
      XNextEvent(x_, &event);
      if (lost_) break;
      translate(event);
    }
  }

  void translate(XEvent& event) {
    switch (event.type) {
      case MotionNotify:
        input_.x = static_cast<float>(event.xmotion.x);
        input_.y = static_cast<float>(event.xmotion.y);
        push(X11Event::Type::kMove, input_.x, input_.y, static_cast<std::uint32_t>(event.xmotion.time));
        break;
      case ButtonPress:
      case ButtonRelease: {
        const bool press = event.type == ButtonPress;
        input_.x = static_cast<float>(event.xbutton.x);
        input_.y = static_cast<float>(event.xbutton.y);
        const auto time = static_cast<std::uint32_t>(event.xbutton.time);
        if (event.xbutton.button == Button1) {
          input_.penDown = press;
          push(press ? X11Event::Type::kPenDown : X11Event::Type::kPenUp, input_.x, input_.y, time);
        } else if (press && (event.xbutton.button == Button4 || event.xbutton.button == Button5)) {
          push(X11Event::Type::kKey, input_.x, input_.y, time,
               event.xbutton.button == Button4 ? "WheelUp" : "WheelDown");
        }
        break;
      }
      case EnterNotify:
      case LeaveNotify:
        input_.inside = event.type == EnterNotify;
        input_.x = static_cast<float>(event.xcrossing.x);
        input_.y = static_cast<float>(event.xcrossing.y);
        break;
      case KeyPress: {
        char text[32] = {};
        KeySym sym = NoSymbol;
        XLookupString(&event.xkey, text, sizeof text - 1, &sym, nullptr);
        const char* symName = sym != NoSymbol ? XKeysymToString(sym) : nullptr;
        std::string key = symName != nullptr ? symName : text;
        if (!key.empty()) {
          push(X11Event::Type::kKey, input_.x, input_.y, static_cast<std::uint32_t>(event.xkey.time), std::move(key));
        }
        break;
      }
      case ClientMessage:
        if (static_cast<Atom>(event.xclient.data.l[0]) == wmDelete_) {
          closed_ = true;
          push(X11Event::Type::kClose, input_.x, input_.y, 0);
        }
        break;
      case DestroyNotify:
        if (event.xdestroywindow.window == window_) {
          closed_ = true;
          push(X11Event::Type::kClose, input_.x, input_.y, 0);
        }
        break;
      default:
        break;
    }
  }

  ::Display* x_;
  int width_, height_;
  Window window_ = 0;
  Colormap colormap_ = 0;
  Atom wmDelete_ = 0;
  std::unique_ptr<EglSession> session_;
  std::unique_ptr<GlPresenter> presenter_;
  std::string name_;
  std::deque<X11Event> queue_;
  X11Input input_;
  bool closed_ = false;
  bool lost_ = false;
};

}  // namespace

Result<std::unique_ptr<Display>> createX11Display(int width, int height, const GlPresenterSettings& settings) {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0') {
    return fail("x11: $DISPLAY not set (no X server; on the kiosk use kms, for a test run use xvfb-run)");
  }
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    return fail("x11: bad window size " + std::to_string(width) + "x" + std::to_string(height));
  }
  installErrorHandlers();
  ::Display* x = XOpenDisplay(nullptr);
  if (x == nullptr) {
    return fail(std::string("x11: cannot open display '") + name +
                "' (is the X server running, and may this user connect? check xauth/xhost)");
  }
  auto display = std::make_unique<X11DisplayImpl>(x, width, height);
  if (emboss::Status s = display->start(settings); !s) return fail(s.error());
  return std::unique_ptr<Display>(std::move(display));
}

}  // namespace emboss

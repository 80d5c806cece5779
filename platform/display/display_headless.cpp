// The headless display: EGL_MESA_platform_surfaceless (or a pbuffer on the default EGL display)
// with the presenter drawing into its own FBO.
#include "display/display_headless.h"

#include "gl/gl_egl.h"

namespace emboss {
namespace {

class HeadlessDisplay final : public Display {
 public:
  HeadlessDisplay(std::unique_ptr<EglSession> session, std::unique_ptr<GlPresenter> presenter, std::string how)
      : session_(std::move(session)), presenter_(std::move(presenter)),
        name_("headless (" + how + ", " + presenter_->renderer() + ")") {}
  ~HeadlessDisplay() override {
    session_->makeCurrent();  // the presenter frees its GL objects in this context
    presenter_.reset();
  }

  std::string name() const override { return name_; }
  int width() const override { return presenter_->width(); }
  int height() const override { return presenter_->height(); }

  bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) override {
    if (!session_->makeCurrent()) return false;
    return presenter_->draw(frame, dirty, overlay);
  }

  Image screenshot() override {
    if (!session_->makeCurrent()) return Image();
    return presenter_->screenshot();
  }

 private:
  std::unique_ptr<EglSession> session_;
  std::unique_ptr<GlPresenter> presenter_;
  std::string name_;
};

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace

Result<std::unique_ptr<Display>> createHeadlessDisplay(int width, int height, const GlPresenterSettings& settings) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    return fail("headless: bad size " + sizeText(width, height));
  }
  const bool surfaceless = hasEglExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless");
  std::string how;
  std::unique_ptr<EglSession> session;
  if (surfaceless) {
    auto opened = EglSession::open(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "headless");
    if (!opened) return fail(opened.error());
    session = std::move(*opened);
    how = "EGL surfaceless";
  } else {
    // No Mesa surfaceless platform: the default EGL display with a pbuffer does the same job.
    auto opened = EglSession::open(EGL_NONE, EGL_DEFAULT_DISPLAY, "headless");
    if (!opened) {
      return fail(opened.error() + "; this EGL also lacks EGL_MESA_platform_surfaceless (install "
                  "Mesa's libegl-mesa0, or use osmesa)");
    }
    session = std::move(*opened);
    how = "EGL default display";
  }
  if (Status s = session->createContext(EGL_PBUFFER_BIT); !s) return fail(s.error());
  if (!surfaceless || !hasEglExtension(session->display(), "EGL_KHR_surfaceless_context")) {
    if (Status s = session->createPbufferSurface(width, height); !s) return fail(s.error());
    how += " + pbuffer";
  }
  if (!session->makeCurrent()) {
    return fail("headless: cannot make the GLES context current (" + eglErrorName(eglGetError()) + ")");
  }
  auto presenter = GlPresenter::create(session->procLoader(), GlFlavor::kGles2, width, height, true, settings);
  if (!presenter) return fail("headless: " + presenter.error());
  return std::unique_ptr<Display>(new HeadlessDisplay(std::move(session), std::move(*presenter), how));
}

}  // namespace emboss

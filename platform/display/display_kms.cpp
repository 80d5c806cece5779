// The KMS display: DRM card and connector discovery, GBM surface, EGL on EGL_PLATFORM_GBM_KHR,
// drmModeSetCrtc for the first frame and drmModePageFlip (waiting for its vblank event) after.
// When the GL is software (llvmpipe: no GPU), the frame is drawn off screen instead and copied into
// the card's dumb buffers under a fault guard (kms_scanout.h), so that a card removed mid-frame is
// a lost output, not a crash.
#include "display/display_kms.h"

#include <fcntl.h>
#include <gbm.h>
#include <poll.h>
#include <unistd.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <algorithm>
#include <cstdlib>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <thread>
#include <utility>
#include <vector>

#include "display/display_headless.h"
#include "gl/gl_egl.h"
#include "display/kms_scanout.h"

namespace emboss {
namespace {

// A 60 Hz flip takes 17 ms, but under load (or emulation) one can take seconds: a slow flip is
// waited for (again before the next one), and only this long without its event means the output
// is gone. One wait is at most a second, so a signal (SIGTERM) is seen within a second.
constexpr int kFlipWaitMs = 1000;
constexpr int kFlipGoneMs = 10000;
constexpr auto kConnectorCheckInterval = std::chrono::seconds(1);

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
      reset();
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  ~UniqueFd() { reset(); }
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

template <class T, void (*Free)(T*)>
struct FreeWith {
  void operator()(T* p) const {
    if (p != nullptr) Free(p);
  }
};
using ResourcesPtr = std::unique_ptr<drmModeRes, FreeWith<drmModeRes, drmModeFreeResources>>;
using ConnectorPtr = std::unique_ptr<drmModeConnector, FreeWith<drmModeConnector, drmModeFreeConnector>>;
using EncoderPtr = std::unique_ptr<drmModeEncoder, FreeWith<drmModeEncoder, drmModeFreeEncoder>>;
using CrtcPtr = std::unique_ptr<drmModeCrtc, FreeWith<drmModeCrtc, drmModeFreeCrtc>>;
using VersionPtr = std::unique_ptr<drmVersion, FreeWith<drmVersion, drmFreeVersion>>;
using GbmDevicePtr = std::unique_ptr<gbm_device, FreeWith<gbm_device, gbm_device_destroy>>;
using GbmSurfacePtr = std::unique_ptr<gbm_surface, FreeWith<gbm_surface, gbm_surface_destroy>>;

// A connected output with an open card, ready to be taken over.
struct Candidate {
  KmsOutput info;
  UniqueFd fd;
  std::uint32_t connectorId = 0;
  std::uint32_t crtcId = 0;
  drmModeModeInfo mode{};
};

std::string cardName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// /dev/dri/card0, card1, ... in numeric order.
std::vector<std::string> listCards() {
  std::vector<std::pair<int, std::string>> cards;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev/dri", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("card", 0) != 0 || name.size() == 4) continue;
    if (!std::all_of(name.begin() + 4, name.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    cards.emplace_back(std::stoi(name.substr(4)), entry.path().string());
  }
  std::sort(cards.begin(), cards.end());
  std::vector<std::string> paths;
  for (auto& c : cards) paths.push_back(std::move(c.second));
  return paths;
}

std::string connectorName(const drmModeConnector& connector) {
  const char* type = drmModeGetConnectorTypeName(connector.connector_type);
  return std::string(type != nullptr ? type : "Unknown") + "-" + std::to_string(connector.connector_type_id);
}

// The preferred mode, else the largest (then fastest).
const drmModeModeInfo* pickMode(const drmModeConnector& connector) {
  const drmModeModeInfo* best = nullptr;
  for (int i = 0; i < connector.count_modes; ++i) {
    const drmModeModeInfo& m = connector.modes[i];
    if (m.type & DRM_MODE_TYPE_PREFERRED) return &m;
    const long area = static_cast<long>(m.hdisplay) * m.vdisplay;
    if (best == nullptr || area > static_cast<long>(best->hdisplay) * best->vdisplay ||
        (area == static_cast<long>(best->hdisplay) * best->vdisplay && m.vrefresh > best->vrefresh)) {
      best = &m;
    }
  }
  return best;
}

// The CRTC already driving the connector, else the first one an encoder of it can use.
std::uint32_t pickCrtc(int fd, const drmModeRes& resources, const drmModeConnector& connector) {
  if (connector.encoder_id != 0) {
    EncoderPtr encoder(drmModeGetEncoder(fd, connector.encoder_id));
    if (encoder && encoder->crtc_id != 0) return encoder->crtc_id;
  }
  for (int i = 0; i < connector.count_encoders; ++i) {
    EncoderPtr encoder(drmModeGetEncoder(fd, connector.encoders[i]));
    if (!encoder) continue;
    for (int j = 0; j < resources.count_crtcs && j < 32; ++j) {
      if (encoder->possible_crtcs & (1u << j)) return resources.crtcs[j];
    }
  }
  return 0;
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

Result<Candidate> findOutput() {
  const std::vector<std::string> cards = listCards();
  if (cards.empty()) return fail("kms: no /dev/dri/card* (no GPU driver loaded)");
  std::vector<std::string> problems;
  for (const std::string& path : cards) {
    UniqueFd fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
    if (fd.get() < 0) {
      const int error = errno;
      std::string problem = "cannot open " + path + ": " + std::strerror(error);
      if (error == EACCES) problem += " (add the kiosk user to the 'video' group)";
      problems.push_back(problem);
      continue;
    }
    ResourcesPtr resources(drmModeGetResources(fd.get()));
    if (!resources) {
      problems.push_back(cardName(path) + " has no display outputs (a render-only GPU)");
      continue;
    }
    VersionPtr version(drmGetVersion(fd.get()));
    const std::string driver = version && version->name != nullptr ? version->name : "unknown driver";
    bool sawConnected = false;
    for (int i = 0; i < resources->count_connectors; ++i) {
      ConnectorPtr connector(drmModeGetConnector(fd.get(), resources->connectors[i]));
      if (!connector || connector->connection != DRM_MODE_CONNECTED || connector->count_modes <= 0) continue;
      sawConnected = true;
      const drmModeModeInfo* mode = pickMode(*connector);
      const std::uint32_t crtc = pickCrtc(fd.get(), *resources, *connector);
      if (mode == nullptr || crtc == 0) {
        problems.push_back(cardName(path) + " " + connectorName(*connector) + " has no usable CRTC");
        continue;
      }
      Candidate c;
      c.info = KmsOutput{path, driver, connectorName(*connector), mode->hdisplay, mode->vdisplay,
                         static_cast<int>(mode->vrefresh)};
      c.connectorId = connector->connector_id;
      c.crtcId = crtc;
      c.mode = *mode;
      c.fd = std::move(fd);
      return c;
    }
    if (!sawConnected) {
      problems.push_back(cardName(path) + " has no connected connector (is the screen plugged in and switched on?)");
    }
  }
  return fail("kms: " + join(problems, "; "));
}

struct FbData {
  int fd;
  std::uint32_t fbId;
};

void destroyFb(gbm_bo* /*bo*/, void* data) {
  auto* fb = static_cast<FbData*>(data);
  if (fb->fbId != 0) drmModeRmFB(fb->fd, fb->fbId);
  delete fb;
}

void onPageFlip(int /*fd*/, unsigned /*frame*/, unsigned /*sec*/, unsigned /*usec*/, void* data) {
  *static_cast<bool*>(data) = false;
}

// EMBOSS_KMS_SCANOUT=gbm|dumb|auto (default auto: dumb buffers when the GL is software).
std::string scanoutChoice() {
  const char* v = std::getenv("EMBOSS_KMS_SCANOUT");
  const std::string s = v != nullptr ? v : "";
  return s == "gbm" || s == "dumb" ? s : "auto";
}

// A buffer that is on screen or being flipped to: a GBM surface's (released back to it), or one of
// the display's own dumb buffers (by index).
struct ScanBuffer {
  gbm_bo* bo = nullptr;
  int dumb = -1;
  bool empty() const { return bo == nullptr && dumb < 0; }
};

class KmsDisplay final : public Display {
 public:
  explicit KmsDisplay(Candidate c)
      : info_(c.info), fd_(std::move(c.fd)), connectorId_(c.connectorId), crtcId_(c.crtcId), mode_(c.mode) {}

  ~KmsDisplay() override {
    if (session_ && session_->makeCurrent()) presenter_.reset();  // GL objects go with the context
    presenter_.reset();
    if (savedCrtc_ && savedCrtc_->mode_valid && modeSet_) {  // give the console its picture back
      drmModeSetCrtc(fd_.get(), savedCrtc_->crtc_id, savedCrtc_->buffer_id, savedCrtc_->x, savedCrtc_->y,
                     &connectorId_, 1, &savedCrtc_->mode);
    }
    if (flipPending_) waitForFlip(kFlipWaitMs);  // a flip under way ends before its buffers go
    if (!flipPending_ && !flipped_.empty()) completeFlip();
    release(flipped_);  // the fd closes after
    release(onScreen_);
    dumb_.clear();      // framebuffers and maps, before the card's fd closes
    soft_.reset();
    session_.reset();  // the EGL surface before the gbm surface under it
    surface_.reset();  // destroys the buffers, whose FbData removes their framebuffers
    gbm_.reset();
  }

  Status start(const GlPresenterSettings& settings) {
    const std::string where = cardName(info_.card) + " " + info_.connector;
    savedCrtc_.reset(drmModeGetCrtc(fd_.get(), crtcId_));
    const std::string choice = scanoutChoice();
    if (choice != "gbm") {
      // Software GL off screen (EGL surfaceless): when that is all this machine has, GBM would give
      // the same llvmpipe drawing straight into the card's memory, so the dumb buffers are taken.
      auto soft = createHeadlessDisplay(mode_.hdisplay, mode_.vdisplay, settings);
      if (soft && (choice == "dumb" || isSoftwareRenderer((*soft)->name()))) return startDumb(std::move(*soft), where);
      if (!soft && choice == "dumb") return fail("kms: " + soft.error());
    }
    gbm_.reset(gbm_create_device(fd_.get()));
    if (!gbm_) return fail("kms: gbm_create_device failed on " + cardName(info_.card) + " (" + info_.driver + ")");
    surface_.reset(gbm_surface_create(gbm_.get(), mode_.hdisplay, mode_.vdisplay, GBM_FORMAT_XRGB8888,
                                      GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING));
    if (!surface_) return fail("kms: cannot create a " + sizeText() + " scanout surface on " + where);
    if (!hasEglExtension(EGL_NO_DISPLAY, "EGL_KHR_platform_gbm") &&
        !hasEglExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_gbm")) {
      return fail("kms: this EGL cannot render to GBM (no EGL_KHR_platform_gbm; install Mesa's libegl-mesa0)");
    }
    auto session = EglSession::open(EGL_PLATFORM_GBM_KHR, gbm_.get(), "kms");
    if (!session) return fail(session.error());
    session_ = std::move(*session);
    const EGLDisplay display = session_->display();
    auto matchesGbm = [display](EGLConfig config) {
      EGLint id = 0;
      return eglGetConfigAttrib(display, config, EGL_NATIVE_VISUAL_ID, &id) && id == GBM_FORMAT_XRGB8888;
    };
    if (Status s = session_->createContext(EGL_WINDOW_BIT, matchesGbm); !s) return s;
    if (Status s = session_->createWindowSurface(surface_.get()); !s) return s;
    if (!session_->makeCurrent()) {
      return fail("kms: cannot make the GLES context current (" + eglErrorName(eglGetError()) + ")");
    }
    auto presenter = GlPresenter::create(session_->procLoader(), GlFlavor::kGles2, mode_.hdisplay,
                                         mode_.vdisplay, false, settings);
    if (!presenter) return fail("kms: " + presenter.error());
    presenter_ = std::move(*presenter);
    name_ = "kms (" + where + " " + sizeText() + "@" + std::to_string(info_.refreshHz) + ", " +
            presenter_->renderer() + ")";
    // Set the mode now with a black picture, so that a busy or refused output fails here, with a
    // message, rather than at the first frame.
    auto clearColor = reinterpret_cast<void (*)(float, float, float, float)>(eglGetProcAddress("glClearColor"));
    auto clear = reinterpret_cast<void (*)(unsigned)>(eglGetProcAddress("glClear"));
    if (clearColor != nullptr && clear != nullptr) {
      clearColor(0, 0, 0, 1);
      clear(0x00004000 /* GL_COLOR_BUFFER_BIT */);
    }
    std::string error;
    if (!showFrame(&error)) return fail(error);
    // GBM allocates a surface's buffers when a swap first needs one. Mesa's software path
    // (kms_swrast) crashes when that allocation fails because the card was just unplugged, so
    // every buffer the flips use (the one on screen, the one being flipped, the one drawn into)
    // is allocated now: two more swaps, their buffers held until both exist.
    gbm_bo* extra[2] = {nullptr, nullptr};
    for (gbm_bo*& bo : extra) {
      if (clearColor != nullptr && clear != nullptr) clear(0x00004000 /* GL_COLOR_BUFFER_BIT */);
      if (!session_->swapBuffers()) break;
      bo = gbm_surface_lock_front_buffer(surface_.get());
      if (bo == nullptr) break;
    }
    for (gbm_bo* bo : extra)
      if (bo != nullptr) gbm_surface_release_buffer(surface_.get(), bo);
    lastConnectorCheck_ = std::chrono::steady_clock::now();
    return Ok{};
  }

  std::string name() const override { return name_; }
  int width() const override { return mode_.hdisplay; }
  int height() const override { return mode_.vdisplay; }

  bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) override {
    if (lost_) return false;
    // Every ioctl on an unplugged card fails with ENODEV: notice it before any GL work, which
    // would need the card's buffers.
    if (CrtcPtr crtc(drmModeGetCrtc(fd_.get(), crtcId_)); !crtc && errno == ENODEV) {
      return loseOutput(cardName(info_.card) + " " + info_.connector + " is gone (the card was removed)");
    }
    if (!soft_ && !session_->makeCurrent()) return loseOutput("cannot make the GLES context current");
    const auto now = std::chrono::steady_clock::now();
    if (now - lastConnectorCheck_ >= kConnectorCheckInterval) {
      lastConnectorCheck_ = now;
      ConnectorPtr connector(drmModeGetConnectorCurrent(fd_.get(), connectorId_));
      if (!connector || connector->connection != DRM_MODE_CONNECTED) {
        return loseOutput(info_.connector + " was disconnected");
      }
    }
    std::string error;
    if (soft_) {
      if (!soft_->present(frame, dirty, overlay)) return false;
      const std::string where = cardName(info_.card) + " " + info_.connector;
      if (flipPending_ && !finishFlip(&error, where)) return loseOutput(error);
      const int next = onScreen_.dumb == 0 ? 1 : 0;
      if (!dumb_[next].write(soft_->screenshot())) {
        return loseOutput(where + " went away while a frame was being written into it (the card was removed)");
      }
      if (!scanout(dumb_[next].framebuffer(), ScanBuffer{nullptr, next}, &error)) return loseOutput(error);
      return true;
    }
    if (!presenter_->draw(frame, dirty, overlay)) return false;
    if (!showFrame(&error)) return loseOutput(error);
    return true;
  }

  Image screenshot() override {
    if (lost_) return Image();
    if (soft_) return soft_->screenshot();
    if (!session_->makeCurrent()) return Image();
    return presenter_->screenshot();
  }

 private:
  std::string sizeText() const { return std::to_string(mode_.hdisplay) + "x" + std::to_string(mode_.vdisplay); }

  bool loseOutput(const std::string& why) {
    if (!lost_) std::fprintf(stderr, "emboss: kms output lost: %s\n", why.c_str());
    lost_ = true;
    return false;
  }

  std::uint32_t framebufferFor(gbm_bo* bo) {
    if (auto* fb = static_cast<FbData*>(gbm_bo_get_user_data(bo))) return fb->fbId;
    const std::uint32_t w = gbm_bo_get_width(bo), h = gbm_bo_get_height(bo);
    std::uint32_t handles[4] = {gbm_bo_get_handle(bo).u32, 0, 0, 0};
    std::uint32_t pitches[4] = {gbm_bo_get_stride(bo), 0, 0, 0};
    std::uint32_t offsets[4] = {0, 0, 0, 0};
    std::uint32_t id = 0;
    if (drmModeAddFB2(fd_.get(), w, h, gbm_bo_get_format(bo), handles, pitches, offsets, &id, 0) != 0 &&
        drmModeAddFB(fd_.get(), w, h, 24, 32, pitches[0], handles[0], &id) != 0) {
      return 0;
    }
    gbm_bo_set_user_data(bo, new FbData{fd_.get(), id}, destroyFb);
    return id;
  }

  // Swaps, then puts the new front buffer on screen: drmModeSetCrtc the first time, afterwards a
  // page flip whose completion (the next vblank) it waits for.
  bool showFrame(std::string* error) {
    const std::string where = cardName(info_.card) + " " + info_.connector;
    if (!session_->swapBuffers()) {
      *error = "kms: eglSwapBuffers failed on " + where + " (" + eglErrorName(eglGetError()) + ")";
      return false;
    }
    gbm_bo* bo = gbm_surface_lock_front_buffer(surface_.get());
    if (bo == nullptr) {
      *error = "kms: no front buffer from GBM on " + where;
      return false;
    }
    const std::uint32_t fb = framebufferFor(bo);
    if (fb == 0) {
      gbm_surface_release_buffer(surface_.get(), bo);
      *error = "kms: cannot make a framebuffer for scanout on " + where + ": " + std::strerror(errno);
      return false;
    }
    return scanout(fb, ScanBuffer{bo, -1}, error);
  }

  // Puts framebuffer `fb` (of buffer `next`) on screen: drmModeSetCrtc the first time, afterwards a
  // page flip whose completion (the next vblank) it waits for.
  bool scanout(std::uint32_t fb, ScanBuffer next, std::string* error) {
    const std::string where = cardName(info_.card) + " " + info_.connector;
    if (!modeSet_) {
      if (drmModeSetCrtc(fd_.get(), crtcId_, fb, 0, 0, &connectorId_, 1, &mode_) != 0) {
        const int e = errno;
        release(next);
        *error = "kms: cannot set " + sizeText() + " on " + where + ": " + std::strerror(e);
        if (e == EACCES || e == EPERM || e == EBUSY) {
          *error += " (another program -- X, Wayland, a second kiosk -- owns the screen; stop it, or use x11)";
        }
        return false;
      }
      modeSet_ = true;
    } else {
      // The previous flip first: a second one while it is pending would be refused (EBUSY).
      if (flipPending_ && !finishFlip(error, where)) {
        release(next);
        return false;
      }
      // The event's data is a member, not a local: a flip that completes after a wait ran out is
      // handled by a later wait, and must find live memory.
      if (drmModePageFlip(fd_.get(), crtcId_, fb, DRM_MODE_PAGE_FLIP_EVENT, &flipPending_) != 0) {
        const int e = errno;
        release(next);
        *error = "kms: page flip refused on " + where + ": " + std::strerror(e);
        return false;
      }
      flipPending_ = true;
      flipped_ = next;
      flipStart_ = std::chrono::steady_clock::now();
      // Wait for this flip within one wait; if it is slower (or a signal came), it is finished
      // before the next frame, and the frame counts as shown.
      if (!waitForFlip(kFlipWaitMs)) return loseFlip(error, where);
      if (flipPending_) return true;
      completeFlip();
      return true;
    }
    release(onScreen_);
    onScreen_ = next;
    return true;
  }

  void release(ScanBuffer& b) {
    if (b.bo != nullptr) gbm_surface_release_buffer(surface_.get(), b.bo);
    b = ScanBuffer{};
  }
  void release(ScanBuffer&& b) { release(b); }

  // The dumb-buffer path (kms_scanout.h): `soft` draws, two dumb buffers take turns on screen.
  Status startDumb(std::unique_ptr<Display> soft, const std::string& where) {
    for (int i = 0; i < 2; ++i) {
      auto b = DumbBuffer::create(fd_.get(), mode_.hdisplay, mode_.vdisplay, where);
      if (!b) return fail(b.error());
      dumb_.push_back(std::move(*b));
    }
    soft_ = std::move(soft);
    std::string renderer = soft_->name();  // "headless (EGL surfaceless, llvmpipe (...))"
    if (const auto comma = renderer.find(", "); comma != std::string::npos) renderer = renderer.substr(comma + 2);
    if (!renderer.empty() && renderer.back() == ')') renderer.pop_back();
    name_ = "kms (" + where + " " + sizeText() + "@" + std::to_string(info_.refreshHz) + ", " + renderer +
            ", dumb buffers)";
    // The mode now, with a black picture: a busy or refused output fails here, with a message.
    std::string error;
    if (!scanout(dumb_[0].framebuffer(), ScanBuffer{nullptr, 0}, &error)) return fail(error);
    lastConnectorCheck_ = std::chrono::steady_clock::now();
    return Ok{};
  }

  // Waits up to ms for the pending flip's event; false when the device reports an error or hang-up.
  // Returns early (true, still pending) on a signal.
  bool waitForFlip(int ms) {
    drmEventContext events{};
    events.version = 2;
    events.page_flip_handler = onPageFlip;
    if (!flipPending_) return true;
    pollfd p{fd_.get(), POLLIN, 0};
    const int ready = ::poll(&p, 1, ms);
    if (ready < 0) return errno == EINTR;
    if (ready == 0) return true;
    if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) return false;
    drmHandleEvent(fd_.get(), &events);
    return true;
  }

  // The flip under way becomes the buffer on screen.
  void completeFlip() {
    release(onScreen_);
    onScreen_ = flipped_;
    flipped_ = ScanBuffer{};
  }

  // Waits for the flip still pending from the last frame: done, or the output is gone.
  bool finishFlip(std::string* error, const std::string& where) {
    while (flipPending_) {
      if (!waitForFlip(kFlipWaitMs)) return loseFlip(error, where);
      if (flipPending_ && std::chrono::steady_clock::now() - flipStart_ > std::chrono::milliseconds(kFlipGoneMs)) {
        *error = "kms: no vblank from " + where + " for " + std::to_string(kFlipGoneMs / 1000) +
                 " s (display off or unplugged?)";
        return false;
      }
    }
    completeFlip();
    return true;
  }

  bool loseFlip(std::string* error, const std::string& where) {
    *error = "kms: the display " + where + " reported an error while flipping (unplugged?)";
    return false;
  }

  KmsOutput info_;
  UniqueFd fd_;  // declared first: closed last, after every GBM and EGL object on it
  std::uint32_t connectorId_, crtcId_;
  drmModeModeInfo mode_;
  CrtcPtr savedCrtc_;
  GbmDevicePtr gbm_;
  GbmSurfacePtr surface_;
  std::unique_ptr<EglSession> session_;
  std::unique_ptr<GlPresenter> presenter_;
  std::unique_ptr<Display> soft_;  // the dumb-buffer path's off-screen drawing (else null)
  std::vector<DumbBuffer> dumb_;   // its two scanout buffers
  ScanBuffer onScreen_;            // the buffer being scanned out (a GBM one is locked)
  ScanBuffer flipped_;             // the buffer of the flip under way
  bool flipPending_ = false;    // the page flip event's data: cleared by onPageFlip
  std::chrono::steady_clock::time_point flipStart_;
  bool modeSet_ = false;
  bool lost_ = false;
  std::chrono::steady_clock::time_point lastConnectorCheck_;
  std::string name_;
};

}  // namespace

Result<KmsOutput> probeKmsOutput() {
  auto found = findOutput();
  if (!found) return fail(found.error());
  return found->info;
}

Result<std::unique_ptr<Display>> createKmsDisplay(const GlPresenterSettings& settings) {
  auto found = findOutput();
  if (!found) return fail(found.error());
  auto display = std::make_unique<KmsDisplay>(std::move(*found));
  if (Status s = display->start(settings); !s) return fail(s.error());
  return std::unique_ptr<Display>(std::move(display));
}

Result<std::unique_ptr<Display>> waitForKmsDisplay(std::chrono::milliseconds timeout,
                                                   const GlPresenterSettings& settings,
                                                   const std::function<bool(const std::string&)>& keepWaiting) {
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + timeout;
  for (;;) {
    auto display = createKmsDisplay(settings);
    if (display) return display;
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      const auto waited = std::chrono::duration_cast<std::chrono::seconds>(now - start).count();
      return fail(display.error() + " (waited " + std::to_string(waited) + " s for a display)");
    }
    if (keepWaiting && !keepWaiting(display.error())) return fail(display.error() + " (gave up waiting)");
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(std::chrono::seconds(1), deadline - now));
  }
}

}  // namespace emboss

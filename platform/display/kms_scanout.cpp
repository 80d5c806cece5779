// Dumb-buffer scanout and the fault guard around writes into a card's memory (kms_scanout.h).
#include "display/kms_scanout.h"

#include <drm_fourcc.h>
#include <sys/mman.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <csignal>
#include <cstring>
#include <mutex>
#include <utility>

namespace emboss {

namespace {

thread_local sigjmp_buf* tGuard = nullptr;
struct sigaction gPreviousSegv {};
struct sigaction gPreviousBus {};

void onFault(int sig, siginfo_t* /*info*/, void* /*context*/) {
  if (sigjmp_buf* env = tGuard) {
    tGuard = nullptr;
    siglongjmp(*env, sig);
  }
  // Not a guarded write: the disposition from before, and the faulting instruction runs again under
  // it (by default the process ends with a core dump, as it would have without this handler).
  sigaction(sig, sig == SIGBUS ? &gPreviousBus : &gPreviousSegv, nullptr);
}

void installFaultHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_sigaction = onFault;
    sa.sa_flags = SA_SIGINFO | SA_NODEFER;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGSEGV, &sa, &gPreviousSegv);
    sigaction(SIGBUS, &sa, &gPreviousBus);
  });
}

struct WriteJob {
  const Image* frame;
  std::uint8_t* map;
  std::uint32_t pitch;
  int rows, columns;
};

void writeRows(void* context) {
  const WriteJob& job = *static_cast<const WriteJob*>(context);
  for (int y = 0; y < job.rows; ++y) {
    const std::uint8_t* src = job.frame->pixel(0, y);
    auto* dst = reinterpret_cast<std::uint32_t*>(job.map + static_cast<std::size_t>(y) * job.pitch);
    for (int x = 0; x < job.columns; ++x, src += 4)
      dst[x] = 0xFF000000u | (std::uint32_t(src[0]) << 16) | (std::uint32_t(src[1]) << 8) | src[2];
  }
}

}  // namespace

bool runGuarded(void (*body)(void*), void* context) {
  installFaultHandlers();
  sigjmp_buf env;
  if (sigsetjmp(env, 1) != 0) return false;  // a fault in the body: tGuard was cleared by the handler
  tGuard = &env;
  body(context);
  tGuard = nullptr;
  return true;
}

bool isSoftwareRenderer(const std::string& renderer) {
  return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos ||
         renderer.find("swrast") != std::string::npos;
}

Result<DumbBuffer> DumbBuffer::create(int fd, int width, int height, const std::string& where) {
  DumbBuffer b;
  b.fd_ = fd;
  b.width_ = width;
  b.height_ = height;
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  std::uint64_t bytes = 0;
  if (drmModeCreateDumbBuffer(fd, width, height, 32, 0, &b.handle_, &b.pitch_, &bytes) != 0) {
    return fail("kms: cannot create a " + size + " dumb buffer on " + where + ": " + std::strerror(errno));
  }
  b.size_ = bytes;
  std::uint64_t offset = 0;
  if (drmModeMapDumbBuffer(fd, b.handle_, &offset) != 0) {
    return fail("kms: cannot map a dumb buffer on " + where + ": " + std::strerror(errno));
  }
  void* map = mmap(nullptr, b.size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd, static_cast<off_t>(offset));
  if (map == MAP_FAILED) return fail("kms: cannot map a dumb buffer on " + where + ": " + std::strerror(errno));
  b.map_ = static_cast<std::uint8_t*>(map);
  std::uint32_t handles[4] = {b.handle_, 0, 0, 0};
  std::uint32_t pitches[4] = {b.pitch_, 0, 0, 0};
  std::uint32_t offsets[4] = {0, 0, 0, 0};
  if (drmModeAddFB2(fd, width, height, DRM_FORMAT_XRGB8888, handles, pitches, offsets, &b.fb_, 0) != 0 &&
      drmModeAddFB(fd, width, height, 24, 32, b.pitch_, b.handle_, &b.fb_) != 0) {
    return fail("kms: cannot make a framebuffer for scanout on " + where + ": " + std::strerror(errno));
  }
  // Black, so that a first SetCrtc before any frame shows nothing stale.
  Image black;
  if (!b.write(black)) return fail("kms: the dumb buffer on " + where + " cannot be written (the card is gone?)");
  return b;
}

DumbBuffer::DumbBuffer(DumbBuffer&& other) noexcept { *this = std::move(other); }

DumbBuffer& DumbBuffer::operator=(DumbBuffer&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    handle_ = std::exchange(other.handle_, 0);
    fb_ = std::exchange(other.fb_, 0);
    pitch_ = std::exchange(other.pitch_, 0);
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
    map_ = std::exchange(other.map_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

DumbBuffer::~DumbBuffer() { release(); }

void DumbBuffer::release() {
  // On a removed card these fail with ENODEV; the kernel frees the buffer with the last reference.
  if (fb_ != 0) drmModeRmFB(fd_, fb_);
  if (map_ != nullptr) munmap(map_, size_);
  if (handle_ != 0) drmModeDestroyDumbBuffer(fd_, handle_);
  fb_ = handle_ = 0;
  map_ = nullptr;
}

bool DumbBuffer::write(const Image& frame) {
  if (map_ == nullptr) return false;
  if (frame.width == 0) {  // clear to black
    struct Clear {
      std::uint8_t* map;
      std::size_t size;
    } clear{map_, size_};
    return runGuarded([](void* c) { std::memset(static_cast<Clear*>(c)->map, 0, static_cast<Clear*>(c)->size); }, &clear);
  }
  WriteJob job{&frame, map_, pitch_, std::min(frame.height, height_), std::min(frame.width, width_)};
  return runGuarded(writeRows, &job);
}

}  // namespace emboss

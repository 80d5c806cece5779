// Scanout from main memory for the KMS display when its GL is software (Mesa's llvmpipe on a card
// without a GPU: a VM's bochs or virtio card, a board whose GPU driver is missing). The frame is
// drawn off screen in ordinary memory and then copied into a dumb buffer of the card's own, under
// a guard: when the card is removed in the middle of that copy (the driver unbound, the adapter
// unplugged) its mapping stops being memory, and the copy ends with false instead of the kiosk
// ending with SIGSEGV or SIGBUS. Drawn by Mesa straight into the card's buffer (the GBM path), the
// same removal kills the process in one of Mesa's threads, where nothing can catch it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "render/image.h"
#include "util/result.h"

namespace emboss {

// A dumb buffer of the card, mapped, with a framebuffer for scanout (XRGB8888).
class DumbBuffer {
 public:
  // Fails with a message ("kms: cannot create a 1280x800 dumb buffer on card0: ...").
  static Result<DumbBuffer> create(int fd, int width, int height, const std::string& where);
  DumbBuffer() = default;
  DumbBuffer(DumbBuffer&& other) noexcept;
  DumbBuffer& operator=(DumbBuffer&& other) noexcept;
  DumbBuffer(const DumbBuffer&) = delete;
  DumbBuffer& operator=(const DumbBuffer&) = delete;
  ~DumbBuffer();

  std::uint32_t framebuffer() const { return fb_; }
  // Writes `frame` (RGBA, the buffer's size or smaller) as XRGB8888; false when the mapping faulted
  // (the card is gone). Rows beyond the frame are left as they are.
  bool write(const Image& frame);

 private:
  void release();

  int fd_ = -1;  // not owned: the display's card
  std::uint32_t handle_ = 0, fb_ = 0, pitch_ = 0;
  int width_ = 0, height_ = 0;
  std::uint8_t* map_ = nullptr;
  std::size_t size_ = 0;
};

// True when `renderer` (GL_RENDERER) is Mesa's software rasteriser.
bool isSoftwareRenderer(const std::string& renderer);

// Runs `body(context)` with SIGSEGV and SIGBUS on this thread caught: returns false when one came
// (the body was cut short), true when the body ran to its end. Faults on other threads, and
// faults while no guard is up, keep their default (the process ends with a core dump).
bool runGuarded(void (*body)(void*), void* context);

}  // namespace emboss

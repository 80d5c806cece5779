// The evdev pen: a live tablet through the kernel's input layer (libevdev), grabbed for the kiosk alone.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "devices/pen.h"
#include "input/evdev_pen_state.h"
#include "unique_fd.h"
#include "util/result.h"

struct libevdev;

namespace emboss {

// What an event node can report (name, axes, keys), read without grabbing it.
Result<EvdevCaps> readEvdevCaps(const std::filesystem::path& node);

// The /dev/input/event* nodes, in numeric order.
std::vector<std::filesystem::path> listEvdevNodes();

class EvdevPen final : public PenSource {
 public:
  // Opens node, checks it is a pen tablet (evdevUnusableReason), takes the axis ranges from the
  // device and, with grab, takes it exclusively (EVIOCGRAB) so the desktop cursor does not follow.
  static Result<std::unique_ptr<EvdevPen>> open(const std::filesystem::path& node, bool grab = true);
  ~EvdevPen() override;

  std::string name() const override { return name_; }
  // Reads what is pending (never blocks). Returns false once the device is gone (ENODEV, unplugged).
  bool poll(std::vector<PenSample>& out) override;
  int fd() const override { return fd_.get(); }

 private:
  struct EvdevFree {
    void operator()(libevdev* d) const;
  };
  EvdevPen(UniqueFd fd, std::unique_ptr<libevdev, EvdevFree> dev, const EvdevCaps& caps, std::string path);

  UniqueFd fd_;                                 // declared first: closed after dev_ is freed
  std::unique_ptr<libevdev, EvdevFree> dev_;
  EvdevPenState state_;
  std::string name_;
  std::string path_;
  bool gone_ = false;
};

}  // namespace emboss

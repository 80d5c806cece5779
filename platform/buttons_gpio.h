// The GPIO buttons: the kiosk's hardware buttons on GPIO lines, read as edge events through libgpiod 1.6.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/button_config.h"
#include "devices/button_gestures.h"
#include "devices/buttons.h"
#include "pen_fd.h"
#include "util/result.h"

struct gpiod_chip;
struct gpiod_line;

namespace emboss {

// Requests every configured line for both edges (active-low and bias as configured, consumer
// "emboss") and returns the source. Fails with a message a person can act on: no /dev/gpiochip* at
// all ("the keyboard stands in"), an unknown chip, a line the chip does not have, a line in use, no
// permission. The caller falls back to the keyboard and may try again later.
Result<std::unique_ptr<ButtonSource>> openGpioButtons(const ButtonConfig& config);

// The /dev/gpiochip* nodes, in numeric order.
std::vector<std::string> listGpioChips();

class GpioButtons final : public ButtonSource {
 public:
  ~GpioButtons() override;
  GpioButtons(const GpioButtons&) = delete;
  GpioButtons& operator=(const GpioButtons&) = delete;

  std::string name() const override { return name_; }
  // Reads the pending edges (never blocks), feeds them through the debounce and gesture logic and
  // appends what became events by now. False once a chip is gone (a USB GPIO adapter unplugged:
  // the line descriptors report POLLHUP/POLLERR); the caller then drops the source and calls
  // openGpioButtons again later.
  // Call it on every main-loop turn (not only when fd() is readable): long presses and debounce
  // deadlines fall between edges.
  bool poll(std::vector<ButtonEvent>& out) override;
  // An epoll descriptor that is readable when any line has an edge pending (for waking the main
  // loop; poll() itself looks at the line descriptors).
  int fd() const override { return epoll_.get(); }

 private:
  struct ChipClose {
    void operator()(gpiod_chip* chip) const;
  };
  struct Line {
    gpiod_chip* chip = nullptr;  // owned by chips_
    gpiod_line* line = nullptr;  // owned by its chip (released when the chip closes)
    std::string label;           // "gpiochip0 line 17 (next_tool)"
    int fd = -1;                 // the line's event descriptor, owned by libgpiod
  };
  friend Result<std::unique_ptr<ButtonSource>> openGpioButtons(const ButtonConfig& config);
  explicit GpioButtons(const ButtonConfig& config);

  std::vector<std::unique_ptr<gpiod_chip, ChipClose>> chips_;
  std::vector<Line> lines_;
  std::vector<bool> levels_;  // the last level fed to gestures_, per line
  UniqueFd epoll_;
  ButtonGestures gestures_;
  std::string name_;
  bool gone_ = false;
};

}  // namespace emboss

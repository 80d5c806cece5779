// The GPIO buttons: the kiosk's hardware buttons on GPIO lines, read through libgpiod 1.6 as edge
// events, or as levels on a chip that can be unplugged (ButtonConfig::read).
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "devices/button_config.h"
#include "devices/button_gestures.h"
#include "devices/buttons.h"
#include "unique_fd.h"
#include "util/result.h"

struct gpiod_chip;
struct gpiod_line;

namespace emboss {

// Requests every configured line (active-low and bias as configured, consumer "emboss"), for both
// edges or as an input whose level is read, as ButtonConfig::read says, and returns the source.
// Fails with a message a person can act on: no /dev/gpiochip* at all ("the keyboard stands in"),
// an unknown chip, a line the chip does not have, a line in use, no permission. The caller falls back to the keyboard and may try again later.
Result<std::unique_ptr<ButtonSource>> openGpioButtons(const ButtonConfig& config);

// The /dev/gpiochip* nodes, in numeric order.
std::vector<std::string> listGpioChips();

// Whether the chip ("gpiochip3") sits on a bus whose devices come and go: one of its parents in
// sysfs belongs to the usb or hid subsystem. `sysRoot` is for tests ("/sys" otherwise).
bool gpioChipIsRemovable(const std::string& chipName, const std::string& sysRoot = "/sys");

class GpioButtons final : public ButtonSource {
 public:
  ~GpioButtons() override;
  GpioButtons(const GpioButtons&) = delete;
  GpioButtons& operator=(const GpioButtons&) = delete;

  std::string name() const override { return name_; }
  // Reads the pending edges, and the changes of the lines read as levels (a thread of its own reads
  // those every 20 ms, so a short press is not lost while the main loop is busy), feeds them
  // through the debounce and gesture logic and appends what became events by now. False once a chip is gone (a USB GPIO adapter unplugged: the line descriptors report
  // POLLHUP/POLLERR, a level read fails with ENODEV); the caller then drops the source and calls
  // openGpioButtons again later.
  // Call it on every main-loop turn (not only when fd() is readable): long presses and debounce
  // deadlines fall between edges.
  bool poll(std::vector<ButtonEvent>& out) override;
  // An epoll descriptor that is readable when any line read as edges has an edge pending (for
  // waking the main loop; poll() itself looks at the line descriptors).
  int fd() const override { return epoll_.get(); }
  // The gestures' next deadline (a debounce settling, a long press, a chord's window), and the
  // reader thread's 20 ms while any line is read as levels (its edges do not wake the epoll).
  double pollWithin() const override;

 private:
  struct ChipClose {
    void operator()(gpiod_chip* chip) const;
  };
  struct Line {
    gpiod_chip* chip = nullptr;  // owned by chips_
    gpiod_line* line = nullptr;  // owned by its chip (released when the chip closes)
    std::string label;           // "gpiochip0 line 17 (next_tool)"
    int fd = -1;                 // the line's event descriptor, owned by libgpiod; -1 when read as levels
    bool levels = false;         // requested as an input whose level the reader thread reads (no interrupt)
  };
  struct Edge {
    double t;  // CLOCK_MONOTONIC seconds
    size_t line;
    bool pressed;
  };
  friend Result<std::unique_ptr<ButtonSource>> openGpioButtons(const ButtonConfig& config);
  explicit GpioButtons(const ButtonConfig& config);
  // The reader thread of the lines read as levels: every 20 ms, a change against `last` (the levels
  // as opened, then as last read) is an edge at the time of the read; a failed read marks the
  // source lost. It touches lines_ (read only) and, under levelMutex_, what it hands over.
  void readLevels(std::vector<bool> last);

  std::vector<std::unique_ptr<gpiod_chip, ChipClose>> chips_;
  std::vector<Line> lines_;
  std::vector<bool> levels_;  // the last level fed to gestures_, per line
  UniqueFd epoll_;
  ButtonGestures gestures_;
  std::string name_;
  bool gone_ = false;

  // The lines read as levels: read on reader_ only (from its start to its join), their edges handed
  // over in levelEdges_.
  std::thread reader_;
  std::mutex levelMutex_;
  std::condition_variable stopReader_;
  bool stopping_ = false;               // guarded by levelMutex_
  std::vector<Edge> levelEdges_;        // guarded by levelMutex_
  std::string levelsLost_;              // guarded by levelMutex_: why a read failed, once one did
};

}  // namespace emboss

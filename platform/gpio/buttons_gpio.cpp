// The GPIO buttons through libgpiod 1.6: one request per line, for edge events (gathered behind one
// epoll fd) or, on a chip that can be unplugged, as an input whose level is read every 20 ms.
#include "gpio/buttons_gpio.h"
#include "platform_util.h"

#include <gpiod.h>
#include <poll.h>
#include <sys/epoll.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

namespace emboss {

namespace {

bool allDigits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Opens a chip named as gpiodetect shows it: "gpiochip0", "0", "/dev/gpiochip0" or its label.
gpiod_chip* openChip(const std::string& name) {
  if (!name.empty() && name[0] == '/') return gpiod_chip_open(name.c_str());
  if (allDigits(name)) return gpiod_chip_open_by_number(static_cast<unsigned>(std::stoul(name)));
  if (name.rfind("gpiochip", 0) == 0) return gpiod_chip_open_by_name(name.c_str());
  return gpiod_chip_open_by_label(name.c_str());
}

std::string chipsHere() {
  std::string s;
  for (const auto& path : listGpioChips()) {
    std::string entry = std::filesystem::path(path).filename().string();
    if (gpiod_chip* c = gpiod_chip_open(path.c_str())) {
      entry += std::string(" [") + gpiod_chip_label(c) + ", " + std::to_string(gpiod_chip_num_lines(c)) + " lines]";
      gpiod_chip_close(c);
    }
    s += (s.empty() ? "" : ", ") + entry;
  }
  return s;
}

int biasFlags(LineBias b) {
  switch (b) {
    case LineBias::AsIs: return 0;
    case LineBias::Disable: return GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE;
    case LineBias::PullUp: return GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP;
    case LineBias::PullDown: return GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN;
  }
  return 0;
}

constexpr const char* kConsumer = "emboss";
constexpr double kClockSkewS = 5.0;  // an edge stamp this far from CLOCK_MONOTONIC is on another clock
// Lines read as levels are read this often. A CP2112's own driver reads its pins every 40 ms to make
// edge interrupts; a button press lasts 100 ms or more.
constexpr double kLevelPeriodS = 0.020;

}  // namespace

std::vector<std::string> listGpioChips() {
  std::vector<std::pair<int, std::string>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("gpiochip", 0) == 0 && allDigits(name.substr(8))) found.emplace_back(std::stoi(name.substr(8)), e.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& [n, path] : found) out.push_back(std::move(path));
  return out;
}

bool gpioChipIsRemovable(const std::string& chipName, const std::string& sysRoot) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path dev = fs::canonical(fs::path(sysRoot) / "bus/gpio/devices" / chipName, ec);
  if (ec) return false;
  const fs::path devices = fs::path(sysRoot) / "devices";
  for (fs::path p = dev.parent_path(); p.has_relative_path() && p != devices && p != p.parent_path(); p = p.parent_path()) {
    const fs::path subsystem = fs::read_symlink(p / "subsystem", ec);
    if (ec) continue;
    const std::string name = subsystem.filename().string();
    if (name == "usb" || name == "hid") return true;
  }
  return false;
}

void GpioButtons::ChipClose::operator()(gpiod_chip* chip) const {
  if (chip) gpiod_chip_close(chip);  // releases the chip's requested lines and their event fds
}

GpioButtons::GpioButtons(const ButtonConfig& config) : gestures_(config) {}
GpioButtons::~GpioButtons() {
  if (reader_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(levelMutex_);
      stopping_ = true;
    }
    stopReader_.notify_all();
    reader_.join();  // before chips_ close the lines it reads
  }
}

void GpioButtons::readLevels(std::vector<bool> last) {
  std::unique_lock<std::mutex> lock(levelMutex_);
  while (!stopReader_.wait_for(lock, std::chrono::duration<double>(kLevelPeriodS), [this] { return stopping_; })) {
    lock.unlock();
    std::vector<Edge> edges;
    std::string lost;
    for (size_t i = 0; i < lines_.size() && lost.empty(); ++i) {
      if (!lines_[i].levels) continue;
      errno = 0;
      const int value = gpiod_line_get_value(lines_[i].line);
      const double t = monotonicSeconds();
      if (value < 0) {
        if (errno != EINTR && errno != EAGAIN) lost = lines_[i].label + " is gone (" + std::strerror(errno) + ")";
        continue;
      }
      if ((value == 1) != last[i]) {
        last[i] = value == 1;
        edges.push_back({t, i, last[i]});
      }
    }
    lock.lock();
    levelEdges_.insert(levelEdges_.end(), edges.begin(), edges.end());
    if (!lost.empty()) {
      levelsLost_ = lost;
      return;
    }
  }
}

Result<std::unique_ptr<ButtonSource>> openGpioButtons(const ButtonConfig& config) {
  if (listGpioChips().empty()) return fail("gpio: no /dev/gpiochip* (no GPIO on this machine); the keyboard stands in");
  if (config.buttons.empty()) return fail("gpio: " + config.source + " configures no buttons; the keyboard stands in");

  std::unique_ptr<GpioButtons> self(new GpioButtons(config));
  self->epoll_ = UniqueFd(epoll_create1(EPOLL_CLOEXEC));
  if (!self->epoll_.valid()) return fail(std::string("gpio: epoll_create1 failed: ") + std::strerror(errno));

  std::map<std::string, gpiod_chip*> byName;
  std::map<gpiod_chip*, bool> levelsOn;  // per chip: read as levels
  const double now = monotonicSeconds();
  std::set<std::string> chipNames;
  for (size_t i = 0; i < config.buttons.size(); ++i) {
    const ButtonLineConfig& b = config.buttons[i];
    const std::string label = b.chip + " line " + std::to_string(b.line) + " (" + actionName(b.action) + ")";
    gpiod_chip* chip = nullptr;
    if (auto it = byName.find(b.chip); it != byName.end()) {
      chip = it->second;
    } else {
      errno = 0;
      chip = openChip(b.chip);
      if (!chip) {
        const int err = errno;
        if (err == EACCES || err == EPERM)
          return fail("gpio: " + b.chip + ": permission denied; install systemd/99-emboss-kiosk.rules and add the kiosk user to group 'emboss' (docs/hardware.md)");
        return fail("gpio: no chip '" + b.chip + "' (" + std::strerror(err) + "); chips here: " + chipsHere() + "; fix \"chip\" in " + config.source);
      }
      self->chips_.emplace_back(chip);
      byName[b.chip] = chip;
      // Linux 6.1 frees an unplugged chip's interrupts under the handlers of lines still requested
      // for edges ("leaking at least 'emboss'"), which can fault later: on a chip that can be
      // unplugged the lines hold no interrupt, and their levels are read instead.
      const bool removable = gpioChipIsRemovable(gpiod_chip_name(chip));
      const bool levels = config.read == GpioRead::Levels || (config.read == GpioRead::Auto && removable);
      levelsOn[chip] = levels;
      chipNames.insert(b.chip + " [" + gpiod_chip_label(chip) + (levels ? ", levels every 20 ms" : ", edge events") +
                       (removable ? ", removable" : "") + "]");
    }
    const unsigned lines = gpiod_chip_num_lines(chip);
    if (b.line >= lines)
      return fail("gpio: " + b.chip + " has lines 0.." + std::to_string(lines - 1) + "; " + label + " does not exist; fix " + config.source);
    gpiod_line* line = gpiod_chip_get_line(chip, b.line);
    if (!line) return fail("gpio: cannot get " + label + ": " + std::strerror(errno));

    const int polarity = b.activeLow ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
    const bool levels = levelsOn[chip];
    const auto request = [&](int flags) {
      return levels ? gpiod_line_request_input_flags(line, kConsumer, flags) : gpiod_line_request_both_edges_events_flags(line, kConsumer, flags);
    };
    int rc = request(polarity | biasFlags(b.bias));
    if (rc < 0 && errno == EINVAL && biasFlags(b.bias) != 0) {
      // Kernels before 5.5 (and some GPIO drivers) cannot set the bias: carry on, the wiring needs resistors.
      logOnce("gpio: " + b.chip + " cannot set bias " + lineBiasName(b.bias) + "; fit an external pull resistor on " + label);
      rc = request(polarity);
    }
    if (rc < 0) {
      const int err = errno;
      if (err == EBUSY) {
        gpiod_line_update(line);
        const char* user = gpiod_line_consumer(line);
        return fail("gpio: " + label + " is in use by '" + (user ? user : "another program") +
                    "'; free it (a device-tree overlay such as gpio-key, or another program) or pick another line");
      }
      if (err == EACCES || err == EPERM)
        return fail("gpio: " + label + ": permission denied; install systemd/99-emboss-kiosk.rules (docs/hardware.md)");
      return fail("gpio: cannot request " + label + (levels ? " as an input: " : " for edge events: ") + std::strerror(err));
    }
    GpioButtons::Line l;
    l.chip = chip;
    l.line = line;
    l.label = label;
    l.levels = levels;
    if (!levels) {
      l.fd = gpiod_line_event_get_fd(line);
      epoll_event ev{};
      ev.events = EPOLLIN;
      ev.data.u64 = i;
      if (l.fd < 0 || epoll_ctl(self->epoll_.get(), EPOLL_CTL_ADD, l.fd, &ev) < 0)
        return fail("gpio: cannot watch " + label + ": " + std::strerror(errno));
    }
    const int value = gpiod_line_get_value(line);
    const bool pressed = value == 1;
    if (pressed) logOnce("gpio: " + label + " reads pressed at start (held, stuck, or active_low/bias wrong); ignored until released");
    self->gestures_.reset(i, pressed, now);
    self->lines_.push_back(l);
    self->levels_.push_back(pressed);
  }
  std::string chips;
  for (const auto& c : chipNames) chips += (chips.empty() ? "" : ", ") + c;
  self->name_ = "gpio: " + std::to_string(config.buttons.size()) + " buttons on " + chips;
  if (std::any_of(self->lines_.begin(), self->lines_.end(), [](const GpioButtons::Line& l) { return l.levels; }))
    self->reader_ = std::thread([p = self.get(), opened = self->levels_]() mutable { p->readLevels(std::move(opened)); });
  return std::unique_ptr<ButtonSource>(std::move(self));
}

bool GpioButtons::poll(std::vector<ButtonEvent>& out) {
  if (gone_) return false;
  std::vector<Edge> edges;
  const double now = monotonicSeconds();
  // The line descriptors themselves, not the epoll: when the chip goes away (a USB GPIO adapter
  // unplugged) Linux 6.1 marks them POLLHUP|POLLERR without waking an epoll that watches them.
  // (A line read as levels has fd -1, which poll() skips.)
  std::vector<pollfd> fds(lines_.size());
  for (size_t i = 0; i < lines_.size(); ++i) fds[i] = {lines_[i].fd, POLLIN, 0};
  if (::poll(fds.data(), fds.size(), 0) < 0) return true;  // EINTR: try again on the next turn
  // The edges the reader thread saw on the lines read as levels.
  {
    std::lock_guard<std::mutex> lock(levelMutex_);
    edges.swap(levelEdges_);
    if (!levelsLost_.empty()) {
      logOnce("gpio: " + levelsLost_ + "; buttons off until the GPIO device is back");
      gone_ = true;
      return false;
    }
  }
  for (size_t i = 0; i < lines_.size(); ++i) {
    Line& l = lines_[i];
    if (fds[i].revents & (POLLHUP | POLLERR | POLLNVAL)) {
      logOnce("gpio: " + l.label + " is gone (the GPIO device was removed); buttons off until it is back");
      gone_ = true;
      return false;
    }
    if (!(fds[i].revents & POLLIN)) continue;
    // Bounded: a line bouncing faster than we read cannot keep us here.
    for (int round = 0; round < 8; ++round) {
      if (round > 0) {
        pollfd p{l.fd, POLLIN, 0};
        if (::poll(&p, 1, 0) <= 0 || !(p.revents & POLLIN)) break;
      }
      gpiod_line_event events[16];
      const int got = gpiod_line_event_read_multiple(l.line, events, 16);
      if (got < 0) {
        const int err = errno;
        if (err == EAGAIN || err == EINTR) break;
        logOnce("gpio: " + l.label + " is gone (" + std::strerror(err) + "); buttons off until the GPIO device is back");
        gone_ = true;
        return false;
      }
      for (int e = 0; e < got; ++e) {
        double t = static_cast<double>(events[e].ts.tv_sec) + events[e].ts.tv_nsec * 1e-9;
        if (std::fabs(t - now) > kClockSkewS) {
          logOnce("gpio: edge time stamps are not CLOCK_MONOTONIC (kernel before 5.7?); using the read time");
          t = now;
        }
        edges.push_back({t, i, events[e].event_type == GPIOD_LINE_EVENT_RISING_EDGE});
      }
    }
  }
  std::stable_sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.t < b.t; });
  for (const Edge& e : edges) {
    gestures_.edge(e.line, e.pressed, e.t, out);
    levels_[e.line] = e.pressed;
  }
  // An edge lost in the kernel's queue would leave a level wrong forever: check the lines that moved.
  for (size_t i = 0; i < lines_.size(); ++i) {
    if (!(fds[i].revents & POLLIN)) continue;
    const int value = gpiod_line_get_value(lines_[i].line);
    if (value >= 0 && (value == 1) != levels_[i]) {
      levels_[i] = value == 1;
      gestures_.edge(i, levels_[i], now, out);
    }
  }
  gestures_.advance(monotonicSeconds(), out);
  return true;
}

double GpioButtons::pollWithin() const {
  if (gone_) return 0.0;
  double within = std::numeric_limits<double>::infinity();
  if (std::any_of(lines_.begin(), lines_.end(), [](const Line& l) { return l.levels; })) within = kLevelPeriodS;
  if (const std::optional<double> d = gestures_.nextDeadline()) within = std::min(within, std::max(0.0, *d - monotonicSeconds()));
  return within;
}

}  // namespace emboss

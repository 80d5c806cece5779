// Shared helpers of the HIL test programs: checks that report and count, waiting, sysfs, uinput and uhid.
// Header-only; every program is one translation unit built by tests/hil/build.sh.
#pragma once

#include <errno.h>
#include <fcntl.h>
#include <linux/uhid.h>
#include <linux/uinput.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace hil {

inline double now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + ts.tv_nsec * 1e-9;
}

inline void sleepS(double s) {
  if (s > 0) std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(s * 1e6)));
}

// ---- checks: every check prints one line ("ok - ..." or "FAIL - ..."); main returns exitCode().
inline int& failures() {
  static int n = 0;
  return n;
}
inline int& checks() {
  static int n = 0;
  return n;
}

inline bool check(bool cond, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
inline bool check(bool cond, const char* fmt, ...) {
  char buf[2048];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  ++checks();
  if (!cond) ++failures();
  std::printf("%s - %s\n", cond ? "ok" : "FAIL", buf);
  std::fflush(stdout);
  return cond;
}

inline void note(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline void note(const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  std::printf("# ");
  std::vprintf(fmt, ap);
  std::printf("\n");
  va_end(ap);
  std::fflush(stdout);
}

inline int finish(const char* program) {
  std::printf("%s: %d checks, %d failed\n", program, checks(), failures());
  std::fflush(stdout);
  return failures() == 0 && checks() > 0 ? 0 : 1;
}

// Waits until pred() holds, polling every step seconds; false after timeout seconds.
inline bool waitFor(const std::function<bool()>& pred, double timeout, double step = 0.01) {
  const double end = now() + timeout;
  for (;;) {
    if (pred()) return true;
    if (now() >= end) return false;
    sleepS(step);
  }
}

// ---- files
inline std::optional<std::string> readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

inline bool writeFile(const std::filesystem::path& p, const std::string& text) {
  const int fd = ::open(p.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t n = ::write(fd, text.data(), text.size());
  const int err = errno;
  ::close(fd);
  errno = err;
  return n == static_cast<ssize_t>(text.size());
}

inline std::vector<uint8_t> readBytes(const std::filesystem::path& p) {
  auto s = readFile(p);
  if (!s) return {};
  return std::vector<uint8_t>(s->begin(), s->end());
}

// The nodes in /sys/class/<cls> whose device path has a component `needle` or `needle.*` (a uinput
// sysname "input7"; a HID device "0003:256C:006D" matches "0003:256C:006D.0001"), as /dev paths.
inline std::vector<std::string> classNodesUnder(const std::string& cls, const std::string& needle) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/sys/class/" + cls, ec)) {
    const auto real = std::filesystem::canonical(e.path(), ec).string();
    if (ec) continue;
    const size_t at = real.find("/" + needle);
    const size_t after = at == std::string::npos ? at : at + 1 + needle.size();
    if (at != std::string::npos && after < real.size() && (real[after] == '/' || real[after] == '.')) out.push_back(std::string("/dev/") + (cls == "input" ? "input/" : "") + e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// ---- uinput: a virtual evdev device.
class Uinput {
 public:
  struct Axis {
    int code;
    int32_t min, max, fuzz, flat, resolution;
  };
  struct Spec {
    std::string name;
    uint16_t bus = BUS_USB, vendor = 0, product = 0, version = 0;
    std::vector<std::pair<int, int>> codes;  // (type, code) of keys, misc, rel, ...
    std::vector<Axis> axes;
    std::vector<int> props;
  };

  Uinput() = default;
  Uinput(const Uinput&) = delete;
  Uinput& operator=(const Uinput&) = delete;
  ~Uinput() { destroy(); }

  // Creates the device and waits for its /dev/input/event* node; false (with errno text in error()) on failure.
  bool create(const Spec& spec) {
    destroy();
    fd_ = ::open("/dev/uinput", O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) return fail("open /dev/uinput");
    std::vector<int> types;
    auto addType = [&](int t) {
      if (std::find(types.begin(), types.end(), t) == types.end()) {
        types.push_back(t);
        ::ioctl(fd_, UI_SET_EVBIT, t);
      }
    };
    addType(EV_SYN);
    for (auto [type, code] : spec.codes) {
      addType(type);
      unsigned long req = 0;
      switch (type) {
        case EV_KEY: req = UI_SET_KEYBIT; break;
        case EV_REL: req = UI_SET_RELBIT; break;
        case EV_MSC: req = UI_SET_MSCBIT; break;
        case EV_LED: req = UI_SET_LEDBIT; break;
        case EV_SW: req = UI_SET_SWBIT; break;
        default: continue;
      }
      if (::ioctl(fd_, req, code) < 0) return fail("UI_SET_*BIT");
    }
    for (const auto& a : spec.axes) {
      addType(EV_ABS);
      if (::ioctl(fd_, UI_SET_ABSBIT, a.code) < 0) return fail("UI_SET_ABSBIT");
      uinput_abs_setup s{};
      s.code = static_cast<uint16_t>(a.code);
      s.absinfo.minimum = a.min;
      s.absinfo.maximum = a.max;
      s.absinfo.fuzz = a.fuzz;
      s.absinfo.flat = a.flat;
      s.absinfo.resolution = a.resolution;
      if (::ioctl(fd_, UI_ABS_SETUP, &s) < 0) return fail("UI_ABS_SETUP");
    }
    for (int p : spec.props) ::ioctl(fd_, UI_SET_PROPBIT, p);
    uinput_setup setup{};
    std::snprintf(setup.name, sizeof setup.name, "%s", spec.name.c_str());
    setup.id.bustype = spec.bus;
    setup.id.vendor = spec.vendor;
    setup.id.product = spec.product;
    setup.id.version = spec.version;
    if (::ioctl(fd_, UI_DEV_SETUP, &setup) < 0) return fail("UI_DEV_SETUP");
    if (::ioctl(fd_, UI_DEV_CREATE) < 0) return fail("UI_DEV_CREATE");
    char sysname[64] = {};
    if (::ioctl(fd_, UI_GET_SYSNAME(sizeof sysname), sysname) < 0) return fail("UI_GET_SYSNAME");
    sysname_ = sysname;
    // devtmpfs creates the node; wait for it (no udev needed).
    const bool ok = waitFor([&] {
      auto nodes = classNodesUnder("input", sysname_);
      for (const auto& n : nodes)
        if (n.find("/event") != std::string::npos && ::access(n.c_str(), R_OK) == 0) {
          node_ = n;
          return true;
        }
      return false;
    }, 5.0);
    if (!ok) return fail("no event node for " + sysname_);
    return true;
  }

  void destroy() {
    if (fd_ >= 0) {
      ::ioctl(fd_, UI_DEV_DESTROY);
      ::close(fd_);
    }
    fd_ = -1;
    node_.clear();
  }

  bool emit(int type, int code, int32_t value) {
    input_event ev{};
    ev.type = static_cast<uint16_t>(type);
    ev.code = static_cast<uint16_t>(code);
    ev.value = value;
    return ::write(fd_, &ev, sizeof ev) == static_cast<ssize_t>(sizeof ev);
  }

  const std::string& node() const { return node_; }
  const std::string& error() const { return error_; }

 private:
  bool fail(const std::string& what) {
    error_ = what + ": " + std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return false;
  }
  int fd_ = -1;
  std::string sysname_;
  std::string node_;
  std::string error_;
};

// ---- uhid: a virtual HID device (the kernel's HID core, hidraw and the HID drivers see a real device).
class Uhid {
 public:
  // Answers GET_REPORT (return the bytes, report ID first; nullopt: error) and SET_REPORT (return false: error).
  using GetReport = std::function<std::optional<std::vector<uint8_t>>(uint8_t rnum, uint8_t rtype)>;
  using SetReport = std::function<bool(uint8_t rnum, uint8_t rtype, const std::vector<uint8_t>& data)>;
  using Output = std::function<void(const std::vector<uint8_t>& data, uint8_t rtype)>;

  Uhid() = default;
  Uhid(const Uhid&) = delete;
  Uhid& operator=(const Uhid&) = delete;
  ~Uhid() { destroy(); }

  void onGetReport(GetReport f) { get_ = std::move(f); }
  void onSetReport(SetReport f) { set_ = std::move(f); }
  void onOutput(Output f) { output_ = std::move(f); }

  bool create(const std::string& name, uint16_t bus, uint16_t vendor, uint16_t product, const std::vector<uint8_t>& descriptor,
              const std::string& phys = "emboss-hil", const std::string& uniq = "") {
    destroy();
    fd_ = ::open("/dev/uhid", O_RDWR | O_CLOEXEC);
    if (fd_ < 0) {
      error_ = std::string("open /dev/uhid: ") + std::strerror(errno);
      return false;
    }
    uhid_event ev{};
    ev.type = UHID_CREATE2;
    std::snprintf(reinterpret_cast<char*>(ev.u.create2.name), sizeof ev.u.create2.name, "%s", name.c_str());
    std::snprintf(reinterpret_cast<char*>(ev.u.create2.phys), sizeof ev.u.create2.phys, "%s", phys.c_str());
    std::snprintf(reinterpret_cast<char*>(ev.u.create2.uniq), sizeof ev.u.create2.uniq, "%s", uniq.c_str());
    ev.u.create2.rd_size = static_cast<uint16_t>(descriptor.size());
    ev.u.create2.bus = bus;
    ev.u.create2.vendor = vendor;
    ev.u.create2.product = product;
    std::memcpy(ev.u.create2.rd_data, descriptor.data(), std::min(descriptor.size(), sizeof ev.u.create2.rd_data));
    if (!send(ev)) {
      error_ = std::string("UHID_CREATE2: ") + std::strerror(errno);
      ::close(fd_);
      fd_ = -1;
      return false;
    }
    stop_ = false;
    reader_ = std::thread([this] { readLoop(); });
    return true;
  }

  void destroy() {
    if (fd_ < 0) return;
    stop_ = true;
    uhid_event ev{};
    ev.type = UHID_DESTROY;
    send(ev);
    if (reader_.joinable()) reader_.join();
    ::close(fd_);
    fd_ = -1;
    started_ = false;
    opened_ = false;
  }

  // One input report (the report ID byte first when the descriptor numbers its reports).
  bool input(const std::vector<uint8_t>& report) {
    uhid_event ev{};
    ev.type = UHID_INPUT2;
    ev.u.input2.size = static_cast<uint16_t>(report.size());
    std::memcpy(ev.u.input2.data, report.data(), std::min(report.size(), sizeof ev.u.input2.data));
    return send(ev);
  }

  bool started() const { return started_; }  // a HID driver bound (UHID_START)
  bool opened() const { return opened_; }     // someone opened it (UHID_OPEN: hidraw or input open)
  const std::string& error() const { return error_; }
  int getReports() const { return getReports_; }

 private:
  bool send(const uhid_event& ev) {
    std::lock_guard<std::mutex> lock(writeMutex_);
    return ::write(fd_, &ev, sizeof ev) == static_cast<ssize_t>(sizeof ev);
  }

  void readLoop() {
    while (!stop_) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      uhid_event ev{};
      if (::read(fd_, &ev, sizeof ev) <= 0) continue;
      switch (ev.type) {
        case UHID_START: started_ = true; break;
        case UHID_STOP: started_ = false; break;
        case UHID_OPEN: opened_ = true; break;
        case UHID_CLOSE: opened_ = false; break;
        case UHID_OUTPUT:
          if (output_) output_(std::vector<uint8_t>(ev.u.output.data, ev.u.output.data + ev.u.output.size), ev.u.output.rtype);
          break;
        case UHID_GET_REPORT: {
          ++getReports_;
          uhid_event reply{};
          reply.type = UHID_GET_REPORT_REPLY;
          reply.u.get_report_reply.id = ev.u.get_report.id;
          auto data = get_ ? get_(ev.u.get_report.rnum, ev.u.get_report.rtype) : std::nullopt;
          if (data) {
            reply.u.get_report_reply.err = 0;
            reply.u.get_report_reply.size = static_cast<uint16_t>(data->size());
            std::memcpy(reply.u.get_report_reply.data, data->data(), std::min(data->size(), sizeof reply.u.get_report_reply.data));
          } else {
            reply.u.get_report_reply.err = EIO;
          }
          send(reply);
          break;
        }
        case UHID_SET_REPORT: {
          uhid_event reply{};
          reply.type = UHID_SET_REPORT_REPLY;
          reply.u.set_report_reply.id = ev.u.set_report.id;
          const std::vector<uint8_t> data(ev.u.set_report.data, ev.u.set_report.data + ev.u.set_report.size);
          reply.u.set_report_reply.err = (set_ && set_(ev.u.set_report.rnum, ev.u.set_report.rtype, data)) ? 0 : EIO;
          send(reply);
          break;
        }
        default: break;
      }
    }
  }

  int fd_ = -1;
  std::thread reader_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> started_{false};
  std::atomic<bool> opened_{false};
  std::atomic<int> getReports_{0};
  std::mutex writeMutex_;
  GetReport get_;
  SetReport set_;
  Output output_;
  std::string error_;
};

}  // namespace hil

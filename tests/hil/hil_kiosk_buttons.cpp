// HIL: the whole kiosk with GPIO buttons on a real gpiochip (the CP2112 emulation of cp2112.h,
// the kernel's hid-cp2112 driver, libgpiod): the kiosk opens the chip from a buttons.json, a press
// wakes it from attract mode, the configured long press takes it to staff mode, pulling the
// adapter out is survived (the buttons are dropped, the kiosk runs on) and plugging it in again
// brings the buttons back; SIGTERM ends the kiosk cleanly.
//   hil_kiosk_buttons EMBOSS_KIOSK          (needs the modules uhid and hid-cp2112)
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "cp2112.h"
#include "hil_common.h"

namespace {

bool logHas(const std::filesystem::path& log, const std::string& text) {
  const auto s = hil::readFile(log);
  return s && s->find(text) != std::string::npos;
}

// Holds pin `pin` down for `seconds`.
void hold(hil::Cp2112& chip, unsigned pin, double seconds) {
  chip.press(pin, true);
  hil::sleepS(seconds);
  chip.press(pin, false);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s EMBOSS_KIOSK\n", argv[0]);
    return 2;
  }
  const std::string kiosk = argv[1];
  char tmpl[] = "/tmp/emboss-hil-kiosk-buttons.XXXXXX";
  const std::filesystem::path dir = mkdtemp(tmpl);
  const auto log = dir / "kiosk.log", config = dir / "buttons.json";

  hil::Cp2112 chip;
  const std::string name = hil::startCp2112(chip);
  if (name.empty()) return hil::finish("hil_kiosk_buttons");
  // Line 0 next tool, 1 undo, 3 new sheet with staff on a long press; 20 ms debounce (the chip's
  // driver polls every 40 ms, the presses below last 400 ms and more).
  // The chip by its label, as for any USB GPIO adapter: its number may change when it comes back.
  std::ofstream(config) << ("{\"chip\": \"cp2112_gpio\", \"active_low\": true, \"bias\": \"pull_up\", \"debounce_ms\": 20,\n"
                         " \"long_press_ms\": 1000, \"buttons\": [{\"line\": 0, \"action\": \"next_tool\"},\n"
                         " {\"line\": 1, \"action\": \"undo\"}, {\"line\": 3, \"action\": \"new_sheet\", \"long_press\": \"staff\"}]}\n");
  hil::check(std::filesystem::file_size(config) > 100, "wrote %s", config.c_str());

  const pid_t pid = fork();
  if (pid == 0) {
    const std::string out = log.string();
    freopen(out.c_str(), "w", stderr);
    freopen("/dev/null", "w", stdout);
    setenv("HOME", dir.c_str(), 1);
    const std::string sessions = "--sessions-dir=" + (dir / "sessions").string(), buttons = "--buttons=" + config.string();
    execl(kiosk.c_str(), kiosk.c_str(), "--display=headless", "--size=160x100", "--tablet=none", "--camera=none", buttons.c_str(),
          sessions.c_str(), static_cast<char*>(nullptr));
    std::perror("exec");
    _exit(127);
  }
  auto alive = [&] { return ::kill(pid, 0) == 0 && waitpid(pid, nullptr, WNOHANG) == 0; };

  const bool opened = hil::waitFor([&] { return logHas(log, "buttons: gpio"); }, 60.0, 0.1);
  std::string line;
  if (const auto s = hil::readFile(log)) {
    const auto at = s->find("buttons: ");
    if (at != std::string::npos) line = s->substr(at, s->find('\n', at) - at);
  }
  hil::check(opened && line.find("3 buttons on cp2112_gpio") != std::string::npos, "the kiosk opened the buttons on %s (%s)", name.c_str(),
             line.c_str());
  hil::check(hil::waitFor([&] { return logHas(log, "first frame on the screen"); }, 150.0, 0.2), "the kiosk shows its first frame");

  hold(chip, 0, 0.4);
  hil::check(hil::waitFor([&] { return logHas(log, "state: visitor-arrived"); }, 30.0, 0.1), "a button press wakes the kiosk (visitor-arrived)");
  hold(chip, 3, 1.8);
  hil::check(hil::waitFor([&] { return logHas(log, "state: staff-entered"); }, 30.0, 0.1), "the long press of new sheet enters staff mode");

  chip.destroy();
  hil::check(hil::waitFor([&] { return logHas(log, "stopped answering; dropped"); }, 30.0, 0.1), "pulling the adapter out drops the buttons");
  hil::sleepS(2.0);
  hil::check(alive(), "the kiosk runs on without its buttons");
  // Plugged in again: the kiosk opens the buttons again (it looks every 3 s).
  hil::Cp2112 again;
  hil::check(again.create(), "uhid CP2112 created again %s", again.error().c_str());
  hil::check(hil::waitFor([&] { return logHas(log, "buttons: back: gpio"); }, 30.0, 0.1), "the kiosk opens the buttons again once the adapter is back");

  ::kill(pid, SIGTERM);
  int status = -1;
  const bool ended = hil::waitFor([&] { return waitpid(pid, &status, WNOHANG) == pid; }, 60.0, 0.1);
  if (!ended) ::kill(pid, SIGKILL), waitpid(pid, &status, 0);
  hil::check(ended && WIFEXITED(status) && WEXITSTATUS(status) == 0, "SIGTERM ends the kiosk with status 0");
  if (const auto s = hil::readFile(log)) hil::note("the kiosk's log:\n%s", s->c_str());
  std::filesystem::remove_all(dir);
  return hil::finish("hil_kiosk_buttons");
}

// cp2112_buttons: buttons for programs under test (the kiosk in the appliance's boot test). Emulates
// the CP2112 USB-HID GPIO bridge over uhid (cp2112.h: the kernel's hid-cp2112 driver registers a real
// gpiochip "cp2112_gpio", 8 lines) and presses its pins as told by lines read from a file, usually
// a FIFO:
//   cp2112_buttons COMMANDS_FILE
//     "press PIN SECONDS"   pulls PIN low for SECONDS (a button wired to ground), then lets it go
//     "quit"                removes the chip and ends
// Prints "chip gpiochipN" once the driver's gpiochip is there, "pressed PIN" after each press.
// Exit 0, or 1 when the chip cannot be made (no /dev/uhid, hid-cp2112 not loaded).
#include <fcntl.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "cp2112.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cp2112_buttons COMMANDS_FILE\n");
    return 2;
  }
  hil::Cp2112 chip;
  const std::string name = hil::startCp2112(chip);
  if (name.empty()) return 1;
  std::printf("chip %s\n", name.c_str());
  std::fflush(stdout);
  // Opened read-write: a FIFO then never reports end of file between writers.
  const int fd = ::open(argv[1], O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    std::fprintf(stderr, "cp2112_buttons: cannot open %s\n", argv[1]);
    return 1;
  }
  FILE* in = fdopen(fd, "r");
  char line[128];
  while (in && std::fgets(line, sizeof line, in)) {
    unsigned pin = 0;
    double seconds = 0;
    if (std::sscanf(line, "press %u %lf", &pin, &seconds) == 2 && pin < 8) {
      chip.press(pin, true);
      hil::sleepS(seconds);
      chip.press(pin, false);
      std::printf("pressed %u\n", pin);
      std::fflush(stdout);
    } else if (std::string(line).rfind("quit", 0) == 0) {
      break;
    }
  }
  chip.destroy();
  return 0;
}

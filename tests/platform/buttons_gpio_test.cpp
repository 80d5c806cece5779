// Tests for the GPIO buttons: clear failures without a chip, and *Hardware* checks that need one.
#include <gtest/gtest.h>

#include <poll.h>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "gpio/buttons_gpio.h"
#include "gpio/buttons_null.h"
#include "devices/button_config.h"

namespace emboss {
namespace {

TEST(ButtonsGpio, WithoutAChipTheKeyboardStandsIn) {
  if (!listGpioChips().empty()) GTEST_SKIP() << "this machine has GPIO chips; see the ButtonsGpioHardware suite";
  auto b = openGpioButtons(defaultButtonConfig());
  ASSERT_FALSE(b);
  EXPECT_EQ(b.error(), "gpio: no /dev/gpiochip* (no GPIO on this machine); the keyboard stands in");
}

TEST(ButtonsGpio, TheNullTwinNeverFails) {
  NullButtons none;
  std::vector<ButtonEvent> out;
  EXPECT_TRUE(none.poll(out));
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(none.fd(), -1);
  EXPECT_EQ(none.name(), "none");
}

// A sysfs tree in a temporary folder: a board's own chip, a CP2112 on USB (its HID device below the
// USB interface), and one over uhid (a HID device with no USB above it).
TEST(ButtonsGpio, AChipOnUsbOrHidIsRemovable) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("emboss-sysfs-" + std::to_string(::getpid()));
  fs::remove_all(root);
  const auto device = [&](const std::string& path, const std::string& subsystem) {
    fs::create_directories(root / "devices" / path);
    fs::create_directories(root / "bus" / subsystem);
    fs::create_directory_symlink(root / "bus" / subsystem, root / "devices" / path / "subsystem");
  };
  const auto chip = [&](const std::string& path, const std::string& name) {
    device(path + "/" + name, "gpio");
    fs::create_directories(root / "bus/gpio/devices");
    fs::create_directory_symlink(root / "devices" / path / name, root / "bus/gpio/devices" / name);
  };
  device("platform/soc", "platform");
  device("platform/soc/fe200000.gpio", "platform");
  chip("platform/soc/fe200000.gpio", "gpiochip0");
  device("pci0000:00/0000:00:14.0/usb1", "usb");
  device("pci0000:00/0000:00:14.0/usb1/1-1", "usb");
  device("pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.0", "usb");
  device("pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.0/0003:10C4:EA90.0001", "hid");
  chip("pci0000:00/0000:00:14.0/usb1/1-1/1-1:1.0/0003:10C4:EA90.0001", "gpiochip1");
  device("virtual/misc/uhid", "misc");
  device("virtual/misc/uhid/0003:10C4:EA90.0002", "hid");
  chip("virtual/misc/uhid/0003:10C4:EA90.0002", "gpiochip2");
  EXPECT_FALSE(gpioChipIsRemovable("gpiochip0", root.string()));
  EXPECT_TRUE(gpioChipIsRemovable("gpiochip1", root.string()));
  EXPECT_TRUE(gpioChipIsRemovable("gpiochip2", root.string()));
  EXPECT_FALSE(gpioChipIsRemovable("gpiochip9", root.string()));  // not there
  fs::remove_all(root);
}

// Needs a GPIO chip; no line is requested, so it is safe on a running kiosk.
TEST(ButtonsGpioHardware, ALineTheChipDoesNotHaveIsNamed) {
  const auto chips = listGpioChips();
  if (chips.empty()) GTEST_SKIP() << "no /dev/gpiochip* on this machine (no GPIO)";
  ButtonConfig c;
  ButtonLineConfig b;
  b.chip = chips.front();
  b.line = 65000;
  b.action = Action::Undo;
  c.buttons.push_back(b);
  auto src = openGpioButtons(c);
  ASSERT_FALSE(src);
  EXPECT_NE(src.error().find("does not exist"), std::string::npos) << src.error();
}

TEST(ButtonsGpioHardware, AnUnknownChipListsTheChipsThereAre) {
  if (listGpioChips().empty()) GTEST_SKIP() << "no /dev/gpiochip* on this machine (no GPIO)";
  ButtonConfig c;
  ButtonLineConfig b;
  b.chip = "gpiochip999";
  b.action = Action::Undo;
  c.buttons.push_back(b);
  auto src = openGpioButtons(c);
  ASSERT_FALSE(src);
  EXPECT_NE(src.error().find("chips here: gpiochip"), std::string::npos) << src.error();
}

// With EMBOSS_BUTTONS_CONFIG naming the kiosk's wiring: press any button within 10 s.
TEST(ButtonsGpioHardware, ConfiguredButtonsGiveEvents) {
  const char* path = std::getenv("EMBOSS_BUTTONS_CONFIG");
  if (listGpioChips().empty()) GTEST_SKIP() << "no /dev/gpiochip* on this machine (no GPIO)";
  if (!path) GTEST_SKIP() << "set EMBOSS_BUTTONS_CONFIG to the kiosk's button configuration to run this";
  auto config = loadButtonConfig(path);
  ASSERT_TRUE(config) << config.error();
  auto src = openGpioButtons(*config);
  ASSERT_TRUE(src) << src.error();
  ASSERT_GE((*src)->fd(), 0);
  std::vector<ButtonEvent> out;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (out.empty() && std::chrono::steady_clock::now() < end) {
    pollfd p{(*src)->fd(), POLLIN, 0};
    ::poll(&p, 1, 50);
    ASSERT_TRUE((*src)->poll(out)) << "the GPIO chip went away";
  }
  if (out.empty()) GTEST_SKIP() << "nobody pressed a button within 10 s";
  EXPECT_TRUE(out[0].pressed);
  EXPECT_NE(out[0].action, Action::None);
}

}  // namespace
}  // namespace emboss

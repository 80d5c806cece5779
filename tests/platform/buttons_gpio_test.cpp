// Tests for the GPIO buttons: clear failures without a chip, and *Hardware* checks that need one.
#include <gtest/gtest.h>

#include <poll.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "buttons_gpio.h"
#include "buttons_null.h"
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

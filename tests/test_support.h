// Helpers shared by the tests: where the shared fixtures are, and skipping when they are absent.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace emboss::test {

// The folder ../shared/fixtures beside the checkout, or nullopt when it is absent.
std::optional<std::filesystem::path> fixturesDir();
// A fresh empty scratch folder for one test (under the build tree).
std::filesystem::path scratchDir(const std::string& name);
std::string readText(const std::filesystem::path& p);

}  // namespace emboss::test

// Skips the current test with a clear message when ../shared/fixtures is absent.
#define EMBOSS_REQUIRE_FIXTURES(var)                                                         \
  auto var##_opt = ::emboss::test::fixturesDir();                                            \
  if (!var##_opt) GTEST_SKIP() << "shared fixtures not found (expected ../shared/fixtures " \
                                  "beside the checkout); skipping";                          \
  const std::filesystem::path var = *var##_opt

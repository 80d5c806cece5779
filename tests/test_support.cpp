// Helpers shared by the tests.
#include "test_support.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace emboss::test {

std::optional<std::filesystem::path> fixturesDir() {
  if (const char* env = std::getenv("EMBOSS_FIXTURES")) {
    if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
  }
  const std::filesystem::path p = std::filesystem::path(EMBOSS_SOURCE_DIR) / ".." / "shared" / "fixtures";
  if (std::filesystem::is_directory(p)) return std::filesystem::canonical(p);
  return std::nullopt;
}

std::filesystem::path scratchDir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::path(EMBOSS_BINARY_DIR) / "test-scratch" / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace emboss::test

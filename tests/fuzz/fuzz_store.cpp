// Fuzz target: the session journal reading back a store it did not write (a damaged or foreign
// sessions.db): it must never crash, and must always leave a store it can write again.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "store/session_journal.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const fs::path dir = fs::temp_directory_path() / ("fuzz-store-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "sessions.db", std::ios::binary);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  {
    emboss::SessionJournal j(dir, {});
    if (j.ok()) {
      (void)j.unfinished();
      (void)j.list();
      j.begin("{}");
      j.operations(0, {"{}"});
      if (!j.flush(10) || !j.unfinished()) __builtin_trap();  // a store it opened takes new sessions
    }
  }
  return 0;
}
